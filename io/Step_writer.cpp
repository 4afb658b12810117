#include "io/Step_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "kernel/Error.h"

namespace extremal::io {

namespace {

// The shortest decimal that reads back to x, in STEP's REAL syntax (a '.' always, E exponent).
std::string real(double x) {
  if (!std::isfinite(x)) throw Invalid_input("STEP writer: a coordinate or weight is not finite");
  if (x == 0.0) return "0.";
  char buf[40];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*G", precision, x);
    if (std::strtod(buf, nullptr) == x) break;
  }
  std::string s = buf;
  const auto e = s.find('E');
  const std::string mantissa = s.substr(0, e);
  if (mantissa.find('.') == std::string::npos)
    s.insert(e == std::string::npos ? s.size() : e, ".");
  return s;
}

// A STEP string literal: quotes doubled, backslashes doubled, non-ASCII replaced by '_'.
std::string text(const std::string& s) {
  std::string out = "'";
  for (unsigned char c : s) {
    if (c == '\'') out += "''";
    else if (c == '\\') out += "\\\\";
    else if (c < 32 || c > 126) out += '_';
    else out += static_cast<char>(c);
  }
  return out + "'";
}

// Distinct knots and their multiplicities, as STEP lists them.
void split_knots(const std::vector<double>& flat, std::string& mults, std::string& knots) {
  std::ostringstream m, k;
  m << '(';
  k << '(';
  for (std::size_t i = 0; i < flat.size();) {
    std::size_t j = i;
    while (j < flat.size() && flat[j] == flat[i]) ++j;
    if (i > 0) m << ',', k << ',';
    m << (j - i);
    k << real(flat[i]);
    i = j;
  }
  m << ')';
  k << ')';
  mults = m.str();
  knots = k.str();
}

class Step_text {
 public:
  int add(const std::string& entity) {
    m_lines.push_back(entity);
    return static_cast<int>(m_lines.size());
  }
  static std::string ref(int id) { return "#" + std::to_string(id); }
  int point(const Vec3& p) {
    return add("CARTESIAN_POINT('',(" + real(p.x()) + "," + real(p.y()) + "," + real(p.z()) +
               "))");
  }
  int direction(double x, double y, double z) {
    return add("DIRECTION('',(" + real(x) + "," + real(y) + "," + real(z) + "))");
  }

  int curve(const Nurbs_curve_3& c) {
    std::string poles = "(";
    for (int i = 0; i < c.number_of_poles(); ++i)
      poles += (i ? "," : "") + ref(point(to_vec3(c.poles()[i])));
    poles += ")";
    std::string mults, knots;
    split_knots(c.knots(), mults, knots);
    const std::string d = std::to_string(c.degree());
    if (!c.is_rational())
      return add("B_SPLINE_CURVE_WITH_KNOTS(''," + d + "," + poles + ",.UNSPECIFIED.,.F.,.F.," +
                 mults + "," + knots + ",.UNSPECIFIED.)");
    std::string w = "(";
    for (std::size_t i = 0; i < c.weights().size(); ++i) w += (i ? "," : "") + real(c.weights()[i]);
    w += ")";
    // Complex instance: partial entities in alphabetical order (ISO 10303-21 external mapping).
    return add("(BOUNDED_CURVE()B_SPLINE_CURVE(" + d + "," + poles +
               ",.UNSPECIFIED.,.F.,.F.)B_SPLINE_CURVE_WITH_KNOTS(" + mults + "," + knots +
               ",.UNSPECIFIED.)CURVE()GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_CURVE(" +
               w + ")REPRESENTATION_ITEM(''))");
  }

  int surface(const Nurbs_surface_3& s) {
    std::string poles = "(", weights = "(";
    for (int i = 0; i < s.number_of_poles_u(); ++i) {
      poles += i ? ",(" : "(";
      weights += i ? ",(" : "(";
      for (int j = 0; j < s.number_of_poles_v(); ++j) {
        poles += (j ? "," : "") + ref(point(to_vec3(s.pole(i, j))));
        if (s.is_rational()) weights += (j ? "," : "") + real(s.weight(i, j));
      }
      poles += ")";
      weights += ")";
    }
    poles += ")";
    weights += ")";
    std::string mu, ku, mv, kv;
    split_knots(s.knots_u(), mu, ku);
    split_knots(s.knots_v(), mv, kv);
    const std::string d = std::to_string(s.degree_u()) + "," + std::to_string(s.degree_v());
    if (!s.is_rational())
      return add("B_SPLINE_SURFACE_WITH_KNOTS(''," + d + "," + poles +
                 ",.UNSPECIFIED.,.F.,.F.,.F.," + mu + "," + mv + "," + ku + "," + kv +
                 ",.UNSPECIFIED.)");
    return add("(BOUNDED_SURFACE()B_SPLINE_SURFACE(" + d + "," + poles +
               ",.UNSPECIFIED.,.F.,.F.,.F.)B_SPLINE_SURFACE_WITH_KNOTS(" + mu + "," + mv + "," +
               ku + "," + kv +
               ",.UNSPECIFIED.)GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_SURFACE(" +
               weights + ")REPRESENTATION_ITEM('')SURFACE())");
  }

  std::string data() const {
    std::ostringstream os;
    for (std::size_t i = 0; i < m_lines.size(); ++i)
      os << '#' << (i + 1) << '=' << m_lines[i] << ";\n";
    return os.str();
  }

 private:
  std::vector<std::string> m_lines;
};

bool is_identity(const Rigid_pose_3& X) {
  return X.rotation() == Mat3::Identity() && X.translation() == Vec3::Zero();
}

std::string body_label(const Body& b, std::size_t k) {
  return "body " + std::to_string(k) + (b.name.empty() ? "" : " '" + b.name + "'");
}

// Writes one body's MANIFOLD_SOLID_BREP and returns its id.
int write_solid(Step_text& out, const Body& body, std::size_t body_index) {
  const std::string label = body_label(body, body_index);
  if (body.faces.empty() || body.edges.empty())
    throw Invalid_input("STEP writer: " + label +
                        " has no B-rep (faces with trim loops on shared edges); only closed "
                        "B-rep solids are written");
  const bool placed = !is_identity(body.placement);

  // Edge curves and end points, in the file frame.
  const std::size_t n_edges = body.edges.size();
  std::vector<Nurbs_curve_3> curves;
  std::vector<Vec3> ends;  // 2 per edge
  double size = 0.0, tolerance = 0.0;
  for (std::size_t e = 0; e < n_edges; ++e) {
    const Edge& edge = body.edges[e];
    if (!edge.curve)
      throw Invalid_input("STEP writer: " + label + ", edge " + std::to_string(e) +
                          " is degenerate (no 3D curve); degenerate edges are not written");
    curves.push_back(placed ? transformed(*edge.curve, body.placement) : *edge.curve);
    const Nurbs_curve_3& c = curves.back();
    const double t0 = std::clamp(edge.t_min, c.domain_min(), c.domain_max());
    const double t1 = std::clamp(edge.t_max, c.domain_min(), c.domain_max());
    ends.push_back(to_vec3(c.point(t0)));
    ends.push_back(to_vec3(c.point(t1)));
    tolerance = std::max(tolerance, edge.tolerance);
    for (const auto& p : c.poles()) size = std::max(size, to_vec3(p).cwiseAbs().maxCoeff());
  }
  // End points closer than this are one vertex.
  const double merge = std::max(2.0 * tolerance, 1e-9 * std::max(size, 1.0));
  std::vector<int> vertex_of_end(ends.size());
  std::vector<Vec3> vertices;
  for (std::size_t k = 0; k < ends.size(); ++k) {
    int found = -1;
    for (std::size_t v = 0; v < vertices.size() && found < 0; ++v)
      if ((vertices[v] - ends[k]).norm() <= merge) found = static_cast<int>(v);
    if (found < 0) {
      found = static_cast<int>(vertices.size());
      vertices.push_back(ends[k]);
    }
    vertex_of_end[k] = found;
  }

  // Each face's loops about its outward normal: a same_sense face keeps the loops as stored
  // (counterclockwise in (u, v) for outer loops), a reversed face runs them backwards.
  struct Use {
    int edge;
    bool forward;  // along the edge's curve
  };
  std::vector<std::vector<std::vector<Use>>> loops(body.faces.size());
  std::vector<int> forward_uses(n_edges, 0), backward_uses(n_edges, 0);
  for (std::size_t f = 0; f < body.faces.size(); ++f) {
    const Face& face = body.faces[f];
    const bool same_sense = face.surface.outward_sign() > 0;
    const std::string face_label = label + ", face " + std::to_string(f);
    if (face.trims.empty())
      throw Invalid_input("STEP writer: " + face_label + " has no trim loop on the body's edges");
    for (std::size_t l = 0; l < face.trims.size(); ++l) {
      std::vector<Use> loop;
      for (const Trim_curve& tc : face.trims[l].curves) {
        if (tc.edge < 0 || tc.edge >= static_cast<int>(n_edges))
          throw Invalid_input("STEP writer: " + face_label + ", loop " + std::to_string(l) +
                              " has a curve that references no edge of the body");
        loop.push_back({tc.edge, !tc.reversed});
      }
      if (!same_sense) {
        std::reverse(loop.begin(), loop.end());
        for (Use& u : loop) u.forward = !u.forward;
      }
      for (std::size_t k = 0; k < loop.size(); ++k) {
        const Use& a = loop[k];
        const Use& b = loop[(k + 1) % loop.size()];
        const int a_end = vertex_of_end[2 * a.edge + (a.forward ? 1 : 0)];
        const int b_start = vertex_of_end[2 * b.edge + (b.forward ? 0 : 1)];
        if (a_end != b_start)
          throw Invalid_input("STEP writer: " + face_label + ", loop " + std::to_string(l) +
                              ": edge " + std::to_string(a.edge) + " does not end where edge " +
                              std::to_string(b.edge) + " starts");
        (a.forward ? forward_uses : backward_uses)[a.edge]++;
      }
      loops[f].push_back(std::move(loop));
    }
  }
  for (std::size_t e = 0; e < n_edges; ++e)
    if (forward_uses[e] != 1 || backward_uses[e] != 1) {
      std::ostringstream os;
      os << "STEP writer: " << label << ", edge " << e << " is used " << forward_uses[e]
         << " time(s) along its curve and " << backward_uses[e]
         << " time(s) against it; a closed, consistently oriented shell uses every edge once "
            "each way";
      throw Invalid_input(os.str());
    }

  std::vector<int> vertex_ids;
  for (const Vec3& v : vertices)
    vertex_ids.push_back(out.add("VERTEX_POINT(''," + Step_text::ref(out.point(v)) + ")"));
  std::vector<int> edge_ids;
  for (std::size_t e = 0; e < n_edges; ++e) {
    const int c = out.curve(curves[e]);
    edge_ids.push_back(out.add("EDGE_CURVE(''," + Step_text::ref(vertex_ids[vertex_of_end[2 * e]]) +
                               "," + Step_text::ref(vertex_ids[vertex_of_end[2 * e + 1]]) + "," +
                               Step_text::ref(c) + ",.T.)"));
  }
  std::string face_list = "(";
  for (std::size_t f = 0; f < body.faces.size(); ++f) {
    const Face& face = body.faces[f];
    std::string bounds = "(";
    for (std::size_t l = 0; l < loops[f].size(); ++l) {
      std::string oriented = "(";
      for (std::size_t k = 0; k < loops[f][l].size(); ++k) {
        const Use& u = loops[f][l][k];
        const int oe = out.add("ORIENTED_EDGE('',*,*," + Step_text::ref(edge_ids[u.edge]) +
                               (u.forward ? ",.T.)" : ",.F.)"));
        oriented += (k ? "," : "") + Step_text::ref(oe);
      }
      oriented += ")";
      const int loop = out.add("EDGE_LOOP(''," + oriented + ")");
      const char* kind = face.trims[l].is_outer ? "FACE_OUTER_BOUND" : "FACE_BOUND";
      const int bound = out.add(std::string(kind) + "(''," + Step_text::ref(loop) + ",.T.)");
      bounds += (l ? "," : "") + Step_text::ref(bound);
    }
    bounds += ")";
    const int surface =
        out.surface(placed ? transformed(face.surface, body.placement) : face.surface);
    face_list += (f ? "," : "") +
                 Step_text::ref(out.add("ADVANCED_FACE(''," + bounds + "," +
                                        Step_text::ref(surface) +
                                        (face.surface.outward_sign() > 0 ? ",.T.)" : ",.F.)")));
  }
  face_list += ")";
  const int shell = out.add("CLOSED_SHELL(''," + face_list + ")");
  return out.add("MANIFOLD_SOLID_BREP(" + text(body.name) + "," + Step_text::ref(shell) + ")");
}

std::string step_document(const std::vector<Body>& bodies, const Step_write_options& options,
                          const std::string& file_name) {
  if (bodies.empty()) throw Invalid_input("STEP writer: no body to write");
  const std::string product =
      options.product_name.empty() ? (bodies[0].name.empty() ? "part" : bodies[0].name)
                                   : options.product_name;
  Step_text out;
  const int app =
      out.add("APPLICATION_CONTEXT('core data for automotive mechanical design processes')");
  out.add("APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000," +
          Step_text::ref(app) + ")");
  const int product_context =
      out.add("PRODUCT_CONTEXT(''," + Step_text::ref(app) + ",'mechanical')");
  const int prod = out.add("PRODUCT(" + text(product) + "," + text(product) + ",'',(" +
                           Step_text::ref(product_context) + "))");
  out.add("PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(" + Step_text::ref(prod) + "))");
  const int formation = out.add("PRODUCT_DEFINITION_FORMATION('',''," + Step_text::ref(prod) + ")");
  const int def_context =
      out.add("PRODUCT_DEFINITION_CONTEXT('part definition'," + Step_text::ref(app) + ",'design')");
  const int definition = out.add("PRODUCT_DEFINITION('design',''," + Step_text::ref(formation) +
                                 "," + Step_text::ref(def_context) + ")");
  const int shape = out.add("PRODUCT_DEFINITION_SHAPE(''," + Step_text::ref(definition) + ")");
  const int length = out.add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))");
  const int angle = out.add("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))");
  const int solid_angle = out.add("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())");
  const int uncertainty =
      out.add("UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07)," + Step_text::ref(length) +
              ",'distance_accuracy_value','confusion accuracy')");
  const int context = out.add(
      "(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((" +
      Step_text::ref(uncertainty) + "))GLOBAL_UNIT_ASSIGNED_CONTEXT((" + Step_text::ref(length) +
      "," + Step_text::ref(angle) + "," + Step_text::ref(solid_angle) +
      "))REPRESENTATION_CONTEXT('Context #1','3D Context with UNIT and UNCERTAINTY'))");
  const int origin = out.point(Vec3::Zero());
  const int z = out.direction(0, 0, 1), x = out.direction(1, 0, 0);
  const int axes = out.add("AXIS2_PLACEMENT_3D(''," + Step_text::ref(origin) + "," +
                           Step_text::ref(z) + "," + Step_text::ref(x) + ")");
  std::string items = "(" + Step_text::ref(axes);
  for (std::size_t k = 0; k < bodies.size(); ++k)
    items += "," + Step_text::ref(write_solid(out, bodies[k], k));
  items += ")";
  const int rep = out.add("ADVANCED_BREP_SHAPE_REPRESENTATION(" + text(product) + "," + items +
                          "," + Step_text::ref(context) + ")");
  out.add("SHAPE_DEFINITION_REPRESENTATION(" + Step_text::ref(shape) + "," + Step_text::ref(rep) +
          ")");

  std::ostringstream os;
  os << "ISO-10303-21;\nHEADER;\n"
     << "FILE_DESCRIPTION(('Extremal B-rep solid'),'2;1');\n"
     << "FILE_NAME(" << text(file_name) << "," << text(options.time_stamp)
     << ",('Extremal'),('Extremal'),'Extremal STEP writer','Extremal','');\n"
     << "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n"
     << out.data() << "ENDSEC;\nEND-ISO-10303-21;\n";
  return os.str();
}

}  // namespace

std::string write_step_string(const std::vector<Body>& bodies, const Step_write_options& options) {
  return step_document(bodies, options, options.file_name);
}

void write_step(const std::string& path, const std::vector<Body>& bodies,
                const Step_write_options& options) {
  const std::string name =
      options.file_name.empty() ? path.substr(path.find_last_of("/\\") + 1) : options.file_name;
  const std::string document = step_document(bodies, options, name);
  std::ofstream file(path, std::ios::binary);
  if (!file) throw Invalid_input(path + ": cannot open for writing");
  file << document;
  if (!file.flush()) throw Invalid_input(path + ": write failed");
}

}  // namespace extremal::io
