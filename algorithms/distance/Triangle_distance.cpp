#include "algorithms/distance/Triangle_distance.h"

#include <algorithm>
#include <cmath>

namespace extremal {

namespace {

// (u, v) of point p in the plane of the triangle (least squares).
void coordinates(const Vec3& p, const Vec3& p0, const Vec3& p1, const Vec3& p2, double uv[2]) {
  const Vec3 e1 = p1 - p0, e2 = p2 - p0, w = p - p0;
  const double a = e1.dot(e1), b = e1.dot(e2), c = e2.dot(e2), d = w.dot(e1), e = w.dot(e2);
  const double det = a * c - b * b;
  if (!(std::abs(det) > 0.0)) {
    uv[0] = uv[1] = 0.0;
    return;
  }
  uv[0] = (c * d - b * e) / det;
  uv[1] = (a * e - b * d) / det;
}

// A point where segment [p, q] crosses triangle t, if it does.
bool segment_crosses(const Vec3& p, const Vec3& q, const Vec3 t[3], Vec3& x) {
  const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double dp = n.dot(p - t[0]), dq = n.dot(q - t[0]);
  if ((dp > 0.0 && dq > 0.0) || (dp < 0.0 && dq < 0.0) || dp == dq) return false;
  x = p + (q - p) * (dp / (dp - dq));
  double uv[2];
  coordinates(x, t[0], t[1], t[2], uv);
  return uv[0] >= 0.0 && uv[1] >= 0.0 && uv[0] + uv[1] <= 1.0;
}

}  // namespace

double segment_segment_squared(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2, Vec3& c1,
                       Vec3& c2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 0.0 && e <= 0.0) {
    c1 = p1;
    c2 = p2;
    return (c1 - c2).squaredNorm();
  }
  if (a <= 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  c1 = p1 + d1 * s;
  c2 = p2 + d2 * t;
  return (c1 - c2).squaredNorm();
}

Triangle_point closest_on_triangle_region(const Vec3& q, const Vec3& a, const Vec3& b,
                                          const Vec3& c) {
  // Ericson, Real-Time Collision Detection 5.1.5: the Voronoi regions of vertices, edges, face.
  Triangle_point r;
  auto at = [&](const Vec3& p, double u, double v, Triangle_feature f, int k) {
    r.point = p;
    r.uv[0] = u;
    r.uv[1] = v;
    r.feature = f;
    r.feature_index = k;
    return r;
  };
  const Vec3 ab = b - a, ac = c - a, ap = q - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return at(a, 0, 0, Triangle_feature::Vertex, 0);
  const Vec3 bp = q - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return at(b, 1, 0, Triangle_feature::Vertex, 1);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return at(a + v * ab, v, 0, Triangle_feature::Edge, 0);
  }
  const Vec3 cp = q - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return at(c, 0, 1, Triangle_feature::Vertex, 2);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return at(a + w * ac, 0, w, Triangle_feature::Edge, 2);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return at(b + w * (c - b), 1.0 - w, w, Triangle_feature::Edge, 1);
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return at(a + ab * v + ac * w, v, w, Triangle_feature::Face, 0);
}

Vec3 closest_on_triangle(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c, double uv[2]) {
  const Triangle_point t = closest_on_triangle_region(q, a, b, c);
  uv[0] = t.uv[0];
  uv[1] = t.uv[1];
  return t.point;
}

Triangle_closest triangle_distance(const Vec3 a[3], const Vec3 b[3]) {
  Triangle_closest r;
  r.distance = HUGE_VAL;
  // An edge of one triangle meets the other only where the other's plane separates the edge's
  // ends: when every corner of b lies strictly on one side of a's plane, or every corner of a
  // on one side of b's, the triangles do not meet and the crossing tests are skipped.
  auto one_side = [](const Vec3 t[3], const Vec3 o[3]) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    const double d0 = n.dot(o[0] - t[0]), d1 = n.dot(o[1] - t[0]), d2 = n.dot(o[2] - t[0]);
    return (d0 > 0.0 && d1 > 0.0 && d2 > 0.0) || (d0 < 0.0 && d1 < 0.0 && d2 < 0.0);
  };
  const bool apart = one_side(a, b) || one_side(b, a);
  for (int side = 0; side < 2 && !apart; ++side) {
    const Vec3* s = side == 0 ? a : b;
    const Vec3* o = side == 0 ? b : a;
    for (int e = 0; e < 3; ++e) {
      Vec3 x;
      if (segment_crosses(s[e], s[(e + 1) % 3], o, x)) {
        r.distance = 0.0;
        r.point_a = r.point_b = x;
        coordinates(x, a[0], a[1], a[2], r.uv_a);
        coordinates(x, b[0], b[1], b[2], r.uv_b);
        return r;
      }
    }
  }
  // Compared squared (the square root is monotone and correctly rounded: the least of the
  // roots is the root of the least), one root at the end.
  double least = HUGE_VAL;
  auto offer = [&](double d2, const Vec3& pa, const Vec3& pb) {
    if (d2 < least) {
      least = d2;
      r.point_a = pa;
      r.point_b = pb;
    }
  };
  // A corner against the other triangle's face: only where its foot falls inside the face (a
  // foot on the border is an edge's, which the edge pairs below cover).
  auto corner_face = [&](const Vec3 t[3], const Vec3 o[3], bool t_is_a) {
    const Vec3 e1 = o[1] - o[0], e2 = o[2] - o[0], n = e1.cross(e2);
    const double nn = n.squaredNorm();
    if (!(nn > 0.0)) return;  // (a degenerate face: its edges)
    const double d00 = e1.dot(e1), d01 = e1.dot(e2), d11 = e2.dot(e2);
    const double denom = d00 * d11 - d01 * d01;
    for (int k = 0; k < 3; ++k) {
      const Vec3 v = t[k] - o[0];
      const double d20 = v.dot(e1), d21 = v.dot(e2);
      const double u = (d11 * d20 - d01 * d21) / denom, w = (d00 * d21 - d01 * d20) / denom;
      if (!(u >= 0.0 && w >= 0.0 && u + w <= 1.0)) continue;
      const double h = v.dot(n);
      const Vec3 foot = t[k] - (h / nn) * n;
      if (t_is_a)
        offer(h * h / nn, t[k], foot);
      else
        offer(h * h / nn, foot, t[k]);
    }
  };
  corner_face(a, b, true);
  corner_face(b, a, false);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Vec3 ca, cb;
      const double d2 = segment_segment_squared(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3], ca, cb);
      offer(d2, ca, cb);
    }
  r.distance = std::sqrt(least);
  coordinates(r.point_a, a[0], a[1], a[2], r.uv_a);
  coordinates(r.point_b, b[0], b[1], b[2], r.uv_b);
  return r;
}

}  // namespace extremal
