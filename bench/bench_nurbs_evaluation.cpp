// Cost of one surface evaluation: point plus all second derivatives (order 2) and point only
// (order 0), for (a) a bicubic polynomial 4 x 4 Bezier patch, (b) the rational ellipsoid
// make_ellipsoid(3, 2, 1.5), (c) a degree 12 polynomial 13 x 13 patch, and (d) the same
// degree 12 patch made rational. Parameters come from a precomputed table of random (u, v), so
// no call sees constant arguments. Target for (a) at order 2: at most 150 ns per call.
//
//   bench_nurbs_evaluation --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cstddef>
#include <random>
#include <vector>

#include "kernel/Nurbs_surface_3.h"
#include "kernel/Shapes.h"

namespace {

using extremal::Nurbs_surface_3;
using extremal::Point_3;
using extremal::Surface_point;

constexpr std::size_t k_table = 1024;  // power of two: the index wraps with a mask

std::vector<Point_3> random_poles(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  std::vector<Point_3> poles;
  for (int k = 0; k < count; ++k) poles.emplace_back(d(rng), d(rng), d(rng));
  return poles;
}

std::vector<double> random_weights(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> d(0.2, 5.0);
  std::vector<double> w;
  for (int k = 0; k < count; ++k) w.push_back(d(rng));
  return w;
}

const Nurbs_surface_3& bicubic() {
  static const Nurbs_surface_3 s = [] {
    std::mt19937_64 rng(1);
    return extremal::make_freeform(3, 3, 4, 4, random_poles(rng, 16));
  }();
  return s;
}

const Nurbs_surface_3& ellipsoid() {
  static const Nurbs_surface_3 s = extremal::make_ellipsoid(3, 2, 1.5);
  return s;
}

const Nurbs_surface_3& degree12() {
  static const Nurbs_surface_3 s = [] {
    std::mt19937_64 rng(2);
    return extremal::make_freeform(12, 12, 13, 13, random_poles(rng, 169));
  }();
  return s;
}

const Nurbs_surface_3& degree12_rational() {
  static const Nurbs_surface_3 s = [] {
    std::mt19937_64 rng(3);
    auto poles = random_poles(rng, 169);
    return extremal::make_freeform(12, 12, 13, 13, std::move(poles), random_weights(rng, 169));
  }();
  return s;
}

struct Parameter_table {
  std::vector<double> u, v;
};

Parameter_table make_table(const Nurbs_surface_3& s) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> du(s.u_min(), s.u_max()), dv(s.v_min(), s.v_max());
  Parameter_table t;
  for (std::size_t i = 0; i < k_table; ++i) {
    t.u.push_back(du(rng));
    t.v.push_back(dv(rng));
  }
  return t;
}

void run(benchmark::State& state, const Nurbs_surface_3& s) {
  const int order = static_cast<int>(state.range(0));
  const Parameter_table t = make_table(s);
  Surface_point sp;
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ & (k_table - 1);
    s.evaluate(t.u[k], t.v[k], sp, order);
    benchmark::DoNotOptimize(sp);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_bicubic_polynomial(benchmark::State& state) { run(state, bicubic()); }
void BM_ellipsoid_rational(benchmark::State& state) { run(state, ellipsoid()); }
void BM_degree12_polynomial(benchmark::State& state) { run(state, degree12()); }
void BM_degree12_rational(benchmark::State& state) { run(state, degree12_rational()); }

}  // namespace

BENCHMARK(BM_bicubic_polynomial)->ArgName("order")->Arg(2)->Arg(0);
BENCHMARK(BM_ellipsoid_rational)->ArgName("order")->Arg(2)->Arg(0);
BENCHMARK(BM_degree12_polynomial)->ArgName("order")->Arg(2)->Arg(0);
BENCHMARK(BM_degree12_rational)->ArgName("order")->Arg(2)->Arg(0);

BENCHMARK_MAIN();
