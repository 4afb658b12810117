#include "algorithms/scene/Report_rows.h"

#include <filesystem>
#include <set>

#include "kernel/Error.h"

namespace extremal::report {

std::vector<std::string> scene_tags(const std::vector<std::string>& scenes) {
  std::vector<std::string> tags;
  std::set<std::string> seen;
  bool clash = false;
  for (const auto& s : scenes) {
    tags.push_back(std::filesystem::path(s).stem().string());
    clash = clash || !seen.insert(tags.back()).second;
  }
  if (clash)
    for (std::size_t i = 0; i < tags.size(); ++i) tags[i] = std::to_string(i + 1) + "-" + tags[i];
  return tags;
}

std::string batch_path(const std::string& path, const std::string& tag, bool batch) {
  if (path.empty() || !batch) return path;
  const std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + "." + tag + p.extension().string())).string();
}

Report_rows::Report_rows(const io::Scene& scene, Report_writer& writer, int every)
    : m_scene(scene),
      m_writer(writer),
      m_every(every),
      m_summaries(scene.pairs.size()),
      m_classes(scene.pairs.size(), io::Clearance_class_builder(clearance_thresholds(scene))),
      m_was_farther(scene.pairs.size(), false) {
  EXTREMAL_PRECONDITION_MSG(every >= 1, "every must be >= 1, got " << every);
}

void Report_rows::add(double t, const std::vector<Pair_report>& reports) {
  const bool written = m_step % m_every == 0 || m_step == m_scene.step_count() - 1;
  ++m_step;
  for (std::size_t k = 0; k < m_summaries.size(); ++k) {
    const Pair_report& r = reports[k];
    const io::Clearance_state state = clearance_state(r.status);
    const bool farther = state == io::Clearance_state::Farther;
    m_summaries[k].add(t, r.distance, state);  // every step, written or not
    m_classes[k].add(t, state, r.distance, r.lower_bound);
    if (!written) continue;
    if (!(farther && m_was_farther[k])) {
      const auto& [a, b] = m_scene.pairs[k];
      m_writer.row(t, m_scene.bodies[a].name, m_scene.bodies[b].name, r);
    }
    m_was_farther[k] = farther;
  }
}

std::vector<io::Pair_summary> Report_rows::finish(const Report_timing& timing) {
  std::vector<io::Pair_summary> result;
  result.reserve(m_summaries.size());
  for (std::size_t k = 0; k < m_summaries.size(); ++k) {
    result.push_back(m_summaries[k].summary());
    result.back().clearance = m_classes[k].verdict();
  }
  m_writer.finish(result, timing);
  return result;
}

}  // namespace extremal::report
