// OBJ free-form geometry (Wavefront OBJ, "free-form curve/surface attributes" and "elements"):
//   v x y z [w]      control vertex (w = weight of rational forms, default 1)
//   vp u [v] [w]     parameter-space vertex (for curv2)
//   cstype [rat] bspline|bezier      (bmatrix, cardinal and taylor are reported and skipped)
//   deg du [dv]      parm u|v k...   knots (B-spline) or segment breakpoints (Bezier)
//   curv u0 u1 v...  3D curve        curv2 vp...  parameter-space curve
//   surf s0 s1 t0 t1 v[/vt][/vn]...  surface, u varying fastest in the control list
//   trim u0 u1 curv2 ...  outer loop  hole u0 u1 curv2 ...  inner loop   end
// Indices are 1-based, negative ones count back from the latest (relative indices). Polygon
// faces (`f`) in the same file become the body's mesh. Every statement that cannot be used is
// reported with its line number and reason; nothing here throws except for a file with no
// usable element at all (read_model's check).
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <optional>
#include <cstdlib>
#include <sstream>

#include "io/internal/Readers.h"
#include "kernel/Error.h"
#include "kernel/Nurbs_refinement.h"

namespace extremal::io::internal {

namespace {

constexpr int k_max_degree_obj = 25;

struct Vertex4 {
  double x, y, z, w;
};

struct Trim_ref {
  double t0, t1;
  long index;  // into curv2 list (1-based or negative)
};

// The element being built between its opening statement (curv, curv2, surf) and `end`.
struct Element {
  enum Kind { None, Curv, Curv2, Surf } kind = None;
  int line = 0;
  bool rational = false;
  std::string type;  // bspline, bezier, ...
  int deg_u = 0, deg_v = 0;
  double s0 = 0, s1 = 0, t0 = 0, t1 = 0;  // curv: [s0, s1]; surf: [s0, s1] x [t0, t1]
  std::vector<long> refs;                 // resolved 0-based vertex (or vp) indices
  std::vector<double> parm_u, parm_v;
  bool has_parm_u = false, has_parm_v = false;
  std::vector<std::pair<bool, std::vector<Trim_ref>>> loops;  // (is_outer, pieces)
};

class Obj_parser {
 public:
  Obj_parser(const std::string& name, const Read_options& options, Model& model)
      : m_name(name), m_options(options), m_model(model) {}

  void parse(const std::string& text);

 private:
  void statement(const std::vector<std::string>& tok, int line);
  void finish_element(bool explicit_end);
  void skip(int line, const std::string& what, const std::string& reason,
            const std::string& action = "skipped") {
    std::ostringstream os;
    os << m_name << " line " << line << " (" << what << ")";
    m_model.skipped.push_back({os.str(), reason, action});
  }
  bool number(const std::string& s, double& out) const {
    if (s.empty()) return false;
    char* end = nullptr;
    out = std::strtod(s.c_str(), &end);
    return end && *end == '\0' && std::isfinite(out);
  }
  bool integer(const std::string& s, long& out) const {
    if (s.empty()) return false;
    char* end = nullptr;
    errno = 0;
    out = std::strtol(s.c_str(), &end, 10);
    return end && (*end == '\0' || *end == '/') && errno == 0;
  }
  // 1-based or negative (relative) index into a list of `count` items -> 0-based, or -1.
  // (idx >= -n, not -idx <= n: -LONG_MIN overflows.)
  static long resolve(long idx, std::size_t count) {
    const long n = static_cast<long>(count);
    if (idx > 0 && idx <= n) return idx - 1;
    if (idx < 0 && idx >= -n) return n + idx;
    return -1;
  }
  std::vector<double> knots_for(const Element& e, bool u, int degree, int n_ctrl,
                                std::string& error) const;
  // The curve of a curv or curv2 statement: knots from its parm u, control points from `list`
  // (v for curv, lengths times m_scale; vp for curv2, in parameter space: z = 0, unscaled).
  Nurbs_curve_3 curve_of(const Element& e, const std::vector<Vertex4>& list,
                         bool parameter_space) const;
  void build_curv(const Element& e);
  void build_curv2(const Element& e);
  void build_surf(Element& e);

  std::string m_name;
  const Read_options& m_options;
  Model& m_model;
  double m_scale = 1.0;
  std::vector<Vertex4> m_v;
  std::vector<Vertex4> m_vp;
  std::vector<std::optional<Nurbs_curve_3>> m_curv2;  // empty optional: an unusable curv2
  std::vector<Nurbs_curve_3> m_curves;
  std::vector<Face> m_faces;
  Triangle_mesh m_mesh;
  std::vector<int> m_vmap;  // OBJ vertex -> mesh vertex
  std::string m_object_name;
  // cstype / deg state
  bool m_rational = false;
  std::string m_type;
  int m_deg_u = 0, m_deg_v = 0;
  Element m_cur;
};

void Obj_parser::parse(const std::string& text) {
  m_scale = scene_scale(m_options.unitless_file_unit, m_options);
  std::vector<std::string> tok;
  std::size_t pos = 0;
  int line_no = 0;
  std::string logical;
  int logical_line = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    if (logical.empty()) logical_line = line_no;
    // Backslash continues the statement on the next line.
    if (!line.empty() && line.back() == '\\') {
      line.pop_back();
      logical += line + " ";
      continue;
    }
    logical += line;
    tok.clear();
    std::istringstream is(logical);
    for (std::string w; is >> w;) tok.push_back(w);
    logical.clear();
    if (!tok.empty()) statement(tok, logical_line);
  }
  if (m_cur.kind != Element::None) finish_element(false);

  if (m_faces.empty() && m_curves.empty() && m_mesh.empty()) return;
  Body b;
  b.source_name = m_object_name;
  b.faces = std::move(m_faces);
  b.curves = std::move(m_curves);
  b.mesh = std::move(m_mesh);
  m_model.bodies.push_back(std::move(b));
}

void Obj_parser::statement(const std::vector<std::string>& tok, int line) {
  const std::string& kw = tok[0];
  auto need = [&](std::size_t n) {
    if (tok.size() < n) {
      skip(line, kw, "too few values");
      return false;
    }
    return true;
  };
  if (kw == "v" || kw == "vp") {
    Vertex4 v{0, 0, 0, 1};
    double* dst[4] = {&v.x, &v.y, &v.z, &v.w};
    bool ok = tok.size() >= 2;
    for (std::size_t i = 1; i < tok.size() && i <= 4 && ok; ++i) ok = number(tok[i], *dst[i - 1]);
    if (kw == "vp" && tok.size() <= 3) v.w = 1.0;  // vp u v [w]: weight is the third value
    if (kw == "vp" && tok.size() >= 4) {
      v.w = v.z;
      v.z = 0.0;
    }
    if (!ok) {
      skip(line, kw, "malformed number; kept as (0, 0, 0) so later indices stay valid");
      v = {0, 0, 0, 1};
    }
    (kw == "v" ? m_v : m_vp).push_back(v);
    return;
  }
  if (kw == "vt" || kw == "vn" || kw == "g" || kw == "s" || kw == "mg" || kw == "usemtl" ||
      kw == "mtllib" || kw == "ctech" || kw == "stech" || kw == "lod" || kw == "bevel" ||
      kw == "c_interp" || kw == "d_interp" || kw == "shadow_obj" || kw == "trace_obj" ||
      kw == "maplib" || kw == "usemap")
    return;  // no geometry
  if (kw == "o") {
    if (tok.size() >= 2 && m_object_name.empty()) m_object_name = tok[1];
    return;
  }
  if (kw == "cstype") {
    if (!need(2)) return;
    m_rational = tok.size() >= 3 && tok[1] == "rat";
    m_type = tok.back();
    return;
  }
  if (kw == "deg") {
    if (!need(2)) return;
    long a = 0, b = 0;
    if (!integer(tok[1], a) || (tok.size() >= 3 && !integer(tok[2], b))) {
      skip(line, kw, "degree is not an integer");
      return;
    }
    if (a < 1 || a > k_max_degree_obj || (tok.size() >= 3 && (b < 1 || b > k_max_degree_obj))) {
      skip(line, kw, "degree outside 1..25; elements using it will be skipped");
      a = b = 0;
    }
    m_deg_u = static_cast<int>(a);
    m_deg_v = static_cast<int>(tok.size() >= 3 ? b : 0);
    return;
  }
  if (kw == "curv" || kw == "curv2" || kw == "surf") {
    if (m_cur.kind != Element::None) finish_element(false);
    Element e;
    e.kind = kw == "curv" ? Element::Curv : kw == "curv2" ? Element::Curv2 : Element::Surf;
    e.line = line;
    e.rational = m_rational;
    e.type = m_type;
    e.deg_u = m_deg_u;
    e.deg_v = m_deg_v;
    std::size_t first = 1;
    if (e.kind == Element::Curv) {
      if (!need(5) || !number(tok[1], e.s0) || !number(tok[2], e.s1)) {
        skip(line, kw, "needs u0 u1 and at least two control vertices");
        return;
      }
      first = 3;
    } else if (e.kind == Element::Surf) {
      if (!need(6) || !number(tok[1], e.s0) || !number(tok[2], e.s1) || !number(tok[3], e.t0) ||
          !number(tok[4], e.t1)) {
        skip(line, kw, "needs s0 s1 t0 t1 and control vertices");
        return;
      }
      first = 5;
    }
    const auto& list = e.kind == Element::Curv2 ? m_vp : m_v;
    for (std::size_t i = first; i < tok.size(); ++i) {
      long idx = 0;
      const long r = integer(tok[i], idx) ? resolve(idx, list.size()) : -1;
      if (r < 0) {
        skip(line, kw, "control vertex reference '" + tok[i] + "' is not a defined vertex");
        if (e.kind == Element::Curv2) m_curv2.emplace_back();  // keep curv2 numbering
        return;
      }
      e.refs.push_back(r);
    }
    m_cur = std::move(e);
    return;
  }
  if (kw == "parm") {
    if (m_cur.kind == Element::None) {
      skip(line, kw, "outside a curv/curv2/surf element");
      return;
    }
    if (!need(3) || (tok[1] != "u" && tok[1] != "v")) {
      skip(line, kw, "needs 'u' or 'v' and values");
      return;
    }
    std::vector<double> vals;
    for (std::size_t i = 2; i < tok.size(); ++i) {
      double x;
      if (!number(tok[i], x)) {
        skip(line, kw, "value '" + tok[i] + "' is not a finite number; element dropped");
        if (m_cur.kind == Element::Curv2) m_curv2.emplace_back();  // keep curv2 numbering
        m_cur = Element{};
        return;
      }
      vals.push_back(x);
    }
    if (tok[1] == "u") {
      m_cur.parm_u = std::move(vals);
      m_cur.has_parm_u = true;
    } else {
      m_cur.parm_v = std::move(vals);
      m_cur.has_parm_v = true;
    }
    return;
  }
  if (kw == "trim" || kw == "hole") {
    if (m_cur.kind != Element::Surf) {
      skip(line, kw, "outside a surf element");
      return;
    }
    if (tok.size() < 4 || (tok.size() - 1) % 3 != 0) {
      skip(line, kw, "needs triples u0 u1 curv2");
      return;
    }
    std::vector<Trim_ref> pieces;
    for (std::size_t i = 1; i + 2 < tok.size(); i += 3) {
      Trim_ref r{};
      if (!number(tok[i], r.t0) || !number(tok[i + 1], r.t1) || !integer(tok[i + 2], r.index)) {
        skip(line, kw, "malformed triple");
        return;
      }
      pieces.push_back(r);
    }
    m_cur.loops.emplace_back(kw == "trim", std::move(pieces));
    return;
  }
  if (kw == "end") {
    if (m_cur.kind == Element::None) return;
    finish_element(true);
    return;
  }
  if (kw == "f" || kw == "fo") {
    std::vector<int> idx;
    for (std::size_t i = 1; i < tok.size(); ++i) {
      long k = 0;
      const long r = integer(tok[i], k) ? resolve(k, m_v.size()) : -1;
      if (r < 0) {
        skip(line, kw, "vertex reference '" + tok[i] + "' is not a defined vertex");
        return;
      }
      idx.push_back(static_cast<int>(r));
    }
    if (idx.size() < 3) {
      skip(line, kw, "a face needs three vertices");
      return;
    }
    // The mesh keeps its own copy of the vertices it uses, scaled.
    if (m_vmap.size() < m_v.size()) m_vmap.resize(m_v.size(), -1);
    std::vector<int> mapped;
    for (int k : idx) {
      if (m_vmap[k] < 0) {
        const Vertex4& v = m_v[k];
        m_mesh.vertices.emplace_back(v.x * m_scale, v.y * m_scale, v.z * m_scale);
        m_vmap[k] = static_cast<int>(m_mesh.vertices.size()) - 1;
      }
      mapped.push_back(m_vmap[k]);
    }
    for (std::size_t i = 1; i + 1 < mapped.size(); ++i)
      m_mesh.triangles.push_back({mapped[0], mapped[i], mapped[i + 1]});
    return;
  }
  if (kw == "p" || kw == "l") {
    skip(line, kw, "points and polylines are not bodies");
    return;
  }
  if (kw == "sp" || kw == "scrv" || kw == "con" || kw == "bmat" || kw == "step" ||
      kw == "call" || kw == "csh") {
    skip(line, kw, "statement not supported");
    return;
  }
  skip(line, kw, "unknown statement");
}

std::vector<double> Obj_parser::knots_for(const Element& e, bool u, int degree, int n_ctrl,
                                          std::string& error) const {
  const std::vector<double>& parm = u ? e.parm_u : e.parm_v;
  const bool has = u ? e.has_parm_u : e.has_parm_v;
  if (e.type == "bspline") {
    if (!has) {
      error = std::string("missing 'parm ") + (u ? "u" : "v") + "'";
      return {};
    }
    return parm;
  }
  // Bezier: n = k * degree + 1 control points for k segments between the breakpoints.
  std::vector<double> br = has ? parm : std::vector<double>{0.0, 1.0};
  if (br.size() < 2 || static_cast<long>(br.size() - 1) * degree + 1 != n_ctrl) {
    std::ostringstream os;
    os << "Bezier with degree " << degree << " and " << br.size() << " breakpoints needs "
       << (br.size() >= 2 ? static_cast<long>(br.size() - 1) * degree + 1 : 0)
       << " control vertices, has " << n_ctrl;
    error = os.str();
    return {};
  }
  std::vector<double> k(degree + 1, br.front());
  for (std::size_t i = 1; i + 1 < br.size(); ++i) k.insert(k.end(), degree, br[i]);
  k.insert(k.end(), degree + 1, br.back());
  return k;
}

// The part of c over [a, b] (inside its domain), or c itself when that is the whole domain.
Nurbs_curve_3 sub_curve(const Nurbs_curve_3& c, double a, double b) {
  Nurbs_curve_3 r = c;
  if (b < r.domain_max() && b > r.domain_min()) r = split(r, b).first;
  if (a > r.domain_min() && a < r.domain_max()) r = split(r, a).second;
  return r;
}

Nurbs_surface_3 sub_surface(const Nurbs_surface_3& s, double u0, double u1, double v0, double v1) {
  Nurbs_surface_3 r = s;
  if (u1 < r.u_max() && u1 > r.u_min()) r = split(r, Parameter_direction::U, u1).first;
  if (u0 > r.u_min() && u0 < r.u_max()) r = split(r, Parameter_direction::U, u0).second;
  if (v1 < r.v_max() && v1 > r.v_min()) r = split(r, Parameter_direction::V, v1).first;
  if (v0 > r.v_min() && v0 < r.v_max()) r = split(r, Parameter_direction::V, v0).second;
  return r;
}

Nurbs_curve_3 Obj_parser::curve_of(const Element& e, const std::vector<Vertex4>& list,
                                   bool parameter_space) const {
  const int n = static_cast<int>(e.refs.size());
  std::string err;
  std::vector<double> k = knots_for(e, true, e.deg_u, n, err);
  if (!err.empty()) throw Invalid_input(err);
  const double scale = parameter_space ? 1.0 : m_scale;
  std::vector<Point_3> poles;
  std::vector<double> w;
  for (long r : e.refs) {
    const Vertex4& v = list[r];
    poles.emplace_back(v.x * scale, v.y * scale, parameter_space ? 0.0 : v.z * scale);
    w.push_back(e.rational ? v.w : 1.0);
  }
  return Nurbs_curve_3(e.deg_u, std::move(poles), std::move(k), std::move(w));
}

void Obj_parser::build_curv(const Element& e) {
  const Nurbs_curve_3 c = curve_of(e, m_v, false);
  const double a = std::max(std::min(e.s0, e.s1), c.domain_min());
  const double b = std::min(std::max(e.s0, e.s1), c.domain_max());
  if (!(a < b)) throw Invalid_input("curve range [u0, u1] lies outside the knot domain");
  m_curves.push_back(sub_curve(c, a, b));
}

void Obj_parser::build_curv2(const Element& e) { m_curv2.back() = curve_of(e, m_vp, true); }

void Obj_parser::build_surf(Element& e) {
  if (e.deg_v < 1) throw Invalid_input("surface needs two degrees ('deg du dv')");
  // The counts follow from the knots: n = knots - degree - 1 (B-spline), or from breakpoints.
  int nu = 0, nv = 0;
  const long total = static_cast<long>(e.refs.size());
  if (e.type == "bspline") {
    if (!e.has_parm_u || !e.has_parm_v) throw Invalid_input("missing 'parm u' or 'parm v'");
    nu = static_cast<int>(e.parm_u.size()) - e.deg_u - 1;
    nv = static_cast<int>(e.parm_v.size()) - e.deg_v - 1;
  } else {
    nu = static_cast<int>((e.has_parm_u ? e.parm_u.size() : 2) - 1) * e.deg_u + 1;
    nv = static_cast<int>((e.has_parm_v ? e.parm_v.size() : 2) - 1) * e.deg_v + 1;
  }
  if (nu < 1 || nv < 1 || static_cast<long>(nu) * nv != total) {
    std::ostringstream os;
    os << "knots and degrees call for " << nu << " x " << nv << " control vertices, the "
       << "statement lists " << total;
    throw Invalid_input(os.str());
  }
  std::string err;
  std::vector<double> ku = knots_for(e, true, e.deg_u, nu, err);
  if (err.empty()) {
    std::vector<double> kv = knots_for(e, false, e.deg_v, nv, err);
    if (err.empty()) {
      std::vector<Point_3> poles(static_cast<std::size_t>(total), Point_3(0, 0, 0));
      std::vector<double> w(static_cast<std::size_t>(total), 1.0);
      // OBJ lists control vertices with u varying fastest; ours are row-major in u.
      for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
          const Vertex4& v = m_v[e.refs[static_cast<std::size_t>(j) * nu + i]];
          poles[static_cast<std::size_t>(i) * nv + j] =
              Point_3(v.x * m_scale, v.y * m_scale, v.z * m_scale);
          w[static_cast<std::size_t>(i) * nv + j] = e.rational ? v.w : 1.0;
        }
      Nurbs_surface_3 s(e.deg_u, e.deg_v, nu, nv, std::move(poles), std::move(ku), std::move(kv),
                        std::move(w));
      // The global parameter ranges [s0, s1] x [t0, t1] restrict the patch.
      const double u0 = std::min(e.s0, e.s1), u1 = std::max(e.s0, e.s1);
      const double v0 = std::min(e.t0, e.t1), v1 = std::max(e.t0, e.t1);
      const double cu0 = std::max(u0, s.u_min()), cu1 = std::min(u1, s.u_max());
      const double cv0 = std::max(v0, s.v_min()), cv1 = std::min(v1, s.v_max());
      if (!(cu0 < cu1 && cv0 < cv1))
        throw Invalid_input("surface range s0 s1 t0 t1 lies outside the knot domain");
      if (cu0 != u0 || cu1 != u1 || cv0 != v0 || cv1 != v1) {
        std::ostringstream os;
        os << m_name << " line " << e.line << " (surf): range s0 s1 t0 t1 reaches outside the "
           << "knot domain; clamped to it";
        m_model.warnings.push_back(os.str());
      }
      std::ostringstream src;
      src << "surf at line " << e.line;
      Face face(sub_surface(s, cu0, cu1, cv0, cv1), e.rational ? "rational " + e.type : e.type);
      // OBJ files print about six digits, so a closed surface's seam (unclamped periodic knots,
      // wrapped control points) closes only to that precision: accept 1e-6 of the patch size.
      {
        const Nurbs_surface_3& fs = face.surface;
        const Bbox_3 hb = fs.hull_bbox();
        const double size = std::max({hb.xmax() - hb.xmin(), hb.ymax() - hb.ymin(),
                                      hb.zmax() - hb.zmin(), 1e-300});
        double gap_u = 0.0, gap_v = 0.0;
        for (int k = 0; k <= 8; ++k) {
          const double fu = std::min(fs.u_min() + (fs.u_max() - fs.u_min()) * k / 8.0, fs.u_max());
          const double fv = std::min(fs.v_min() + (fs.v_max() - fs.v_min()) * k / 8.0, fs.v_max());
          gap_u = std::max(gap_u, (to_vec3(fs.point(fs.u_min(), fv)) -
                                   to_vec3(fs.point(fs.u_max(), fv))).norm());
          gap_v = std::max(gap_v, (to_vec3(fs.point(fu, fs.v_min())) -
                                   to_vec3(fs.point(fu, fs.v_max()))).norm());
        }
        face.surface.set_closed(fs.is_closed_u() || gap_u <= 1e-6 * size,
                                fs.is_closed_v() || gap_v <= 1e-6 * size);
      }
      face.source = src.str();
      // Trim loops.
      for (auto& [outer, pieces] : e.loops) {
        Trim_loop loop;
        loop.is_outer = outer;
        bool ok = true;
        for (const Trim_ref& r : pieces) {
          const long ci = resolve(r.index, m_curv2.size());
          if (ci < 0 || !m_curv2[ci]) {
            std::ostringstream os;
            os << "trim curve " << r.index << " is not a usable curv2";
            skip(e.line, outer ? "trim" : "hole", os.str(), "loop dropped");
            ok = false;
            break;
          }
          const Nurbs_curve_3& c = *m_curv2[ci];
          const double a = std::max(std::min(r.t0, r.t1), c.domain_min());
          const double b = std::min(std::max(r.t0, r.t1), c.domain_max());
          if (!(a < b)) {
            skip(e.line, outer ? "trim" : "hole", "curve range outside the curv2's domain",
                 "loop dropped");
            ok = false;
            break;
          }
          loop.curves.push_back({sub_curve(c, a, b), -1, r.t0 > r.t1});
        }
        if (ok && !loop.curves.empty()) face.trims.push_back(std::move(loop));
      }
      const double extent = std::max(face.surface.u_max() - face.surface.u_min(),
                                     face.surface.v_max() - face.surface.v_min());
      face.update_trim_region(m_options.trim_tolerance * extent);
      if (!face.trim_region.is_closed()) {
        std::ostringstream os;
        os << m_name << " line " << e.line << " (surf): a trim loop does not close";
        m_model.warnings.push_back(os.str());
      }
      m_faces.push_back(std::move(face));
      return;
    }
  }
  throw Invalid_input(err);
}

void Obj_parser::finish_element(bool explicit_end) {
  Element e = std::move(m_cur);
  m_cur = Element{};
  const char* what = e.kind == Element::Curv ? "curv" : e.kind == Element::Curv2 ? "curv2" : "surf";
  if (e.kind == Element::Curv2) m_curv2.emplace_back();  // numbered even when unusable
  if (!explicit_end) {
    std::ostringstream os;
    os << m_name << " line " << e.line << " (" << what << "): no 'end'; element closed here";
    m_model.warnings.push_back(os.str());
  }
  if (e.type != "bspline" && e.type != "bezier") {
    skip(e.line, what,
         e.type.empty() ? "no 'cstype' before it"
                        : "cstype '" + e.type + "' is not supported (bspline and bezier are)");
    return;
  }
  if (e.deg_u < 1) {
    skip(e.line, what, "no valid 'deg' before it");
    return;
  }
  try {
    if (e.kind == Element::Curv)
      build_curv(e);
    else if (e.kind == Element::Curv2)
      build_curv2(e);
    else if (e.kind == Element::Surf)
      build_surf(e);
  } catch (const Invalid_input& ex) {
    skip(e.line, what, ex.what());
  } catch (const Precondition_violation& ex) {
    skip(e.line, what, ex.what());
  }
}

}  // namespace

void read_obj_freeform(const std::string& name, const std::string& text,
                       const Read_options& options, Model& model) {
  model.format_name = "OBJ free-form";
  model.file_unit = options.unitless_file_unit + " (assumed: OBJ carries no unit)";
  model.scale_to_unit = scene_scale(options.unitless_file_unit, options);
  Obj_parser(name, options, model).parse(text);
}

}  // namespace extremal::io::internal
