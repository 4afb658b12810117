// extremal.Tracker (two bodies) and extremal.SceneTracker (several bodies, watched pairs): the
// extremal pair of each watched pair kept up to date while Python moves the bodies.
#include <atomic>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "Convert.h"
#include "algorithms/scene/Scene_setup.h"

namespace extremal::python {

namespace {

// The reading fields of a Pair_report (its counters are statistics, not the reading).
struct Py_pair_report {
  double time = 0.0, distance = 0.0;
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero(), normal = Vec3::Zero();
  int face_a = -1, face_b = -1;
  Vec4 params = Vec4::Zero();
  Pair_status status = Pair_status::Tracking;
  Degeneracy degeneracy = Degeneracy::None;
  bool solved = false;

  explicit Py_pair_report(const Pair_report& r)
      : time(r.time),
        distance(r.distance),
        point_a(r.point_a),
        point_b(r.point_b),
        normal(r.normal),
        face_a(r.feature_a),
        face_b(r.feature_b),
        params(r.params),
        status(r.status),
        degeneracy(r.degeneracy),
        solved(r.solved) {}
};

// The tracker settings of a scene file's "tracker" object and "threshold", mapped onto the
// trackers' options exactly as `extremal report` maps a scene's (pair_options_of).
Body_pair_options pair_options(double gain, int substeps, const std::string& integrator,
                               int audit_every, double own_basin_gap,
                               std::optional<double> threshold) {
  io::Scene scene;
  if (!(std::isfinite(gain) && gain >= 0.0))
    throw Invalid_input("gain: must be finite and >= 0 (0: 1/dt), got " + number_text(gain));
  if (substeps < 1) throw Invalid_input("substeps: must be at least 1, got " + std::to_string(substeps));
  if (integrator != "euler" && integrator != "rk4")
    throw Invalid_input("integrator: expected 'euler' or 'rk4', got '" + integrator + "'");
  if (audit_every < 0)
    throw Invalid_input("audit_every: must be >= 0 (0: never), got " + std::to_string(audit_every));
  if (!(own_basin_gap >= 0.0 && own_basin_gap < 1.0))
    throw Invalid_input("own_basin_gap: must be >= 0 and < 1, got " + number_text(own_basin_gap));
  if (threshold && !(std::isfinite(*threshold) && *threshold > 0.0))
    throw Invalid_input("threshold: must be finite and > 0 (None: every pair tracked)");
  scene.tracker.gain = gain;
  scene.tracker.substeps = substeps;
  scene.tracker.rk4 = integrator == "rk4";
  scene.tracker.audit_every = audit_every;
  scene.tracker.own_basin_gap = own_basin_gap;
  scene.threshold = threshold;
  return pair_options_of(scene);
}

// Marks the tracker in use for one call; a second thread's call raises.
struct Busy {
  explicit Busy(std::atomic<bool>& flag) : m_flag(flag) {
    if (m_flag.exchange(true))
      throw std::runtime_error(
          "this tracker is being stepped by another thread: a tracker is not shared between "
          "threads (give each thread its own)");
  }
  ~Busy() { m_flag.store(false); }
  std::atomic<bool>& m_flag;
};

// A tracker per watched pair of bodies, stepped with the bodies' poses and twists. Not for
// several threads at once: a call while another thread's call runs raises RuntimeError.
class Py_scene_tracker {
 public:
  Py_scene_tracker(std::vector<Body_ptr> bodies, std::vector<std::pair<int, int>> pairs,
                   const Body_pair_options& options)
      : m_bodies(std::move(bodies)), m_pairs(std::move(pairs)) {
    const int n = static_cast<int>(m_bodies.size());
    if (m_pairs.empty()) throw Invalid_input("pairs: no pair of bodies to watch");
    std::map<std::pair<int, int>, bool> seen;
    for (std::size_t k = 0; k < m_pairs.size(); ++k) {
      const auto [a, b] = m_pairs[k];
      const std::string which = "pairs[" + std::to_string(k) + "]";
      if (a < 0 || a >= n || b < 0 || b >= n)
        throw Invalid_input(which + ": body index out of range (" + std::to_string(n) + " bodies)");
      if (a == b) throw Invalid_input(which + ": a body cannot be paired with itself");
      if (seen[std::minmax(a, b)]) throw Invalid_input(which + ": the pair is listed twice");
      seen[std::minmax(a, b)] = true;
    }
    for (std::size_t i = 0; i < m_bodies.size(); ++i)
      if (m_bodies[i]->body().is_empty())
        throw Invalid_input("bodies[" + std::to_string(i) + "]: body '" + m_bodies[i]->body().name +
                            "' has no face, curve, point or triangle");
    py::gil_scoped_release release;
    m_trackers.reserve(m_pairs.size());
    for (const auto& [a, b] : m_pairs)
      m_trackers.emplace_back(m_bodies[a]->tracking_model(), m_bodies[b]->tracking_model(), options);
    m_entry.resize(m_bodies.size());
    m_entry_twists.resize(m_bodies.size());
    m_poses.resize(m_bodies.size());
    m_twists.resize(m_bodies.size());
  }

  std::size_t body_count() const { return m_bodies.size(); }
  const std::vector<std::pair<int, int>>& pairs() const { return m_pairs; }
  const std::vector<Body_ptr>& bodies() const { return m_bodies; }

  std::vector<Py_pair_report> step(double t, const py::handle& poses, const py::handle& twists,
                                   double dt) {
    // First: anything below may release the GIL (NumPy does), and another thread's call must
    // find the tracker taken by then.
    Busy busy(m_busy);
    check_time(t, dt);
    const std::size_t n = m_bodies.size();
    const auto p = double_array(poses, "poses");
    const bool three = p.ndim() == 2 && p.shape(1) == 3;
    if (p.ndim() != 2 || static_cast<std::size_t>(p.shape(0)) != n || (p.shape(1) != 7 && !three))
      throw Invalid_input("poses: expected one pose per body, shape (" + std::to_string(n) +
                          ", 7) or (" + std::to_string(n) + ", 3)");
    for (std::size_t i = 0; i < n; ++i) m_entry[i] = pose_row(p.data() + i * p.shape(1), three, i);
    read_twists(twists);
    return step_entries(t, dt);
  }

  // One step from poses and twists already made (one per body, the file frames').
  std::vector<Py_pair_report> step(double t, const Rigid_pose_3* poses, const Twist_3* twists,
                                   double dt) {
    check_time(t, dt);
    Busy busy(m_busy);
    for (std::size_t i = 0; i < m_bodies.size(); ++i) {
      m_entry[i] = poses[i];
      m_entry_twists[i] = twists[i];
    }
    return step_entries(t, dt);
  }

  // Many steps: times (m,), poses (m, n, 7 or 3), twists None or (m, n, 6); dt of the last step
  // `dt`, or the last interval.
  py::dict track(const py::handle& times_in, const py::handle& poses_in,
                 const py::handle& twists_in, std::optional<double> dt_last) {
    Busy busy(m_busy);  // first, as in step()
    const std::size_t n = m_bodies.size(), P = m_pairs.size();
    const auto times = double_array(times_in, "times");
    if (times.ndim() != 1 || times.size() < 1)
      throw Invalid_input("times: expected a 1-d array of at least one time");
    const std::size_t steps = static_cast<std::size_t>(times.size());
    if (steps == 1 && !dt_last) throw Invalid_input("dt: needed when times holds one time");
    const double* T = times.data();
    for (std::size_t i = 0; i < steps; ++i) {
      if (!std::isfinite(T[i])) throw Invalid_input("times[" + std::to_string(i) + "]: not finite");
      if (i > 0 && !(T[i] > T[i - 1]))
        throw Invalid_input("times[" + std::to_string(i) + "]: times must increase");
    }
    const double last_dt = dt_last ? *dt_last : T[steps - 1] - T[steps - 2];
    check_time(T[0], last_dt);
    const auto poses = double_array(poses_in, "poses");
    if (poses.ndim() != 3 || static_cast<std::size_t>(poses.shape(0)) != steps ||
        static_cast<std::size_t>(poses.shape(1)) != n || (poses.shape(2) != 7 && poses.shape(2) != 3))
      throw Invalid_input("poses: expected shape (" + std::to_string(steps) + ", " +
                          std::to_string(n) + ", 7) (or 3 numbers a pose), one per time and body");
    const bool three = poses.shape(2) == 3;
    py::array_t<double, py::array::c_style> twists;
    if (!twists_in.is_none()) {
      twists = double_array(twists_in, "twists");
      if (twists.ndim() != 3 || static_cast<std::size_t>(twists.shape(0)) != steps ||
          static_cast<std::size_t>(twists.shape(1)) != n || twists.shape(2) != 6)
        throw Invalid_input("twists: expected shape (" + std::to_string(steps) + ", " +
                            std::to_string(n) + ", 6), one per time and body, or None");
    }
    const double* Pd = poses.data();
    const double* Vd = twists_in.is_none() ? nullptr : twists.data();
    const std::size_t pose_size = three ? 3 : 7;

    std::vector<double> distance(steps * P), point_a(steps * P * 3), point_b(steps * P * 3),
        normal(steps * P * 3), params(steps * P * 4);
    std::vector<int> face_a(steps * P), face_b(steps * P);
    std::vector<std::int8_t> status(steps * P), degeneracy(steps * P);
    std::vector<bool> solved_flags(steps * P);
    {
      py::gil_scoped_release release;
      // Every value checked before the first step, so bad input leaves the trackers as they were.
      for (std::size_t i = 0; i < steps; ++i)
        for (std::size_t j = 0; j < n; ++j) {
          pose_row(Pd + (i * n + j) * pose_size, three, j, i);
          if (Vd)
            for (int c = 0; c < 6; ++c)
              if (!std::isfinite(Vd[(i * n + j) * 6 + c]))
                throw Invalid_input("twists[" + std::to_string(i) + "][" + std::to_string(j) +
                                    "]: not finite");
        }
      for (std::size_t i = 0; i < steps; ++i) {
        for (std::size_t j = 0; j < n; ++j) {
          m_entry[j] = pose_row(Pd + (i * n + j) * pose_size, three, j, i);
          if (Vd) {
            const double* v = Vd + (i * n + j) * 6;
            m_entry_twists[j].linear = Vec3(v[0], v[1], v[2]);
            m_entry_twists[j].angular = Vec3(v[3], v[4], v[5]);
          } else {
            m_entry_twists[j] = Twist_3();
          }
        }
        advance(T[i], i + 1 < steps ? T[i + 1] - T[i] : last_dt);
        for (std::size_t k = 0; k < P; ++k) {
          const Pair_report& r = *m_reports[k];
          const std::size_t at = i * P + k;
          distance[at] = r.distance;
          for (int c = 0; c < 3; ++c) {
            point_a[at * 3 + c] = r.point_a[c];
            point_b[at * 3 + c] = r.point_b[c];
            normal[at * 3 + c] = r.normal[c];
          }
          for (int c = 0; c < 4; ++c) params[at * 4 + c] = r.params[c];
          face_a[at] = r.feature_a;
          face_b[at] = r.feature_b;
          status[at] = static_cast<std::int8_t>(r.status);
          degeneracy[at] = static_cast<std::int8_t>(r.degeneracy);
          solved_flags[at] = r.solved;
        }
      }
    }
    const auto m = static_cast<py::ssize_t>(steps), pp = static_cast<py::ssize_t>(P);
    py::array_t<bool> solved({m, pp});
    for (std::size_t i = 0; i < steps * P; ++i) solved.mutable_data()[i] = solved_flags[i];
    py::dict out;
    out["time"] = py::array_t<double>(m, T);  // a copy
    out["distance"] = take_array(std::move(distance), {m, pp});
    out["point_a"] = take_array(std::move(point_a), {m, pp, 3});
    out["point_b"] = take_array(std::move(point_b), {m, pp, 3});
    out["normal"] = take_array(std::move(normal), {m, pp, 3});
    out["face_a"] = take_array(std::move(face_a), {m, pp});
    out["face_b"] = take_array(std::move(face_b), {m, pp});
    out["params"] = take_array(std::move(params), {m, pp, 4});
    out["status"] = names(status, {m, pp}, [](int c) { return to_string(static_cast<Pair_status>(c)); });
    out["degeneracy"] =
        names(degeneracy, {m, pp}, [](int c) { return to_string(static_cast<Degeneracy>(c)); });
    out["solved"] = solved;
    return out;
  }

 private:
  std::vector<Py_pair_report> step_entries(double t, double dt) {
    {
      py::gil_scoped_release release;
      advance(t, dt);
    }
    std::vector<Py_pair_report> out;
    out.reserve(m_pairs.size());
    for (std::size_t k = 0; k < m_pairs.size(); ++k) out.emplace_back(*m_reports[k]);
    return out;
  }

  static void check_time(double t, double dt) {
    if (!std::isfinite(t)) throw Invalid_input("t: not a finite time");
    if (!(std::isfinite(dt) && dt > 0.0)) {
      std::ostringstream os;
      os << "dt: must be finite and > 0, got " << dt;
      throw Invalid_input(os.str());
    }
  }

  // Pose j (at step i, for messages) from 7 numbers, or 3 (unturned).
  static Rigid_pose_3 pose_row(const double* p, bool three, std::size_t j, long i = -1) {
    const std::string which =
        "poses" + (i >= 0 ? "[" + std::to_string(i) + "]" : std::string()) + "[" + std::to_string(j) + "]";
    if (!three) return pose_from_numbers(p, which);
    const double full[7] = {p[0], p[1], p[2], 1.0, 0.0, 0.0, 0.0};
    return pose_from_numbers(full, which);
  }

  void read_twists(const py::handle& twists) {
    const std::size_t n = m_bodies.size();
    if (twists.is_none()) {
      for (auto& v : m_entry_twists) v = Twist_3();
      return;
    }
    const auto a = double_array(twists, "twists");
    if (a.ndim() != 2 || static_cast<std::size_t>(a.shape(0)) != n || a.shape(1) != 6)
      throw Invalid_input("twists: expected one twist per body, shape (" + std::to_string(n) +
                          ", 6), or None");
    for (std::size_t i = 0; i < n; ++i) {
      const double* v = a.data() + i * 6;
      for (int c = 0; c < 6; ++c)
        if (!std::isfinite(v[c]))
          throw Invalid_input("twists[" + std::to_string(i) + "][" + std::to_string(c) + "]: not finite");
      m_entry_twists[i].linear = Vec3(v[0], v[1], v[2]);
      m_entry_twists[i].angular = Vec3(v[3], v[4], v[5]);
    }
  }

  // One step from m_entry, m_entry_twists (the file frames); m_reports point at the results.
  void advance(double t, double dt) {
    for (std::size_t i = 0; i < m_bodies.size(); ++i)
      place_body(m_bodies[i]->body(), m_entry[i], m_entry_twists[i], m_poses[i], m_twists[i]);
    m_reports.resize(m_pairs.size());  // allocates on the first step only
    for (std::size_t k = 0; k < m_pairs.size(); ++k) {
      const auto [a, b] = m_pairs[k];
      m_reports[k] = &m_trackers[k].step(t, m_poses[a], m_twists[a], m_poses[b], m_twists[b], dt);
    }
  }

  template <class Name>
  static py::array names(const std::vector<std::int8_t>& codes, std::vector<py::ssize_t> shape,
                         Name name) {
    int top = 0;
    for (std::int8_t c : codes) top = std::max(top, static_cast<int>(c));
    py::list table;
    for (int c = 0; c <= top; ++c) table.append(name(c));
    const py::module_ np = py::module_::import("numpy");
    const py::array code_array = py::array_t<std::int8_t>(shape, codes.data());
    return np.attr("asarray")(table).attr("__getitem__")(code_array);
  }

  std::vector<Body_ptr> m_bodies;
  std::vector<std::pair<int, int>> m_pairs;
  std::vector<Body_pair_tracker> m_trackers;
  std::vector<Rigid_pose_3> m_entry, m_poses;
  std::vector<Twist_3> m_entry_twists, m_twists;
  std::vector<const Pair_report*> m_reports;
  std::atomic<bool> m_busy{false};
};

// The watched pairs of a SceneTracker: "all", or a list of (i, j) indices or (name, name).
std::vector<std::pair<int, int>> pairs_from(const py::handle& value, const std::vector<Body_ptr>& bodies) {
  std::vector<std::pair<int, int>> out;
  const int n = static_cast<int>(bodies.size());
  if (py::isinstance<py::str>(value)) {
    if (value.cast<std::string>() != "all")
      throw Invalid_input("pairs: expected \"all\" or a list of pairs");
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b) out.emplace_back(a, b);
    return out;
  }
  auto index = [&](const py::handle& x, const std::string& which) {
    if (py::isinstance<py::str>(x)) {
      const std::string name = x.cast<std::string>();
      int found = -1;
      for (int i = 0; i < n; ++i)
        if (bodies[static_cast<std::size_t>(i)]->body().name == name) {
          if (found >= 0) throw Invalid_input(which + ": two bodies are named '" + name + "'");
          found = i;
        }
      if (found < 0) throw Invalid_input(which + ": no body named '" + name + "'");
      return found;
    }
    try {
      return x.cast<int>();
    } catch (const py::cast_error&) {
      throw Invalid_input(which + ": expected a body index or name");
    }
  };
  if (!py::isinstance<py::sequence>(value)) throw Invalid_input("pairs: expected \"all\" or a list of pairs");
  const py::sequence s = value.cast<py::sequence>();
  for (std::size_t k = 0; k < s.size(); ++k) {
    const std::string which = "pairs[" + std::to_string(k) + "]";
    if (!py::isinstance<py::sequence>(s[k]) || py::isinstance<py::str>(s[k]) || py::len(s[k]) != 2)
      throw Invalid_input(which + ": expected (a, b)");
    const py::sequence ab = s[k].cast<py::sequence>();
    out.emplace_back(index(ab[0], which + "[0]"), index(ab[1], which + "[1]"));
  }
  return out;
}

std::vector<Body_ptr> body_list(const py::handle& value) {
  if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value))
    throw Invalid_input("bodies: expected a list of extremal.Body");
  const py::sequence s = value.cast<py::sequence>();
  std::vector<Body_ptr> out;
  for (std::size_t i = 0; i < s.size(); ++i) out.push_back(one_body(s[i], "bodies[" + std::to_string(i) + "]"));
  if (out.size() < 2) throw Invalid_input("bodies: a scene needs at least two bodies");
  return out;
}

// Two bodies: the common case, with poses and twists given one by one.
class Py_pair_tracker {
 public:
  Py_pair_tracker(const Body_ptr& a, const Body_ptr& b, const Body_pair_options& options)
      : m_scene({a, b}, {{0, 1}}, options) {}

  Py_pair_report step(double t, const py::handle& pose_a, const py::handle& twist_a,
                      const py::handle& pose_b, const py::handle& twist_b, double dt) {
    Busy busy(m_busy);
    const Rigid_pose_3 X[2] = {pose_from(pose_a, "pose_a"), pose_from(pose_b, "pose_b")};
    const Twist_3 V[2] = {twist_from(twist_a, "twist_a"), twist_from(twist_b, "twist_b")};
    return m_scene.step(t, X, V, dt).front();
  }

  py::dict track(const py::handle& times, const py::handle& poses_a, const py::handle& poses_b,
                 const py::handle& twists_a, const py::handle& twists_b, std::optional<double> dt) {
    Busy busy(m_busy);
    const py::module_ np = py::module_::import("numpy");
    // Each (m, 7), or (m, 3) made (m, 7) unturned.
    auto full = [&](const py::handle& value, const char* argument) -> py::object {
      const auto p = double_array(value, argument);
      if (p.ndim() != 2 || (p.shape(1) != 7 && p.shape(1) != 3))
        throw Invalid_input(std::string(argument) + ": expected shape (m, 7) or (m, 3), one pose per time");
      if (p.shape(1) == 7) return p;
      const py::object unturned = np.attr("tile")(py::make_tuple(1.0, 0.0, 0.0, 0.0),
                                                  py::make_tuple(p.shape(0), 1));
      return np.attr("hstack")(py::make_tuple(p, unturned));
    };
    const py::object pa = full(poses_a, "poses_a"), pb = full(poses_b, "poses_b");
    if (!pa.attr("shape").equal(pb.attr("shape")))
      throw Invalid_input("poses_a, poses_b: one pose per time each, got " +
                          std::string(py::str(pa.attr("shape"))) + " and " +
                          std::string(py::str(pb.attr("shape"))));
    const py::object poses = np.attr("stack")(py::make_tuple(pa, pb), 1);
    const long m = pa.attr("shape").cast<py::tuple>()[0].cast<long>();
    py::object twists = py::none();
    if (!twists_a.is_none() || !twists_b.is_none()) {
      const py::object zero = np.attr("zeros")(py::make_tuple(m, 6));
      const py::object ta = twists_a.is_none() ? zero : py::object(double_array(twists_a, "twists_a"));
      const py::object tb = twists_b.is_none() ? zero : py::object(double_array(twists_b, "twists_b"));
      if (py::len(ta.attr("shape")) != 2 || ta.attr("shape").cast<py::tuple>()[0].cast<long>() != m ||
          !ta.attr("shape").equal(tb.attr("shape")))
        throw Invalid_input("twists_a, twists_b: expected arrays of shape (m, 6), one per time, or None");
      twists = np.attr("stack")(py::make_tuple(ta, tb), 1);
    }
    const py::dict all = m_scene.track(times, poses, twists, dt);
    // One pair: (m,) and (m, 3) columns rather than (m, 1) and (m, 1, 3).
    py::dict out;
    for (auto item : all)
      out[item.first] = item.first.cast<std::string>() == "time"
                            ? py::reinterpret_borrow<py::object>(item.second)
                            : item.second.attr("__getitem__")(py::make_tuple(
                                  py::slice(py::none(), py::none(), py::none()), 0));
    return out;
  }

  const Py_scene_tracker& scene() const { return m_scene; }

 private:
  Py_scene_tracker m_scene;
  std::atomic<bool> m_busy{false};  // this tracker's calls (m_scene has its own)
};

const char* const k_options_doc = R"doc(
Options, as a scene file's "tracker" object and "threshold" (and mapped onto the trackers exactly
as `extremal report` maps a scene's): gain (1/s; 0: 1/dt), substeps, integrator ('euler' or
'rk4'), audit_every (steps between audits by the certified global solver; 0: never),
own_basin_gap (0 to 1, default 0.001; 0: a tracked pair's second basin is not watched),
threshold (None: every pair tracked; else pairs whose boxes are farther apart are 'farther',
their distance a lower bound).
)doc";

}  // namespace

void bind_tracker(py::module_& m) {
  py::class_<Py_pair_report>(m, "PairReport", R"doc(
One watched pair at one time: the signed extremal distance (positive apart, 0 at contact,
negative inside: the local penetration depth), the witnesses point_a, point_b (world), the unit
normal from A to B (point_b - point_a = distance * normal), the faces face_a, face_b, the
pair's parameters (ua, va, ub, vb), status ('tracking', 'contact', 'penetrating', 'boundary',
'farther', 'fallback'), degeneracy (why a step fell back: '' when it did not, else 'pole', 'parallel',
'coincident', 'singular') and
solved (no tracker held the pair at this step: the certified solver's answer).
)doc")
      .def_readonly("time", &Py_pair_report::time)
      .def_readonly("distance", &Py_pair_report::distance)
      .def_property_readonly("point_a", [](const Py_pair_report& r) { return vec_array(r.point_a); })
      .def_property_readonly("point_b", [](const Py_pair_report& r) { return vec_array(r.point_b); })
      .def_property_readonly("normal", [](const Py_pair_report& r) { return vec_array(r.normal); })
      .def_readonly("face_a", &Py_pair_report::face_a)
      .def_readonly("face_b", &Py_pair_report::face_b)
      .def_property_readonly("params", [](const Py_pair_report& r) {
        py::array_t<double> a(4);
        for (int c = 0; c < 4; ++c) a.mutable_data()[c] = r.params[c];
        return a;
      })
      .def_property_readonly("status", [](const Py_pair_report& r) { return std::string(to_string(r.status)); })
      .def_property_readonly("degeneracy",
                             [](const Py_pair_report& r) { return std::string(to_string(r.degeneracy)); })
      .def_readonly("solved", &Py_pair_report::solved)
      .def("__repr__", [](const Py_pair_report& r) {
        std::ostringstream os;
        os.precision(17);
        os << "<extremal.PairReport t=" << r.time << " distance=" << r.distance << " "
           << to_string(r.status) << ">";
        return os.str();
      });

  py::class_<Py_pair_tracker>(m, "Tracker",
                              (std::string(R"doc(
Tracker(a, b, *, gain=0, substeps=1, integrator='euler', audit_every=0, own_basin_gap=1e-3,
        threshold=None)

Keeps the extremal pair of bodies a and b (each a Body, or a Model of one body) up to date
while they move: start from the certified global pair, then a fraction of a microsecond per
step for a pair of patches (docs/behaviour.md says what it reports when). Poses place each body's file frame in the world (x, y, z, qw, qx, qy, qz,
or x, y, z); twists are that frame's world velocity (vx, vy, vz, wx, wy, wz: the linear velocity
of its origin and the angular velocity), None at rest. step() reports at t, then advances the
tracker over [t, t + dt] with the twists: the poses of the next call are where the bodies are.

A tracker is not shared between threads: give each thread its own (a call from a second thread
while one runs raises RuntimeError). Its calls release the GIL, so trackers in several threads
step at once.
)doc") + k_options_doc).c_str())
      .def(py::init([](const py::object& a, const py::object& b, double gain, int substeps,
                       const std::string& integrator, int audit_every, double own_basin_gap,
                       std::optional<double> threshold) {
             return std::make_unique<Py_pair_tracker>(
                 one_body(a, "a"), one_body(b, "b"),
                 pair_options(gain, substeps, integrator, audit_every, own_basin_gap, threshold));
           }),
           py::arg("a"), py::arg("b"), py::kw_only(), py::arg("gain") = 0.0,
           py::arg("substeps") = 1, py::arg("integrator") = "euler", py::arg("audit_every") = 0,
           py::arg("own_basin_gap") = 1e-3, py::arg("threshold") = py::none())
      .def("step", &Py_pair_tracker::step, py::arg("t"), py::arg("pose_a"), py::arg("twist_a"),
           py::arg("pose_b"), py::arg("twist_b"), py::arg("dt"),
           "The pair at time t (a PairReport), then the tracker advances over [t, t + dt].")
      .def("track", &Py_pair_tracker::track, py::arg("times"), py::arg("poses_a"),
           py::arg("poses_b"), py::arg("twists_a") = py::none(), py::arg("twists_b") = py::none(),
           py::arg("dt") = py::none(), R"doc(
Many steps in one call (the GIL released throughout): times (m,) increasing, poses_a, poses_b
(m, 7) or (m, 3), twists_a, twists_b (m, 6) or None (at rest). The last step advances by dt, by
default the last interval (needed when m is 1). Returns a dict of NumPy arrays: time (m,),
distance (m,), point_a, point_b, normal (m, 3), face_a, face_b (m,), params (m, 4), status and
degeneracy (m,) of str, solved (m,) of bool. Every value is checked before the first step.
)doc")
      .def_property_readonly("bodies", [](const Py_pair_tracker& t) { return t.scene().bodies(); });

  py::class_<Py_scene_tracker>(m, "SceneTracker",
                               (std::string(R"doc(
SceneTracker(bodies, pairs='all', *, gain=0, substeps=1, integrator='euler', audit_every=0,
             own_basin_gap=1e-3, threshold=None)

A Tracker per watched pair of a list of bodies, each body's tracking model shared by its pairs.
pairs: 'all', or a list of (i, j) body indices or (name, name). step(t, poses, twists, dt) takes one pose
per body (n, 7) and one twist per body (n, 6) or None (all at rest), and returns a PairReport per pair in the order
of `pairs`. Not shared between threads (as Tracker).
)doc") + k_options_doc).c_str())
      .def(py::init([](const py::object& bodies, const py::object& pairs, double gain, int substeps,
                       const std::string& integrator, int audit_every, double own_basin_gap,
                       std::optional<double> threshold) {
             const std::vector<Body_ptr> list = body_list(bodies);
             return std::make_unique<Py_scene_tracker>(
                 list, pairs_from(pairs, list),
                 pair_options(gain, substeps, integrator, audit_every, own_basin_gap, threshold));
           }),
           py::arg("bodies"), py::arg("pairs") = "all", py::kw_only(), py::arg("gain") = 0.0,
           py::arg("substeps") = 1, py::arg("integrator") = "euler", py::arg("audit_every") = 0,
           py::arg("own_basin_gap") = 1e-3, py::arg("threshold") = py::none())
      .def("step",
           static_cast<std::vector<Py_pair_report> (Py_scene_tracker::*)(
               double, const py::handle&, const py::handle&, double)>(&Py_scene_tracker::step),
           py::arg("t"), py::arg("poses"), py::arg("twists"), py::arg("dt"),
           "The watched pairs at time t (a list of PairReport), then the trackers advance over "
           "[t, t + dt].")
      .def("track", &Py_scene_tracker::track, py::arg("times"), py::arg("poses"),
           py::arg("twists") = py::none(), py::arg("dt") = py::none(), R"doc(
Many steps in one call (the GIL released throughout): times (m,), poses (m, n, 7) or (m, n, 3),
twists (m, n, 6) or None. Returns a dict of NumPy arrays with a pair axis after the time axis:
time (m,), distance (m, p), point_a, point_b, normal (m, p, 3), face_a, face_b (m, p), params
(m, p, 4), status, degeneracy (m, p) of str, solved (m, p).
)doc")
      .def_property_readonly("pairs", &Py_scene_tracker::pairs)
      .def_property_readonly("bodies", &Py_scene_tracker::bodies);
}

}  // namespace extremal::python
