#include "kernel/Bracket.h"

#include <array>
#include <cmath>
#include <sstream>

#include "kernel/Error.h"

namespace extremal {

namespace {

constexpr double k_pi = 3.14159265358979323846;

// One profile segment in the xz-plane: a line (2 poles) or a quarter arc (3 poles, the middle
// one at the corner the arc rounds off, weights 1, sqrt(1/2), 1). Parameter in [0, 1].
struct Segment {
  std::vector<std::array<double, 2>> poles;  // (x, z)
  std::vector<double> weights;               // empty for a line
  int degree() const { return static_cast<int>(poles.size()) - 1; }
  std::vector<double> knots() const {
    return degree() == 1 ? std::vector<double>{0, 0, 1, 1} : std::vector<double>{0, 0, 0, 1, 1, 1};
  }
};

Segment line(double x0, double z0, double x1, double z1) { return {{{x0, z0}, {x1, z1}}, {}}; }
Segment arc(double x0, double z0, double xc, double zc, double x1, double z1) {
  return {{{x0, z0}, {xc, zc}, {x1, z1}}, {1.0, std::sqrt(0.5), 1.0}};
}

// The closed profile, counterclockwise in (x, z) (x right, z up), starting on the bottom face.
std::vector<Segment> profile(const Bracket_size& s) {
  const double X = s.width / 2, H = s.height, f = s.floor, h = s.slot_width / 2;
  const double r = s.fillet, R = s.round;
  return {
      line(-X + R, 0, X - R, 0),             // 0 bottom
      arc(X - R, 0, X, 0, X, R),             // 1 right rounded edge (convex)
      line(X, R, X, H),                      // 2 right outer wall
      line(X, H, h, H),                      // 3 right top
      line(h, H, h, f + r),                  // 4 right slot wall
      arc(h, f + r, h, f, h - r, f),         // 5 right fillet (concave)
      line(h - r, f, -h + r, f),             // 6 slot floor
      arc(-h + r, f, -h, f, -h, f + r),      // 7 left fillet (concave)
      line(-h, f + r, -h, H),                // 8 left slot wall
      line(-h, H, -X, H),                    // 9 left top
      line(-X, H, -X, R),                    // 10 left outer wall
      arc(-X, R, -X, 0, -X + R, 0),          // 11 left rounded edge (convex)
  };
}

void check(const Bracket_size& s) {
  auto positive = [](double x, const char* what) {
    if (!(std::isfinite(x) && x > 0.0)) {
      std::ostringstream os;
      os << "bracket: " << what << " must be finite and > 0, got " << x;
      throw Invalid_input(os.str());
    }
  };
  positive(s.width, "width");
  positive(s.height, "height");
  positive(s.length, "length");
  positive(s.floor, "floor");
  positive(s.slot_width, "slot_width");
  positive(s.fillet, "fillet");
  positive(s.round, "round");
  if (!(s.slot_width < s.width)) throw Invalid_input("bracket: slot_width must be < width");
  if (!(s.floor + s.fillet < s.height))
    throw Invalid_input("bracket: floor + fillet must be < height");
  if (!(2 * s.fillet < s.slot_width))
    throw Invalid_input("bracket: two fillets must fit in the slot (2 fillet < slot_width)");
  if (!(2 * s.round < s.width - s.slot_width) || !(s.round < s.height))
    throw Invalid_input("bracket: the rounded edges must fit beside the slot and below the top");
}

Nurbs_curve_3 curve_at(const Segment& seg, double y) {
  std::vector<Point_3> poles;
  for (const auto& p : seg.poles) poles.emplace_back(p[0], y, p[1]);
  return Nurbs_curve_3(seg.degree(), std::move(poles), seg.knots(), seg.weights);
}

// The segment in a cap's (u, v) = ((x + X) / w, z / h): an affine image, so the same rational
// parametrisation as the 3D edge.
Nurbs_curve_3 curve_in_cap(const Segment& seg, const Bracket_size& s) {
  std::vector<Point_3> poles;
  for (const auto& p : seg.poles)
    poles.emplace_back((p[0] + s.width / 2) / s.width, p[1] / s.height, 0.0);
  return Nurbs_curve_3(seg.degree(), std::move(poles), seg.knots(), seg.weights);
}

Nurbs_curve_3 uv_line(double u0, double v0, double u1, double v1) {
  return Nurbs_curve_3(1, {Point_3(u0, v0, 0), Point_3(u1, v1, 0)}, {0, 0, 1, 1});
}

}  // namespace

double bracket_volume(const Bracket_size& s) {
  check(s);
  const double corner = 1.0 - k_pi / 4.0;  // area of a unit square outside its quarter disk
  const double area = s.width * s.height - s.slot_width * (s.height - s.floor) -
                      2.0 * corner * s.round * s.round + 2.0 * corner * s.fillet * s.fillet;
  return area * s.length;
}

Body make_bracket_body(const Bracket_size& s, const std::string& name) {
  check(s);
  const std::vector<Segment> segs = profile(s);
  const int n = static_cast<int>(segs.size());
  const double y_plus = s.length / 2, y_minus = -s.length / 2;

  Body body;
  body.name = name;
  body.source_name = name;
  // Edges: profile at +l/2 (k), at -l/2 (n + k), rulings from +l/2 to -l/2 at the start of
  // segment k (2n + k).
  for (int k = 0; k < n; ++k) {
    Edge e;
    e.curve = curve_at(segs[k], y_plus);
    e.t_min = 0.0;
    e.t_max = 1.0;
    body.edges.push_back(std::move(e));
  }
  for (int k = 0; k < n; ++k) {
    Edge e;
    e.curve = curve_at(segs[k], y_minus);
    e.t_max = 1.0;
    body.edges.push_back(std::move(e));
  }
  for (int k = 0; k < n; ++k) {
    const auto& p = segs[k].poles.front();
    Edge e;
    e.curve = Nurbs_curve_3(1, {Point_3(p[0], y_plus, p[1]), Point_3(p[0], y_minus, p[1])},
                            {0, 0, 1, 1});
    e.t_max = 1.0;
    body.edges.push_back(std::move(e));
  }
  auto use = [&](Face& face, int face_index, Trim_loop& loop, Nurbs_curve_3 uv, int edge,
                 bool reversed) {
    body.edges[edge].uses.push_back({face_index, static_cast<int>(face.trims.size()),
                                     static_cast<int>(loop.curves.size())});
    loop.curves.push_back({std::move(uv), edge, reversed});
  };

  // Sides: ruled between the segment at +l/2 (v = 0) and at -l/2 (v = 1); with the profile
  // counterclockwise in (x, z), f_u x f_v points out of the material.
  for (int k = 0; k < n; ++k) {
    const Segment& seg = segs[k];
    std::vector<Point_3> poles;
    std::vector<double> weights;
    for (std::size_t i = 0; i < seg.poles.size(); ++i) {
      for (double y : {y_plus, y_minus}) {
        poles.emplace_back(seg.poles[i][0], y, seg.poles[i][1]);
        if (!seg.weights.empty()) weights.push_back(seg.weights[i]);
      }
    }
    Face face(Nurbs_surface_3(seg.degree(), 1, seg.degree() + 1, 2, std::move(poles), seg.knots(),
                              {0, 0, 1, 1}, std::move(weights)),
              "bspline");
    face.surface.set_outward_sign(+1);
    face.source = "bracket side " + std::to_string(k);
    // Counterclockwise in (u, v): v = 0 forward, u = 1 up, v = 1 back, u = 0 down.
    Trim_loop loop;
    use(face, k, loop, uv_line(0, 0, 1, 0), k, false);
    use(face, k, loop, uv_line(1, 0, 1, 1), 2 * n + (k + 1) % n, false);
    use(face, k, loop, uv_line(0, 1, 1, 1), n + k, true);
    use(face, k, loop, uv_line(0, 0, 0, 1), 2 * n + k, true);
    face.trims.push_back(std::move(loop));
    face.update_trim_region();
    body.faces.push_back(std::move(face));
  }

  // Caps: the profile's box as a bilinear plane, u along x, v along z (f_u x f_v = -y), trimmed
  // by the profile, counterclockwise in (u, v).
  for (int cap = 0; cap < 2; ++cap) {
    const double y = cap == 0 ? y_minus : y_plus;
    const double X = s.width / 2;
    std::vector<Point_3> poles = {{-X, y, 0}, {-X, y, s.height}, {X, y, 0}, {X, y, s.height}};
    Face face(Nurbs_surface_3(1, 1, 2, 2, std::move(poles), {0, 0, 1, 1}, {0, 0, 1, 1}),
              "bspline");
    face.surface.set_outward_sign(cap == 0 ? +1 : -1);
    face.source = cap == 0 ? "bracket cap y-" : "bracket cap y+";
    const int face_index = n + cap;
    Trim_loop loop;
    for (int k = 0; k < n; ++k)
      use(face, face_index, loop, curve_in_cap(segs[k], s), cap == 0 ? n + k : k, false);
    face.trims.push_back(std::move(loop));
    face.update_trim_region();
    body.faces.push_back(std::move(face));
  }
  return body;
}

}  // namespace extremal
