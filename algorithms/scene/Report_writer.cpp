#include "algorithms/scene/Report_writer.h"

#include <cstdio>
#include <sstream>

#include "algorithms/body_pair/Body_pair_options.h"
#include "kernel/Error.h"

namespace extremal::report {

namespace {

// The detail column: why the tracker fell back, or that the certified solver answered (with the
// reading rule that rejected the closest tracker's reading, if one did); then, past the pair's
// memory limit, `memory_limit`.
std::string detail(const Pair_report& r) {
  std::string d = !r.solved ? to_string(r.degeneracy)
                  : r.rejected_by == Reading_rule::None
                      ? "solved"
                      : std::string("solved: ") + to_string(r.rejected_by);
  if (r.memory_limited) d += d.empty() ? "memory_limit" : "; memory_limit";
  return d;
}

nlohmann::json vec_json(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json intervals_json(const std::vector<io::Time_interval>& runs) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& r : runs) j.push_back({{"start", r.start}, {"end", r.end}});
  return j;
}

class Csv_writer final : public Report_writer {
 public:
  Csv_writer(std::ostream& out, bool header, std::string scene)
      : m_out(out), m_scene(scene.empty() ? std::string() : csv_field(scene)) {
    if (header) m_out << csv_header(!scene.empty()) << '\n';
  }
  void row(double t, const std::string& body_a, const std::string& body_b,
           const Pair_report& r) override {
    m_out << format_number(t) << ',' << csv_field(body_a) << ',' << csv_field(body_b) << ','
          << format_number(r.distance);
    for (const Vec3* v : {&r.point_a, &r.point_b, &r.normal})
      for (int c = 0; c < 3; ++c) m_out << ',' << format_number((*v)[c]);
    m_out << ',' << r.feature_a << ',' << r.feature_b << ',' << to_string(r.status) << ','
          << detail(r);
    for (int c = 0; c < 4; ++c) m_out << ',' << format_number(r.params[c]);
    m_out << ',';
    if (r.lower_bound) m_out << format_number(*r.lower_bound);  // (empty: no bound)
    if (!m_scene.empty()) m_out << ',' << m_scene;
    m_out << '\n';
  }
  void finish(const std::vector<io::Pair_summary>&, const Report_timing&) override {
    m_out.flush();
  }

 private:
  std::ostream& m_out;
  std::string m_scene;
};

// Streams the rows (one per line) so long runs never hold the report in memory.
class Json_writer final : public Report_writer {
 public:
  Json_writer(std::ostream& out, const io::Scene& scene) : m_out(out), m_scene(scene) {
    nlohmann::json bodies = nlohmann::json::array();
    for (const auto& b : scene.bodies) {
      // A shape entry's source is its shape object; a file entry's, the file's path.
      const nlohmann::json shape = nlohmann::json::parse(b.source, nullptr, false);
      if (shape.is_object())
        bodies.push_back({{"name", b.name}, {"shape", shape}});
      else
        bodies.push_back({{"name", b.name}, {"file", b.source}});
    }
    nlohmann::json pairs = nlohmann::json::array();
    const io::Clearance_thresholds thresholds = clearance_thresholds(scene);
    for (const auto& [a, b] : scene.pairs)
      pairs.push_back({scene.bodies[a].name, scene.bodies[b].name});
    m_out << "{\n\"scene\": " << nlohmann::json(scene.path).dump()
          << ",\n\"units\": " << nlohmann::json(scene.units).dump() << ",\n\"time\": "
          << nlohmann::json({{"start", scene.start},
                             {"end", scene.end},
                             {"step", scene.step},
                             {"steps", scene.step_count()}})
                 .dump()
          << ",\n\"contact_tolerance\": " << nlohmann::json(thresholds.contact).dump()
          << ",\n\"clearance\": "
          << (thresholds.clearance ? nlohmann::json(*thresholds.clearance) : nlohmann::json()).dump()
          << ",\n\"bodies\": " << bodies.dump() << ",\n\"pairs\": " << pairs.dump()
          << ",\n\"rows\": [";
  }
  void row(double t, const std::string& body_a, const std::string& body_b,
           const Pair_report& r) override {
    const nlohmann::json j = {{"t", t},
                              {"body_a", body_a},
                              {"body_b", body_b},
                              {"distance", r.distance},
                              {"point_a", vec_json(r.point_a)},
                              {"point_b", vec_json(r.point_b)},
                              {"normal", vec_json(r.normal)},
                              {"face_a", r.feature_a},
                              {"face_b", r.feature_b},
                              {"status", to_string(r.status)},
                              {"detail", detail(r)},
                              {"params", {r.params[0], r.params[1], r.params[2], r.params[3]}},
                              {"lower_bound", r.lower_bound ? nlohmann::json(*r.lower_bound)
                                                            : nlohmann::json()}};
    m_out << (m_first ? "\n" : ",\n") << j.dump();
    m_first = false;
  }
  void finish(const std::vector<io::Pair_summary>& summaries,
              const Report_timing& timing) override {
    EXTREMAL_PRECONDITION(timing.pairs.size() == summaries.size());
    m_out << "\n],\n\"summary\": [";
    for (std::size_t k = 0; k < summaries.size(); ++k) {
      const auto& [a, b] = m_scene.pairs[k];
      m_out << (k ? ",\n" : "\n")
            << summary_json(m_scene.bodies[a].name, m_scene.bodies[b].name, summaries[k],
                            timing.pairs[k], timing.audit_pairs[k])
                   .dump();
    }
    m_out << "\n],\n\"step_time_us\": " << step_time_json(timing.scene).dump()
          << ",\n\"audit_time_us\": " << step_time_json(timing.audit_scene).dump() << "\n}\n";
    m_out.flush();
  }

 private:
  std::ostream& m_out;
  const io::Scene& m_scene;
  bool m_first = true;
};

std::string short_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

std::string intervals_text(const std::vector<io::Time_interval>& runs) {
  std::ostringstream os;
  const std::size_t shown = std::min<std::size_t>(runs.size(), 3);
  for (std::size_t i = 0; i < shown; ++i) {
    os << (i ? ", " : "") << "t = " << short_number(runs[i].start);
    if (runs[i].end > runs[i].start) os << " to " << short_number(runs[i].end);
  }
  if (runs.size() > shown) os << " and " << runs.size() - shown << " more";
  return os.str();
}

// "clash", or "undecided (clearance to contact)": the class and, undecided, its range.
std::string class_text(const io::Clearance_verdict& v) {
  std::string text = to_string(v.verdict);
  if (v.verdict == io::Clearance_class::Undecided)
    text += std::string(" (") + to_string(v.range.proven) + " to " + to_string(v.range.possible) + ")";
  return text;
}

// "(contact within 1e-09, clearance below 2)".
std::string thresholds_text(const io::Clearance_thresholds& t) {
  return "(contact within " + short_number(t.contact) +
         (t.clearance ? ", clearance below " + short_number(*t.clearance) : ", no clearance set") +
         ")";
}

}  // namespace

std::string class_counts_text(const std::vector<io::Pair_summary>& summaries) {
  std::string text;
  for (io::Clearance_class c : {io::Clearance_class::Clash, io::Clearance_class::Contact,
                                io::Clearance_class::Clearance, io::Clearance_class::Undecided,
                                io::Clearance_class::Clear}) {
    long n = 0;
    for (const auto& s : summaries) n += s.clearance.verdict == c;
    if (n) text += (text.empty() ? "" : ", ") + std::to_string(n) + " " + to_string(c);
  }
  return text;
}

std::string csv_header(bool with_scene_column) {
  return std::string("t,body_a,body_b,distance,ax,ay,az,bx,by,bz,nx,ny,nz,face_a,face_b,status,"
                     "detail,ua,va,ub,vb,lower_bound") +
         (with_scene_column ? ",scene" : "");
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string format_number(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

io::Clearance_state clearance_state(Pair_status status) {
  switch (status) {
    case Pair_status::Contact: return io::Clearance_state::Contact;
    case Pair_status::Penetrating: return io::Clearance_state::Penetrating;
    case Pair_status::Farther: return io::Clearance_state::Farther;
    case Pair_status::Uncertified: return io::Clearance_state::Uncertified;
    default: return io::Clearance_state::Apart;
  }
}

io::Clearance_thresholds clearance_thresholds(const io::Scene& scene) {
  return {Body_pair_options{}.contact_tolerance, scene.clearance};
}

std::unique_ptr<Report_writer> make_csv_writer(std::ostream& out, bool header,
                                               const std::string& scene_column) {
  return std::make_unique<Csv_writer>(out, header, scene_column);
}

std::unique_ptr<Report_writer> make_json_writer(std::ostream& out, const io::Scene& scene) {
  return std::make_unique<Json_writer>(out, scene);
}

nlohmann::json summary_json(const std::string& body_a, const std::string& body_b,
                            const io::Pair_summary& s, const Step_time_stats& step_time,
                            const Step_time_stats& audit_time) {
  nlohmann::json j = {{"body_a", body_a},
                      {"body_b", body_b},
                      {"class", to_string(s.clearance.verdict)},
                      {"class_range",
                       {to_string(s.clearance.range.proven), to_string(s.clearance.range.possible)}},
                      {"undecided", intervals_json(s.clearance.undecided)},
                      {"rows", s.rows},
                      {"tracked_rows", s.tracked_rows}};
  j["min_distance"] = s.min_distance ? nlohmann::json(*s.min_distance) : nlohmann::json();
  j["min_time"] = s.min_distance ? nlohmann::json(s.min_time) : nlohmann::json();
  j["contact"] = intervals_json(s.contact);
  j["penetration"] = intervals_json(s.penetration);
  j["deepest_penetration"] =
      s.deepest_penetration ? nlohmann::json(*s.deepest_penetration) : nlohmann::json();
  j["deepest_time"] = s.deepest_penetration ? nlohmann::json(s.deepest_time) : nlohmann::json();
  j["farther"] = intervals_json(s.farther);
  j["uncertified"] = intervals_json(s.uncertified);
  j["step_time_us"] = step_time_json(step_time);
  j["audit_time_us"] = step_time_json(audit_time);
  return j;
}

void print_summary(std::ostream& out, const io::Scene& scene, const std::string& written_to,
                   const std::vector<io::Pair_summary>& summaries, const Report_timing& timing) {
  EXTREMAL_PRECONDITION(timing.pairs.size() == summaries.size());
  out << scene.path << ": " << scene.bodies.size() << " bodies, " << scene.pairs.size()
      << " watched pair" << (scene.pairs.size() == 1 ? "" : "s") << ", " << scene.step_count()
      << " steps from t = " << short_number(scene.start) << " to "
      << short_number(scene.time_of(scene.step_count() - 1)) << " s (lengths in " << scene.units
      << ")";
  if (!written_to.empty()) out << " -> " << written_to;
  out << "\n";
  out << "  step time of the scene (its pairs' together): " << step_time_text(timing.scene) << "\n";
  if (timing.audit_scene.max > 0.0)
    out << "  audits (apart from the step time): " << step_time_text(timing.audit_scene) << "\n";
  out << "  classes " << thresholds_text(clearance_thresholds(scene)) << ": "
      << class_counts_text(summaries) << "\n";
  for (std::size_t k = 0; k < summaries.size(); ++k) {
    const io::Pair_summary& s = summaries[k];
    const auto& [a, b] = scene.pairs[k];
    out << "  " << scene.bodies[a].name << " - " << scene.bodies[b].name << ": ";
    const std::string step_time = "    class: " + class_text(s.clearance) + "\n    step time: " +
                                  step_time_text(timing.pairs[k]) + "\n";
    if (!s.min_distance) {
      out << "farther than the threshold " << short_number(scene.threshold.value_or(0.0))
          << " throughout\n"
          << step_time;
      continue;
    }
    out << "minimum clearance " << short_number(*s.min_distance) << " at t = "
        << short_number(s.min_time) << "\n";
    if (s.contact.empty())
      out << "    never in contact\n";
    else
      out << "    in contact " << intervals_text(s.contact) << "\n";
    if (!s.penetration.empty())
      out << "    penetrating " << intervals_text(s.penetration) << "; deepest "
          << short_number(*s.deepest_penetration) << " at t = " << short_number(s.deepest_time)
          << "\n";
    if (!s.farther.empty())
      out << "    farther than the threshold " << intervals_text(s.farther) << "\n";
    if (!s.uncertified.empty())
      out << "    uncertified (lower bound short of the error budget) " << intervals_text(s.uncertified)
          << "\n";
    if (!s.clearance.undecided.empty())
      out << "    undecided (a bound leaves the class open) "
          << intervals_text(s.clearance.undecided) << "\n";
    out << step_time;
  }
}

}  // namespace extremal::report
