#include "algorithms/mesh/Mesh_bvh.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

#include "algorithms/mesh/internal/Mesh_tuning.h"
#include "kernel/Error.h"

namespace extremal {

using internal::k_box_rounding;
using internal::k_frame_check;
using internal::k_max_depth;
using internal::k_parallel_axes;

// ---- Closest points on a triangle ----------------------------------------------------------

Mesh_point closest_on_triangle_feature(const Vec3& q, const Vec3& a, const Vec3& b,
                                       const Vec3& c) {
  const Triangle_point t = closest_on_triangle_region(q, a, b, c);
  Mesh_point r;
  r.point = t.point;
  r.uv[0] = t.uv[0];
  r.uv[1] = t.uv[1];
  r.feature = t.feature;
  r.feature_index = t.feature_index;
  r.distance = (q - t.point).norm();
  return r;
}

// ---- Box bounds ----------------------------------------------------------------------------

double triangle_box_lower_bound(const Vec3 t[3], const Vec3& centre, const Mat3& axes,
                                const Vec3& half, double enough) {
  // (The rounding of the products: a few ulps of the lengths involved.)
  const double rounding =
      k_box_rounding * (centre.norm() + half.norm() + t[0].norm() + (t[1] - t[0]).norm() + (t[2] - t[0]).norm());
  const double stop = enough + rounding;
  double gap = 0.0;
  // The box's axes: the corners' offsets from its centre in its frame.
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
  for (int k = 0; k < 3; ++k) {
    const Vec3 q = axes.transpose() * (t[k] - centre);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  for (int i = 0; i < 3; ++i) gap = std::max({gap, lo[i] - half[i], -half[i] - hi[i]});
  if (gap >= stop) return gap - rounding;
  // The triangle's normal: its plane against the box's extent along it.
  const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double len = n.norm();
  if (len > 0.0) {
    const double extent = (axes.transpose() * n).cwiseAbs().dot(half);
    gap = std::max(gap, (std::abs(n.dot(centre - t[0])) - extent) / len);
    if (gap >= stop) return gap - rounding;
  }
  // The line from the centroid to the box's centre.
  const Vec3 d = centre - (t[0] + t[1] + t[2]) / 3.0;
  const double dn = d.norm();
  if (dn > 0.0) {
    const Vec3 u = d / dn;
    const double reach = std::max({u.dot(t[0]), u.dot(t[1]), u.dot(t[2])});
    const double extent = (axes.transpose() * u).cwiseAbs().dot(half);
    gap = std::max(gap, u.dot(centre) - extent - reach);
  }
  if (!(gap > 0.0)) return 0.0;
  return std::max(0.0, gap - rounding);
}


double obb_lower_bound(const Obb& a, const Obb& b, const Mat3& R_AB, const Vec3& t_AB,
                       double enough) {
  const Vec3& ha = a.half;
  const Vec3& hb = b.half;
  // The balls and the line through the centres first: they need no rotation between the boxes'
  // frames, and clear most pairs a traversal bounds.
  const Vec3 offset = R_AB * b.centre + t_AB - a.centre;  // centres' offset, A's frame
  const double centres = offset.norm();
  // (The rounding of the products below: a few ulps of the lengths involved.)
  const double rounding = k_box_rounding * (centres + ha.norm() + hb.norm());
  const double stop = enough + rounding;
  double gap = centres - ha.norm() - hb.norm();  // the balls
  if (gap >= stop) return gap - rounding;
  if (centres > 0.0) {
    // The line through the centres, often the best axis of boxes apart on a diagonal.
    const Vec3 u = offset / centres;
    const Vec3 ua = a.axes.transpose() * u;
    const Vec3 ub = b.axes.transpose() * (R_AB.transpose() * u);
    gap = std::max(gap, centres - (ua.cwiseAbs().dot(ha) + ub.cwiseAbs().dot(hb)));
    if (gap >= stop) return gap - rounding;
  }
  // In a's coordinates: b's axes (columns of R) and centre (T).
  const Mat3 R = a.axes.transpose() * (R_AB * b.axes);
  const Vec3 T = a.axes.transpose() * offset;
  const Mat3 Ra = R.cwiseAbs();
  for (int i = 0; i < 3; ++i) {
    gap = std::max(gap, std::abs(T[i]) - (ha[i] + Ra.row(i).dot(hb)));
    gap = std::max(gap, std::abs(T.dot(R.col(i))) - (Ra.col(i).dot(ha) + hb[i]));
  }
  if (gap >= stop) return gap - rounding;
  // The cross axes e_i x b_j, |e_i x b_j| = sqrt(1 - R(i, j)^2) (skipped where nearly parallel:
  // the face axes bound those).
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double len2 = 1.0 - R(i, j) * R(i, j);
      if (!(len2 > k_parallel_axes)) continue;
      const double t = std::abs(T[i2] * R(i1, j) - T[i1] * R(i2, j));
      const double ra = ha[i1] * Ra(i2, j) + ha[i2] * Ra(i1, j);
      const double rb = hb[j1] * Ra(i, j2) + hb[j2] * Ra(i, j1);
      gap = std::max(gap, (t - ra - rb) / std::sqrt(len2));
    }
  }
  if (!(gap > 0.0)) return 0.0;
  return std::max(0.0, gap - rounding);
}

namespace {

// The box of points [first, last) along orthonormal axes (the columns), inflated for the
// rounding of the projections.
Obb box_along(const Mat3& axes, const Vec3* first, const Vec3* last) {
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
  const Mat3 to_box = axes.transpose();
  for (const Vec3* p = first; p != last; ++p) {
    const Vec3 q = to_box * *p;
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  Obb box;
  box.axes = axes;
  const Vec3 mid = 0.5 * (lo + hi);
  box.centre = axes * mid;
  const double scale = mid.norm() + (hi - lo).norm();
  box.half = 0.5 * (hi - lo) + Vec3::Constant(k_box_rounding * scale);
  return box;
}

// The box of the corners of leaf slots [begin, end) (3 a slot) along the axes of their
// covariance.
Obb fit_box(const Vec3* corners, int begin, int end) {
  const Vec3* first = corners + 3 * static_cast<std::size_t>(begin);
  const Vec3* last = corners + 3 * static_cast<std::size_t>(end);
  // One pass: sums about the first corner (no cancellation from far origins).
  const Vec3 origin = first[0];
  Vec3 sum = Vec3::Zero();
  Mat3 outer = Mat3::Zero();
  for (const Vec3* p = first; p != last; ++p) {
    const Vec3 d = *p - origin;
    sum += d;
    outer.noalias() += d * d.transpose();
  }
  const double count = static_cast<double>(last - first);
  const Vec3 mean = sum / count;
  const Mat3 cov = outer / count - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  eig.computeDirect(cov);
  Mat3 axes = eig.eigenvectors();
  if (!axes.allFinite() || std::abs(std::abs(axes.determinant()) - 1.0) > k_frame_check) {
    // Degenerate spreads (a single point, collinear points): the frame's axes.
    axes = Mat3::Identity();
  } else {
    // Orthonormalised to rounding (Gram-Schmidt): the bounds need unit, orthogonal axes.
    const Vec3 a0 = axes.col(0).normalized();
    const Vec3 a1 = (axes.col(1) - a0.dot(axes.col(1)) * a0).normalized();
    axes.col(0) = a0;
    axes.col(1) = a1;
    axes.col(2) = a0.cross(a1);
  }
  return box_along(axes, first, last);
}

// The box of a triangle along its longest edge, the edge's perpendicular in its plane, and its
// normal (degenerate triangles: any frame through the edge, or the frame's axes).
Obb triangle_box(const Vec3* c) {
  int k = 0;
  double longest = -1.0;
  for (int e = 0; e < 3; ++e) {
    const double len = (c[(e + 1) % 3] - c[e]).squaredNorm();
    if (len > longest) longest = len, k = e;
  }
  Mat3 axes = Mat3::Identity();
  if (longest > 0.0) {
    const Vec3 a0 = (c[(k + 1) % 3] - c[k]).normalized();
    const Vec3 normal = (c[1] - c[0]).cross(c[2] - c[0]);
    const Vec3 a1 = normal.squaredNorm() > 0.0 ? Vec3(normal.cross(a0).normalized()) : Vec3(a0.unitOrthogonal());
    axes.col(0) = a0;
    axes.col(1) = a1;
    axes.col(2) = a0.cross(a1);
  }
  return box_along(axes, c, c + 3);
}

}  // namespace

Obb Mesh_bvh::box(int ref) const {
  return is_leaf(ref) ? triangle_box(corners(leaf_slot(ref))) : node(ref).box;
}

// ---- Build ---------------------------------------------------------------------------------

Mesh_bvh::Mesh_bvh(const Triangle_mesh& mesh, const std::string& name) {
  const int nv = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k : mesh.triangles[t])
      if (k < 0 || k >= nv)
        throw Invalid_input("body '" + name + "': triangle " + std::to_string(t) +
                            " refers to vertex " + std::to_string(k) + " of " + std::to_string(nv));
  if (mesh.triangles.empty()) throw Invalid_input("body '" + name + "': a mesh with no triangles");
  build(mesh);
  find_adjacency(mesh, name);
}

void Mesh_bvh::build(const Triangle_mesh& mesh) {
  const std::size_t n = mesh.triangles.size();
  // The corners in leaf-slot order from the start: a node's triangles are a run of slots, read
  // in one sweep by its box fit and reordered by its median split.
  m_corners.resize(3 * n);
  m_order.resize(n);
  m_box = Bbox_3();
  for (std::size_t t = 0; t < n; ++t) {
    m_order[t] = static_cast<int>(t);
    for (int k = 0; k < 3; ++k) {
      const Point_3& p = mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][static_cast<std::size_t>(k)])];
      m_corners[3 * t + static_cast<std::size_t>(k)] = to_vec3(p);
      m_box += p.bbox();
    }
  }
  m_nodes.clear();
  m_nodes.reserve(n > 0 ? n - 1 : 0);  // (a binary tree over n leaves has n - 1 inner nodes)
  std::vector<double> key(n);  // a slot's centroid along the splitting axis (times 3)
  auto swap_slots = [&](int i, int j) {
    std::swap(key[static_cast<std::size_t>(i)], key[static_cast<std::size_t>(j)]);
    std::swap(m_order[static_cast<std::size_t>(i)], m_order[static_cast<std::size_t>(j)]);
    for (int k = 0; k < 3; ++k)
      std::swap(m_corners[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(k)],
                m_corners[3 * static_cast<std::size_t>(j) + static_cast<std::size_t>(k)]);
  };
  // Slots [begin, end) reordered so that those before `mid` have keys at most those after
  // (quickselect, Hoare's partition about a median of three).
  auto select = [&](int begin, int mid, int end) {
    int lo = begin, hi = end - 1;
    while (hi > lo) {
      const double a = key[static_cast<std::size_t>(lo)], b = key[static_cast<std::size_t>((lo + hi) / 2)],
                   c = key[static_cast<std::size_t>(hi)];
      const double pivot = std::max(std::min(a, b), std::min(std::max(a, b), c));
      int i = lo, j = hi;
      while (i <= j) {
        while (key[static_cast<std::size_t>(i)] < pivot) ++i;
        while (key[static_cast<std::size_t>(j)] > pivot) --j;
        if (i <= j) swap_slots(i++, j--);
      }
      if (mid <= j)
        hi = j;
      else if (mid >= i)
        lo = i;
      else
        break;
    }
  };
  // Top down: each inner node's box fits its triangles' corners; it splits at the median
  // centroid along its longest axis. A run of one slot is a leaf.
  struct Task {
    int begin, end, depth;
    int parent, side;  // where its reference goes (-1: the root)
  };
  std::vector<Task> stack;
  if (n >= 2) stack.push_back({0, static_cast<int>(n), 0, -1, 0});
  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    const int count = task.end - task.begin;
    int ref = -task.begin - 1;
    if (count > 1) {
      EXTREMAL_PRECONDITION_MSG(task.depth < k_max_depth, "mesh hierarchy deeper than " << k_max_depth);
      ref = static_cast<int>(m_nodes.size());
      m_nodes.emplace_back();
      m_nodes.back().box = fit_box(m_corners.data(), task.begin, task.end);
    }
    if (task.parent >= 0) m_nodes[static_cast<std::size_t>(task.parent)].child[task.side] = ref;
    if (count == 1) continue;
    const Obb& box = m_nodes[static_cast<std::size_t>(ref)].box;
    int axis = 0;
    box.half.maxCoeff(&axis);
    const Vec3 dir = box.axes.col(axis);
    for (int s = task.begin; s < task.end; ++s) {
      const Vec3* c = m_corners.data() + 3 * static_cast<std::size_t>(s);
      key[static_cast<std::size_t>(s)] = dir.dot(c[0] + c[1] + c[2]);
    }
    const int mid = task.begin + count / 2;
    select(task.begin, mid, task.end);
    stack.push_back({task.begin, mid, task.depth + 1, ref, 0});
    stack.push_back({mid, task.end, task.depth + 1, ref, 1});
  }
  m_slot.resize(n);
  for (std::size_t s = 0; s < n; ++s) m_slot[static_cast<std::size_t>(m_order[s])] = static_cast<int>(s);
}

void Mesh_bvh::find_adjacency(const Triangle_mesh& mesh, const std::string& name) {
  // Directed edges (from, to, triangle, edge): each undirected edge of a closed, consistently
  // oriented mesh is run once each way.
  struct Directed {  // 16 bytes: a mesh of 10^6 triangles holds 3 10^6 of them at once
    std::uint64_t key;  // (min, max) vertex ids
    std::uint32_t use;  // (3 triangle + edge) * 2 + (from < to)
    int triangle() const { return static_cast<int>(use >> 1) / 3; }
    int edge() const { return static_cast<int>(use >> 1) % 3; }
    bool forward() const { return use & 1u; }
  };
  const std::size_t n = mesh.triangles.size();
  // Vertices at the same position are one (formats such as STL repeat a corner per triangle,
  // and readers split corners by their normals): each vertex's id is its position's first.
  std::vector<int> weld(mesh.vertices.size());
  {
    std::vector<int> by_position(mesh.vertices.size());
    std::iota(by_position.begin(), by_position.end(), 0);
    auto key = [&](int v) {
      const Point_3& p = mesh.vertices[static_cast<std::size_t>(v)];
      return std::make_tuple(p.x(), p.y(), p.z(), v);
    };
    std::sort(by_position.begin(), by_position.end(), [&](int x, int y) { return key(x) < key(y); });
    for (std::size_t i = 0; i < by_position.size(); ++i) {
      const int v = by_position[i];
      const bool same = i > 0 && mesh.vertices[static_cast<std::size_t>(v)] ==
                                     mesh.vertices[static_cast<std::size_t>(by_position[i - 1])];
      weld[static_cast<std::size_t>(v)] = same ? weld[static_cast<std::size_t>(by_position[i - 1])] : v;
    }
  }
  auto corner = [&](std::size_t t, int k) {
    return weld[static_cast<std::size_t>(mesh.triangles[t][static_cast<std::size_t>(k)])];
  };
  std::vector<Directed> edges;
  edges.reserve(3 * n);
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = corner(t, k);
      const int b = corner(t, (k + 1) % 3);
      if (a == b) continue;  // a degenerate triangle's collapsed edge joins nothing
      const std::uint64_t lo = static_cast<std::uint32_t>(std::min(a, b));
      const std::uint64_t hi = static_cast<std::uint32_t>(std::max(a, b));
      edges.push_back({(lo << 32) | hi, static_cast<std::uint32_t>((3 * t + static_cast<std::size_t>(k)) * 2 + (a < b ? 1 : 0))});
    }
  std::sort(edges.begin(), edges.end(),
            [](const Directed& x, const Directed& y) { return x.key < y.key; });
  m_across.assign(n, {-1, -1, -1});
  m_closed = true;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    const auto a = static_cast<int>(edges[i].key >> 32), b = static_cast<int>(edges[i].key & 0xffffffffu);
    if (m_closed && j - i != 2) {
      m_closed = false;
      m_reason = "mesh edge (" + std::to_string(a) + ", " + std::to_string(b) + ") of body '" + name +
                 "' has " + std::to_string(j - i) + " triangle(s), not 2: the mesh is not closed";
    } else if (m_closed && edges[i].forward() == edges[i + 1].forward()) {
      m_closed = false;
      m_reason = "mesh edge (" + std::to_string(a) + ", " + std::to_string(b) + ") of body '" + name +
                 "' runs the same way in both its triangles: the mesh is not consistently oriented";
    }
    if (j - i == 2) {
      m_across[static_cast<std::size_t>(edges[i].triangle())][static_cast<std::size_t>(edges[i].edge())] = edges[i + 1].triangle();
      m_across[static_cast<std::size_t>(edges[i + 1].triangle())][static_cast<std::size_t>(edges[i + 1].edge())] = edges[i].triangle();
    }
    i = j;
  }
  if (!m_closed) {
    m_across.clear();
    m_across.shrink_to_fit();
    return;
  }
  m_reason = "every mesh edge has two triangles that run it in opposite directions";
  // Outward: the enclosed volume (divergence theorem) is positive.
  double volume = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3 p0 = to_vec3(mesh.vertices[static_cast<std::size_t>(t[0])]);
    const Vec3 p1 = to_vec3(mesh.vertices[static_cast<std::size_t>(t[1])]);
    const Vec3 p2 = to_vec3(mesh.vertices[static_cast<std::size_t>(t[2])]);
    volume += p0.dot(p1.cross(p2));
  }
  m_flipped = volume < 0.0;
  m_vertex_ids.resize(n);
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) m_vertex_ids[t][static_cast<std::size_t>(k)] = corner(t, k);
  // Angle-weighted pseudo-normals of the vertices.
  m_vertex_normals.assign(mesh.vertices.size(), Vec3::Zero());
  for (std::size_t t = 0; t < n; ++t) {
    const Vec3 nrm = face_normal(static_cast<int>(t));
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = triangle(static_cast<int>(t))[k];
      const Vec3 e1 = (triangle(static_cast<int>(t))[(k + 1) % 3] - p).normalized();
      const Vec3 e2 = (triangle(static_cast<int>(t))[(k + 2) % 3] - p).normalized();
      const double angle = std::acos(std::clamp(e1.dot(e2), -1.0, 1.0));
      if (std::isfinite(angle)) m_vertex_normals[static_cast<std::size_t>(corner(t, k))] += angle * nrm;
    }
  }
}

Vec3 Mesh_bvh::face_normal(int t) const {
  const Vec3* c = triangle(t);
  const Vec3 n = (c[1] - c[0]).cross(c[2] - c[0]);
  const double len = n.norm();
  if (!(len > 0.0)) return Vec3::Zero();
  return (m_flipped ? -1.0 : 1.0) * n / len;
}

// ---- Queries -------------------------------------------------------------------------------

Mesh_point Mesh_bvh::closest_point(const Vec3& p, double upper) const {
  Mesh_point best;
  best.distance = upper;
  auto box_distance_to = [&](const Obb& b) {
    const Vec3 local = b.axes.transpose() * (p - b.centre);
    const Vec3 out = (local.cwiseAbs() - b.half).cwiseMax(0.0);
    return out.norm();
  };
  auto measure = [&](int slot) {
    const Vec3* c = corners(slot);
    Mesh_point q = closest_on_triangle_feature(p, c[0], c[1], c[2]);
    if (q.distance < best.distance) {
      q.triangle = triangle_of_slot(slot);
      best = q;
    }
  };
  if (is_leaf(root())) {
    measure(leaf_slot(root()));
    return best;
  }
  // Depth first, nearer child first; a node whose box is no closer than the best is pruned,
  // a leaf measured at once.
  struct Item {
    int node;
    double lower;
  };
  Item stack[k_max_depth + 2];
  int top = 0;
  stack[top++] = {root(), box_distance_to(node(root()).box)};
  while (top > 0) {
    const Item it = stack[--top];
    if (!(it.lower < best.distance)) continue;
    Item children[2];
    int inner = 0;
    for (int ref : node(it.node).child) {
      if (is_leaf(ref))
        measure(leaf_slot(ref));
      else
        children[inner++] = {ref, box_distance_to(node(ref).box)};
    }
    // (Median splits keep the depth at about log2 of the leaves: the stack holds it.)
    if (inner == 2 && children[0].lower < children[1].lower) std::swap(children[0], children[1]);
    for (int k = 0; k < inner; ++k) stack[top++] = children[k];
  }
  return best;
}

bool Mesh_bvh::inside(const Vec3& p, const Mesh_point& c) const {
  if (!m_closed || c.triangle < 0 || !(c.distance > 0.0)) return false;
  Vec3 n = Vec3::Zero();
  switch (c.feature) {
    case Triangle_feature::Face: n = face_normal(c.triangle); break;
    case Triangle_feature::Edge: {
      const int other = m_across[static_cast<std::size_t>(c.triangle)][static_cast<std::size_t>(c.feature_index)];
      n = face_normal(c.triangle) + (other >= 0 ? face_normal(other) : Vec3::Zero());
      break;
    }
    case Triangle_feature::Vertex:
      n = m_vertex_normals[static_cast<std::size_t>(m_vertex_ids[static_cast<std::size_t>(c.triangle)][static_cast<std::size_t>(c.feature_index)])];
      break;
  }
  return (p - c.point).dot(n) < 0.0;
}

std::size_t Mesh_bvh::memory_bytes() const {
  return m_nodes.capacity() * sizeof(Node) + m_corners.capacity() * sizeof(Vec3) +
         (m_order.capacity() + m_slot.capacity()) * sizeof(int) +
         (m_across.capacity() + m_vertex_ids.capacity()) * sizeof(std::array<int, 3>) +
         m_vertex_normals.capacity() * sizeof(Vec3);
}

}  // namespace extremal
