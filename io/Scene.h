// Scene files (docs/cli.md): units, time range, bodies with shapes or files, poses and
// motions, watched pairs, threshold and tracker settings. Every error names the file, the JSON
// path and the reason, e.g. "scene.json: bodies[1].motion.keyframes[1].t: times must increase";
// unknown keys are errors, not ignored.
#pragma once

#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "kernel/Body.h"
#include "kernel/Motion.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal::io {

struct Scene_body {
  std::string name;    // unique; a multi-solid file entry NAME gives NAME/1, NAME/2, ...
  std::string entry;   // the scene entry's name (the same as name for single bodies)
  std::string source;  // shape spec or file path, for reports
  Body body;           // in the body frame, lengths in scene units
  Motion motion;
};

struct Tracker_settings {
  double gain = 0.0;  // 1/s; 0 means 1/step
  int substeps = 1;
  bool rk4 = false;
  int audit_every = 0;  // steps between global audits; 0 = never
  // A tracked pair's second basin is taken once closer by this fraction of the distance
  // (Body_pair_options::own_basin_gap); 0 = not watched.
  double own_basin_gap = 1e-3;
  // The most memory one pair's candidate stage may hold, in MiB
  // (Body_pair_options::memory_limit); 0: the options' default.
  double memory_limit_mib = 0.0;
};

// What an apart row may miss the true distance by (Body_pair_options::tolerance): its
// certified lower bound is at least d - max(absolute, relative |d|).
struct Tolerance_settings {
  double absolute = 1e-9;  // scene units, > 0
  double relative = 1e-9;  // > 0 and < 1
};

struct Scene {
  std::string path;
  std::string units = "mm";
  double start = 0.0, end = 0.0, step = 0.0;
  std::vector<Scene_body> bodies;
  std::vector<std::pair<int, int>> pairs;  // indices into bodies
  std::optional<double> threshold;
  // The scene's "clearance": pairs closer than it (and not in contact) are of the class
  // `clearance` (io/Clearance_class.h); none: no such class.
  std::optional<double> clearance;
  Tracker_settings tracker;
  Tolerance_settings tolerance;  // the scene's "tolerance": {"absolute", "relative"}

  int step_count() const;  // number of time steps from start to end inclusive
  double time_of(int step_index) const;
};

// Loads the bodies of a `file` entry: (path, units of the entry) -> bodies in scene units.
// Installed by the CAD import layer; without one, file entries are reported as unsupported.
using File_loader = std::function<std::vector<Body>(const std::string& path,
                                                    const std::string& file_units,
                                                    const std::string& scene_units)>;

Scene read_scene(const std::string& path, const File_loader& load_file = {});
Scene parse_scene(const std::string& json_text, const std::string& path,
                  const File_loader& load_file = {});

// The poses of a pose table (a scene's `"motion": {"type": "table", "file": ...}`): an optional
// header `t,x,y,z,qw,qx,qy,qz`, then one row of 8 finite numbers per pose, times increasing,
// unit quaternions; blank lines and lines starting with '#' are skipped. Throws Invalid_input
// "NAME:LINE: reason" (NAME: the table's file name) on anything else, or when it has no rows.
std::vector<Keyframe> parse_pose_table(std::istream& in, const std::string& name);

// Length of one unit in millimetres ("mm", "cm", "m", "in", "ft", "um"); throws otherwise.
double unit_in_mm(const std::string& unit);

}  // namespace extremal::io
