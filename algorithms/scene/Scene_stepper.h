// The one scene runner: steps the watched body pairs of a scene of moving bodies through time
// and reports the extremal distance of each pair at every step. Used by `extremal report`, the
// Python module and the benchmarks alike:
//   - each watched body is prepared once (its Tracking_model, read only, shared by its pairs)
//     and placed once a step (a static body once);
//   - each pair has its own Body_pair_tracker, whose pose gate keeps a pair's answer while its
//     relative pose is bit for bit the one the answer was made at (a pair of two static
//     bodies is computed once);
//   - run() steps the pairs in blocks of steps, the pairs of a block in parallel (TBB), each
//     pair through the block's steps in turn (its state stays in cache), and hands the rows
//     over in order, step by step; the rows are the same on any number of threads;
//   - each pair's step is timed (its tracker's step only), with the time its audits took
//     apart.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/body_pair/Tracking_model.h"
#include "kernel/Body.h"
#include "kernel/Motion.h"

namespace extremal {

struct Scene_stepper_body {
  const Body* body;      // must outlive the stepper
  const Motion* motion;  // must outlive the stepper; the body sits at motion * body->placement
  std::string name = {};  // in error messages (empty: "body K")
};

// Body `b`'s frame at time t: its motion's pose times its placement in its file, and its twist
// with the linear part the velocity of that frame's origin.
void body_pose_at(const Scene_stepper_body& b, double t, Rigid_pose_3& pose, Twist_3& twist);

struct Scene_stepper_options {
  // Worker threads stepping the watched pairs (TBB); 1 steps them in this thread. Every pair
  // is stepped by one thread with its own state, so the reports are bit-identical to one
  // thread's whatever the count.
  int threads = 1;
  // run(): the steps each pair runs before the block's rows are handed over.
  int block_steps = 512;
  // Prefixed to error messages (a scene file's path); empty: none.
  std::string source = {};
};

// Called once per time step, in order: the step's index, its time, and one report per pair (in
// the order of the stepper's pairs).
using Scene_step_callback =
    std::function<void(int step, double t, const std::vector<Pair_report>& reports)>;

class Scene_stepper {
 public:
  // Bodies may be NURBS (imported or generated), points or meshes. Throws Invalid_input naming
  // the source, the pair and the body when a pair cannot be tracked, and
  // Precondition_violation for a bad pair, thread count or block size.
  Scene_stepper(std::vector<Scene_stepper_body> bodies, std::vector<std::pair<int, int>> pairs,
                const Body_pair_options& options, const Scene_stepper_options& stepper = {});
  ~Scene_stepper();

  // The reports of all watched pairs at time t, then the trackers advance over [t, t + dt].
  const std::vector<Pair_report>& step(double t, double dt);

  // Steps 0 .. count - 1 at times time_of(i), each advancing over dt, in blocks; calls
  // on_step for each step in order. Records the step times (step_times_us).
  void run(int count, const std::function<double(int)>& time_of, double dt,
           const Scene_step_callback& on_step);

  const std::vector<std::pair<int, int>>& pairs() const { return m_pairs; }
  // The work pair k's tracker has done since its start.
  const Pair_statistics& statistics(std::size_t k) const { return m_trackers[k].statistics(); }
  // After run(): step_times_us()[k][i], the wall time of pair k's step i in microseconds,
  // measured (steady_clock) around that pair's tracker step only, less its audits (the global
  // solves of Body_pair_options::audit_every), which audit_times_us()[k][i] holds.
  const std::vector<std::vector<float>>& step_times_us() const { return m_step_times_us; }
  const std::vector<std::vector<float>>& audit_times_us() const { return m_audit_times_us; }
  // Threads used by step() and run() (>= 1).
  void set_threads(int threads);
  int threads() const { return m_options.threads; }

 private:
  // Pair k's reports at the block's steps [first, first + count) into m_block[k].
  void run_pair(std::size_t k, int first, int count, const std::function<double(int)>& time_of,
                double dt, bool timed);
  // The watched bodies' poses and twists at the block's steps.
  void place_bodies(int first, int count, const std::function<double(int)>& time_of);
  // Runs f(k) for every pair, on the stepper's threads.
  template <class F>
  void for_each_pair(F f);
  // An Invalid_input of pair k's, with the source and the pair's bodies named.
  [[noreturn]] void rethrow_for_pair(std::size_t k, const std::exception& e) const;

  std::vector<Scene_stepper_body> m_bodies;
  std::vector<std::pair<int, int>> m_pairs;
  Scene_stepper_options m_options;
  std::vector<std::shared_ptr<const Tracking_model>> m_models;  // per body, built if watched
  std::vector<Body_pair_tracker> m_trackers;
  bool m_placed = false;  // static bodies placed (their poses hold for every later step)
  // The block's reports [pair][step] and the bodies' poses and twists [step][body].
  std::vector<std::vector<Pair_report>> m_block;
  std::vector<std::vector<Rigid_pose_3>> m_poses;
  std::vector<std::vector<Twist_3>> m_twists;
  std::vector<Pair_report> m_reports;  // one step's, in pair order
  std::vector<std::vector<float>> m_step_times_us, m_audit_times_us;
  struct Parallel;  // the TBB arena
  std::unique_ptr<Parallel> m_parallel;
};

}  // namespace extremal
