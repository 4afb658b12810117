// Knot insertion, Bezier extraction and splitting leave curves and surfaces unchanged (same
// points, same parametrisation); hull boxes contain the geometry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernel/Error.h"
#include "kernel/internal/Knot_vector.h"
#include "kernel/Nurbs_refinement.h"
#include "kernel/Shapes.h"
#include "tests/support/Nurbs_test_support.h"

namespace extremal {
namespace {

using namespace extremal::test;

std::vector<Point_3> random_poles(std::mt19937_64& rng, int count) {
  std::vector<Point_3> poles;
  for (int k = 0; k < count; ++k) poles.push_back(to_point(random_vec3(rng)));
  return poles;
}
std::vector<double> random_weights(std::mt19937_64& rng, int count) {
  std::vector<double> w;
  for (int k = 0; k < count; ++k) w.push_back(std::exp(uniform(rng, std::log(0.2), std::log(5.0))));
  return w;
}

double reach(const Bbox_3& b) {
  return std::max({std::abs(b.xmin()), std::abs(b.xmax()), std::abs(b.ymin()), std::abs(b.ymax()),
                   std::abs(b.zmin()), std::abs(b.zmax())});
}

// Distinct knot values inside [lo, hi], ends included.
std::vector<double> breakpoints(const std::vector<double>& knots, int n, int p) {
  std::vector<double> b;
  for (int i = p; i <= n; ++i)
    if (b.empty() || knots[i] != b.back()) b.push_back(knots[i]);
  return b;
}

// Parameters in [lo, hi]: a uniform grid, the ends and the given knots, and points beside them.
std::vector<double> samples_in(double lo, double hi, int grid, const std::vector<double>& knots) {
  std::vector<double> t;
  for (int i = 0; i <= grid; ++i) t.push_back(lo + (hi - lo) * i / grid);
  t.back() = hi;
  for (double k : knots) {
    t.push_back(k);
    t.push_back(std::nextafter(k, lo));
    t.push_back(std::nextafter(k, hi));
    t.push_back(k - 1e-9 * (hi - lo));
    t.push_back(k + 1e-9 * (hi - lo));
  }
  t.erase(std::remove_if(t.begin(), t.end(), [&](double x) { return !(x >= lo && x <= hi); }),
          t.end());
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  return t;
}

// At a knot, evaluation takes the span on the right (the last span at the domain end). A piece
// ending at a knot of the original therefore evaluates the left limit there while the original
// evaluates the right one, and derivatives above the continuity at that knot differ: compare
// only points there.
bool one_sided_at(double x, double got_max, double want_max, const std::vector<double>& want_knots) {
  return x == got_max && x < want_max &&
         std::find(want_knots.begin(), want_knots.end(), x) != want_knots.end();
}

// `got` equals `want` on [ulo, uhi] x [vlo, vhi]: points to 1e-14 of the size (the relative
// accuracy issue 2 asks for), derivatives to 1e-12 relative plus a rounding bound. `got` is evaluated in its
// own domain, which must contain the box.
void expect_same_surface(const Nurbs_surface_3& got, const Nurbs_surface_3& want, double ulo,
                         double uhi, double vlo, double vhi, int grid) {
  ASSERT_LE(got.u_min(), ulo);
  ASSERT_GE(got.u_max(), uhi);
  ASSERT_LE(got.v_min(), vlo);
  ASSERT_GE(got.v_max(), vhi);
  const double size = bbox_size(want.hull_bbox()) + reach(want.hull_bbox());
  // Rounding in a k-th derivative grows like size (degree / shortest span)^k, in either form.
  const double gu = got.degree_u() / std::min(min_span(got.knots_u(), got.number_of_poles_u(),
                                                       got.degree_u()),
                                              min_span(want.knots_u(), want.number_of_poles_u(),
                                                       want.degree_u()));
  const double gv = got.degree_v() / std::min(min_span(got.knots_v(), got.number_of_poles_v(),
                                                       got.degree_v()),
                                              min_span(want.knots_v(), want.number_of_poles_v(),
                                                       want.degree_v()));
  const auto us = samples_in(ulo, uhi, grid, want.knots_u());
  const auto vs = samples_in(vlo, vhi, grid, want.knots_v());
  Surface_point a, b;
  for (double u : us)
    for (double v : vs) {
      got.evaluate(u, v, a, 2);
      want.evaluate(u, v, b, 2);
      ASSERT_LE((a.p - b.p).norm(), 1e-14 * size)
          << "u = " << u << ", v = " << v << ": " << a.p.transpose() << " vs " << b.p.transpose();
      if (one_sided_at(u, got.u_max(), want.u_max(), want.knots_u()) ||
          one_sided_at(v, got.v_max(), want.v_max(), want.knots_v()))
        continue;
      const Vec3* ga[5] = {&a.du, &a.dv, &a.duu, &a.duv, &a.dvv};
      const Vec3* gb[5] = {&b.du, &b.dv, &b.duu, &b.duv, &b.dvv};
      const double scale[5] = {size * gu, size * gv, size * gu * gu, size * gu * gv,
                               size * gv * gv};
      for (int d = 0; d < 5; ++d)
        ASSERT_LE((*ga[d] - *gb[d]).norm(), 1e-12 * gb[d]->norm() + 1e-13 * scale[d])
            << "derivative " << d << " at u = " << u << ", v = " << v << ": "
            << ga[d]->transpose() << " vs " << gb[d]->transpose();
    }
}

void expect_same_curve(const Nurbs_curve_3& got, const Nurbs_curve_3& want, double lo, double hi,
                       int grid) {
  ASSERT_LE(got.domain_min(), lo);
  ASSERT_GE(got.domain_max(), hi);
  const double size = bbox_size(want.hull_bbox()) + reach(want.hull_bbox());
  const double g = got.degree() / std::min(min_span(got.knots(), got.number_of_poles(), got.degree()),
                                           min_span(want.knots(), want.number_of_poles(),
                                                    want.degree()));
  Curve_point a, b;
  for (double t : samples_in(lo, hi, grid, want.knots())) {
    got.evaluate(t, a, 2);
    want.evaluate(t, b, 2);
    ASSERT_LE((a.p - b.p).norm(), 1e-14 * size)
        << "t = " << t << ": " << a.p.transpose() << " vs " << b.p.transpose();
    if (one_sided_at(t, got.domain_max(), want.domain_max(), want.knots())) continue;
    ASSERT_LE((a.d1 - b.d1).norm(), 1e-12 * b.d1.norm() + 1e-13 * size * g) << "d1 at t = " << t;
    ASSERT_LE((a.d2 - b.d2).norm(), 1e-12 * b.d2.norm() + 1e-13 * size * g * g)
        << "d2 at t = " << t;
  }
}

// Every sample of s lies in its hull box (to a few ulps of its coordinates).
void expect_hull_contains(const Nurbs_surface_3& s, int grid) {
  const Bbox_3 box = s.hull_bbox();
  const double slack = 4 * k_eps * reach(box);
  Surface_point sp;
  for (double u : samples_in(s.u_min(), s.u_max(), grid, s.knots_u()))
    for (double v : samples_in(s.v_min(), s.v_max(), grid, s.knots_v())) {
      s.evaluate(u, v, sp, 0);
      ASSERT_TRUE(box_contains(box, sp.p, slack))
          << "u = " << u << ", v = " << v << ": " << sp.p.transpose() << " outside " << box;
    }
}

void expect_hull_contains(const Nurbs_curve_3& c, int grid) {
  const Bbox_3 box = c.hull_bbox();
  const double slack = 4 * k_eps * reach(box);
  Curve_point cp;
  for (double t : samples_in(c.domain_min(), c.domain_max(), grid, c.knots())) {
    c.evaluate(t, cp, 0);
    ASSERT_TRUE(box_contains(box, cp.p, slack)) << "t = " << t << ": " << cp.p.transpose();
  }
}

bool box_inside(const Bbox_3& inner, const Bbox_3& outer, double slack) {
  return inner.xmin() >= outer.xmin() - slack && inner.xmax() <= outer.xmax() + slack &&
         inner.ymin() >= outer.ymin() - slack && inner.ymax() <= outer.ymax() + slack &&
         inner.zmin() >= outer.zmin() - slack && inner.zmax() <= outer.zmax() + slack;
}

// The knot vector after inserting t `times` times.
std::vector<double> with_knot(std::vector<double> knots, double t, int times) {
  knots.insert(std::upper_bound(knots.begin(), knots.end(), t), times, t);
  return knots;
}

enum class Kind { Clamped, Unclamped };

Nurbs_curve_3 random_curve(std::mt19937_64& rng, int p, int n, Kind kind) {
  const auto knots = kind == Kind::Clamped ? random_clamped_knots(rng, p, n, -1.0, 2.0, 0.3)
                                           : random_unclamped_knots(rng, p, n, 0.5, 0.4, 0.2);
  return Nurbs_curve_3(p, random_poles(rng, n), knots, random_weights(rng, n));
}

Nurbs_surface_3 random_surface(std::mt19937_64& rng, int p, int q, int nu, int nv, Kind ku,
                               Kind kv) {
  const auto knots_u = ku == Kind::Clamped ? random_clamped_knots(rng, p, nu, 0.0, 1.0, 0.3)
                                           : random_unclamped_knots(rng, p, nu, -2.0, 0.5, 0.2);
  const auto knots_v = kv == Kind::Clamped ? random_clamped_knots(rng, q, nv, 3.0, 4.0, 0.3)
                                           : random_unclamped_knots(rng, q, nv, 1.0, 0.3, 0.2);
  return Nurbs_surface_3(p, q, nu, nv, random_poles(rng, nu * nv), knots_u, knots_v,
                         random_weights(rng, nu * nv));
}

// ---------------------------------------------------------------------------------------------
// Knot insertion.

TEST(InsertKnot, CurveUnchangedAtRandomParametersAndExistingKnots) {
  EXTREMAL_SEEDED_RNG(rng);
  for (Kind kind : {Kind::Clamped, Kind::Unclamped})
    for (int p = 1; p <= 12; ++p) {
      SCOPED_TRACE(::testing::Message() << (kind == Kind::Clamped ? "clamped" : "unclamped")
                                        << ", degree " << p);
      const Nurbs_curve_3 c = random_curve(rng, p, p + 1 + uniform_int(rng, 0, 5), kind);
      const double lo = c.domain_min(), hi = c.domain_max();
      // A fresh parameter, and an existing interior knot when there is one.
      std::vector<double> ts = {uniform(rng, lo, hi)};
      for (int i = p + 1; i < c.number_of_poles(); ++i)
        if (c.knots()[i] > lo && c.knots()[i] < hi) ts.push_back(c.knots()[i]);
      for (double t : ts) {
        const int s = internal::knot_multiplicity(c.knots(), t);
        for (int times = 1; s + times <= p; ++times) {
          SCOPED_TRACE(::testing::Message() << "t = " << t << " inserted " << times << " times");
          const Nurbs_curve_3 r = insert_knot(c, t, times);
          EXPECT_EQ(r.number_of_poles(), c.number_of_poles() + times);
          EXPECT_EQ(r.knots(), with_knot(c.knots(), t, times));
          EXPECT_EQ(r.domain_min(), lo);
          EXPECT_EQ(r.domain_max(), hi);
          expect_same_curve(r, c, lo, hi, 200);
          expect_hull_contains(r, 50);
          // Refinement pulls the control polygon towards the curve: the hull does not grow.
          EXPECT_TRUE(box_inside(r.hull_bbox(), c.hull_bbox(), 4 * k_eps * reach(c.hull_bbox())));
          if (HasFailure()) return;
        }
      }
    }
}

TEST(InsertKnot, SurfaceUnchangedInBothDirections) {
  EXTREMAL_SEEDED_RNG(rng);
  for (Kind kind : {Kind::Clamped, Kind::Unclamped})
    for (auto [p, q] : {std::pair{1, 1}, {2, 2}, {3, 2}, {2, 5}, {12, 3}}) {
      SCOPED_TRACE(::testing::Message() << (kind == Kind::Clamped ? "clamped" : "unclamped")
                                        << ", degrees " << p << " x " << q);
      const int nu = p + 1 + uniform_int(rng, 0, 4), nv = q + 1 + uniform_int(rng, 0, 4);
      const Nurbs_surface_3 s = random_surface(rng, p, q, nu, nv, kind, kind);
      for (Parameter_direction dir : {Parameter_direction::U, Parameter_direction::V}) {
        const bool in_u = dir == Parameter_direction::U;
        const int deg = in_u ? p : q;
        const double t = in_u ? uniform(rng, s.u_min(), s.u_max()) : uniform(rng, s.v_min(), s.v_max());
        for (int times = 1; times <= deg; ++times) {
          SCOPED_TRACE(::testing::Message() << (in_u ? "u" : "v") << " = " << t << " inserted "
                                            << times << " times");
          const Nurbs_surface_3 r = insert_knot(s, dir, t, times);
          EXPECT_EQ(r.number_of_poles_u(), nu + (in_u ? times : 0));
          EXPECT_EQ(r.number_of_poles_v(), nv + (in_u ? 0 : times));
          EXPECT_EQ(r.knots_u(), in_u ? with_knot(s.knots_u(), t, times) : s.knots_u());
          EXPECT_EQ(r.knots_v(), in_u ? s.knots_v() : with_knot(s.knots_v(), t, times));
          expect_same_surface(r, s, s.u_min(), s.u_max(), s.v_min(), s.v_max(), 30);
          expect_hull_contains(r, 20);
          EXPECT_TRUE(box_inside(r.hull_bbox(), s.hull_bbox(), 4 * k_eps * reach(s.hull_bbox())));
          if (HasFailure()) return;
        }
      }
    }
}

TEST(InsertKnot, AtTheDomainEndsOfUnclampedKnotVectors) {
  EXTREMAL_SEEDED_RNG(rng);
  // Uniform unclamped knots (multiplicity 1 at the ends) and random ones; insertion up to full
  // multiplicity p + 1 at an end, which clamps that end.
  for (int p = 1; p <= 6; ++p) {
    const int n = p + 1 + uniform_int(rng, 0, 4);
    for (bool uniform_knots : {true, false}) {
      const auto knots = uniform_knots ? uniform_unclamped_knots(p, n, -1.0, 0.5)
                                       : random_unclamped_knots(rng, p, n, 0.0, 0.3, 0.3);
      const Nurbs_curve_3 c(p, random_poles(rng, n), knots, random_weights(rng, n));
      for (double t : {c.domain_min(), c.domain_max()}) {
        const int s = internal::knot_multiplicity(c.knots(), t);
        for (int times = 1; s + times <= p + 1; ++times) {
          SCOPED_TRACE(::testing::Message() << "degree " << p << ", knots "
                                            << ::testing::PrintToString(knots) << ", end " << t
                                            << " inserted " << times << " times");
          const Nurbs_curve_3 r = insert_knot(c, t, times);
          EXPECT_EQ(r.knots(), with_knot(c.knots(), t, times));
          EXPECT_EQ(r.domain_min(), c.domain_min());
          EXPECT_EQ(r.domain_max(), c.domain_max());
          expect_same_curve(r, c, c.domain_min(), c.domain_max(), 100);
          if (s + times == p + 1) {
            // Clamped now: the curve passes through the pole that ends (or starts) the knot
            // run: pole (last index of t) - p at the left end, (first index of t) - 1 at the
            // right one.
            const auto& K = r.knots();
            const int first = static_cast<int>(std::lower_bound(K.begin(), K.end(), t) - K.begin());
            const int last = static_cast<int>(std::upper_bound(K.begin(), K.end(), t) - K.begin()) - 1;
            const Vec3 end = to_vec3(r.poles()[t == c.domain_min() ? last - p : first - 1]);
            Curve_point cp;
            c.evaluate(t, cp, 0);
            EXPECT_LE((cp.p - end).norm(), 1e-14 * reach(c.hull_bbox()));
          }
          if (HasFailure()) return;
        }
        // One more would exceed p + 1.
        EXPECT_THROW(insert_knot(c, t, p + 2 - s), Precondition_violation);
      }
    }
  }
  // The same on a surface, in both directions.
  const int p = 3, q = 2, nu = 6, nv = 5;
  const Nurbs_surface_3 s(p, q, nu, nv, random_poles(rng, nu * nv),
                          uniform_unclamped_knots(p, nu, 0.0, 1.0),
                          uniform_unclamped_knots(q, nv, -1.0, 0.25), random_weights(rng, nu * nv));
  for (Parameter_direction dir : {Parameter_direction::U, Parameter_direction::V}) {
    const bool in_u = dir == Parameter_direction::U;
    const int deg = in_u ? p : q;
    for (double t : in_u ? std::vector<double>{s.u_min(), s.u_max()}
                         : std::vector<double>{s.v_min(), s.v_max()})
      for (int times = 1; times <= deg; ++times) {
        SCOPED_TRACE(::testing::Message() << (in_u ? "u" : "v") << " end " << t << " inserted "
                                          << times << " times");
        const Nurbs_surface_3 r = insert_knot(s, dir, t, times);
        expect_same_surface(r, s, s.u_min(), s.u_max(), s.v_min(), s.v_max(), 20);
        if (HasFailure()) return;
      }
  }
}

TEST(InsertKnot, ZeroTimesIsTheIdentity) {
  const Nurbs_surface_3 s = make_torus(2, 0.5);
  const Nurbs_surface_3 r = insert_knot(s, Parameter_direction::U, 1.0, 0);
  EXPECT_EQ(r.knots_u(), s.knots_u());
  EXPECT_EQ(r.homogeneous_poles(), s.homogeneous_poles());
}

TEST(InsertKnot, RejectsParametersOutsideTheDomainAndExcessMultiplicity) {
  const Nurbs_curve_3 c = make_circle(1.0);  // degree 2, double knots at multiples of pi/2
  EXPECT_THROW(insert_knot(c, -0.1), Precondition_violation);
  EXPECT_THROW(insert_knot(c, 2 * k_pi + 0.1), Precondition_violation);
  EXPECT_THROW(insert_knot(c, std::nan("")), Precondition_violation);
  EXPECT_THROW(insert_knot(c, 1.0, -1), Precondition_violation);
  EXPECT_THROW(insert_knot(c, 1.0, 3), Precondition_violation);  // interior: at most p = 2
  EXPECT_NO_THROW(insert_knot(c, 1.0, 2));
  EXPECT_THROW(insert_knot(c, c.knots()[3], 1), Precondition_violation);  // already double
  EXPECT_THROW(insert_knot(c, 0.0, 1), Precondition_violation);  // clamped end: already p + 1
  try {
    insert_knot(c, 1.0, 3);
    ADD_FAILURE() << "no exception";
  } catch (const Precondition_violation& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds the allowed multiplicity"), std::string::npos)
        << e.what();
  }
  try {
    insert_knot(c, 7.0);
    ADD_FAILURE() << "no exception";
  } catch (const Precondition_violation& e) {
    EXPECT_NE(std::string(e.what()).find("outside the domain"), std::string::npos) << e.what();
  }
  const Nurbs_surface_3 s = make_sphere(1.0);
  EXPECT_THROW(insert_knot(s, Parameter_direction::U, 7.0), Precondition_violation);
  EXPECT_THROW(insert_knot(s, Parameter_direction::V, 2.0), Precondition_violation);
  EXPECT_THROW(insert_knot(s, Parameter_direction::V, 0.0, 1), Precondition_violation);
  EXPECT_THROW(insert_knot(s, Parameter_direction::V, 0.5, 3), Precondition_violation);
}

// ---------------------------------------------------------------------------------------------
// Bezier extraction.

void check_curve_pieces(const Nurbs_curve_3& c) {
  const int p = c.degree();
  const auto b = breakpoints(c.knots(), c.number_of_poles(), p);
  const auto pieces = extract_bezier(c);
  ASSERT_EQ(pieces.size(), b.size() - 1);
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    SCOPED_TRACE(::testing::Message() << "piece " << i << " on [" << b[i] << ", " << b[i + 1] << "]");
    const Nurbs_curve_3& piece = pieces[i];
    EXPECT_EQ(piece.degree(), p);
    EXPECT_EQ(piece.number_of_poles(), p + 1);
    std::vector<double> knots(p + 1, b[i]);
    knots.insert(knots.end(), p + 1, b[i + 1]);
    EXPECT_EQ(piece.knots(), knots);
    expect_same_curve(piece, c, b[i], b[i + 1], 50);
    expect_hull_contains(piece, 30);
    EXPECT_TRUE(box_inside(piece.hull_bbox(), c.hull_bbox(), 4 * k_eps * reach(c.hull_bbox())));
    if (::testing::Test::HasFailure()) return;
  }
}

TEST(ExtractBezier, CurvePiecesCoverTheirKnotSpans) {
  EXTREMAL_SEEDED_RNG(rng);
  for (Kind kind : {Kind::Clamped, Kind::Unclamped})
    for (int p = 1; p <= 12; ++p) {
      SCOPED_TRACE(::testing::Message() << (kind == Kind::Clamped ? "clamped" : "unclamped")
                                        << ", degree " << p);
      check_curve_pieces(random_curve(rng, p, p + 1 + uniform_int(rng, 0, 6), kind));
      if (HasFailure()) return;
    }
  check_curve_pieces(make_circle(2.0));
}

void check_surface_pieces(const Nurbs_surface_3& s) {
  const auto bu = breakpoints(s.knots_u(), s.number_of_poles_u(), s.degree_u());
  const auto bv = breakpoints(s.knots_v(), s.number_of_poles_v(), s.degree_v());
  const Bezier_patches pieces = extract_bezier(s);
  ASSERT_EQ(pieces.count_u, static_cast<int>(bu.size()) - 1);
  ASSERT_EQ(pieces.count_v, static_cast<int>(bv.size()) - 1);
  ASSERT_EQ(pieces.patches.size(), static_cast<std::size_t>(pieces.count_u * pieces.count_v));
  const int p = s.degree_u(), q = s.degree_v();
  for (int i = 0; i < pieces.count_u; ++i)
    for (int j = 0; j < pieces.count_v; ++j) {
      SCOPED_TRACE(::testing::Message() << "patch (" << i << ", " << j << ") on [" << bu[i] << ", "
                                        << bu[i + 1] << "] x [" << bv[j] << ", " << bv[j + 1] << "]");
      const Nurbs_surface_3& piece = pieces.patches[i * pieces.count_v + j];
      EXPECT_EQ(piece.degree_u(), p);
      EXPECT_EQ(piece.degree_v(), q);
      EXPECT_EQ(piece.number_of_poles_u(), p + 1);
      EXPECT_EQ(piece.number_of_poles_v(), q + 1);
      // Its own parameter interval, which is its knot range.
      EXPECT_EQ(piece.u_min(), bu[i]);
      EXPECT_EQ(piece.u_max(), bu[i + 1]);
      EXPECT_EQ(piece.v_min(), bv[j]);
      EXPECT_EQ(piece.v_max(), bv[j + 1]);
      EXPECT_EQ(piece.knots_u().front(), bu[i]);
      EXPECT_EQ(piece.knots_u().back(), bu[i + 1]);
      EXPECT_EQ(piece.outward_sign(), s.outward_sign());
      expect_same_surface(piece, s, bu[i], bu[i + 1], bv[j], bv[j + 1], 12);
      expect_hull_contains(piece, 12);
      EXPECT_TRUE(box_inside(piece.hull_bbox(), s.hull_bbox(), 4 * k_eps * reach(s.hull_bbox())));
      if (::testing::Test::HasFailure()) return;
    }
}

TEST(ExtractBezier, SurfacePatchesCoverTheirKnotRanges) {
  EXTREMAL_SEEDED_RNG(rng);
  for (Kind kind : {Kind::Clamped, Kind::Unclamped})
    for (auto [p, q] : {std::pair{1, 1}, {2, 2}, {3, 3}, {1, 4}, {4, 2}, {12, 2}}) {
      SCOPED_TRACE(::testing::Message() << (kind == Kind::Clamped ? "clamped" : "unclamped")
                                        << ", degrees " << p << " x " << q);
      const int nu = p + 1 + uniform_int(rng, 0, 3), nv = q + 1 + uniform_int(rng, 0, 3);
      check_surface_pieces(random_surface(rng, p, q, nu, nv, kind, kind));
      if (HasFailure()) return;
    }
  // Mixed: clamped in u, unclamped in v.
  check_surface_pieces(random_surface(rng, 3, 2, 7, 6, Kind::Clamped, Kind::Unclamped));
}

TEST(ExtractBezier, Shapes) {
  for (const Nurbs_surface_3& s : {make_sphere(1.5), make_ellipsoid(3, 2, 1.5), make_torus(3, 1),
                                   make_cylinder_side(1, 2), make_disk(1, 0.5, true),
                                   make_plane(2, 3)}) {
    check_surface_pieces(s);
    if (HasFailure()) return;
  }
  EXPECT_EQ(extract_bezier(make_sphere(1)).patches.size(), 8u);  // 4 longitude x 2 latitude
  EXPECT_EQ(extract_bezier(make_torus(2, 1)).patches.size(), 16u);
  // Pieces of the sphere still lie on it.
  const double r = 1.5;
  Surface_point sp;
  for (const auto& piece : extract_bezier(make_sphere(r)).patches)
    for (int a = 0; a <= 20; ++a)
      for (int b = 0; b <= 20; ++b) {
        const double u = piece.u_min() + (piece.u_max() - piece.u_min()) * a / 20;
        const double v = piece.v_min() + (piece.v_max() - piece.v_min()) * b / 20;
        piece.evaluate(std::min(u, piece.u_max()), std::min(v, piece.v_max()), sp, 0);
        ASSERT_NEAR(sp.p.norm(), r, 1e-14 * r);
      }
}

// ---------------------------------------------------------------------------------------------
// Splitting.

TEST(Split, CurvePartsAreTheTwoHalves) {
  EXTREMAL_SEEDED_RNG(rng);
  for (Kind kind : {Kind::Clamped, Kind::Unclamped})
    for (int p = 1; p <= 12; ++p) {
      const Nurbs_curve_3 c = random_curve(rng, p, p + 1 + uniform_int(rng, 0, 5), kind);
      std::vector<double> ts = {uniform(rng, c.domain_min(), c.domain_max())};
      for (int i = p + 1; i < c.number_of_poles(); ++i)
        if (c.knots()[i] > c.domain_min() && c.knots()[i] < c.domain_max())
          ts.push_back(c.knots()[i]);
      for (double t : ts) {
        SCOPED_TRACE(::testing::Message() << "degree " << p << ", split at " << t);
        const auto [left, right] = split(c, t);
        EXPECT_EQ(left.domain_min(), c.domain_min());
        EXPECT_EQ(left.domain_max(), t);
        EXPECT_EQ(right.domain_min(), t);
        EXPECT_EQ(right.domain_max(), c.domain_max());
        expect_same_curve(left, c, c.domain_min(), t, 100);
        expect_same_curve(right, c, t, c.domain_max(), 100);
        expect_hull_contains(left, 30);
        expect_hull_contains(right, 30);
        if (HasFailure()) return;
      }
    }
}

TEST(Split, SurfacePartsAreTheTwoHalves) {
  EXTREMAL_SEEDED_RNG(rng);
  for (Kind kind : {Kind::Clamped, Kind::Unclamped})
    for (auto [p, q] : {std::pair{1, 2}, {2, 2}, {3, 3}, {5, 1}, {2, 12}}) {
      const int nu = p + 1 + uniform_int(rng, 0, 3), nv = q + 1 + uniform_int(rng, 0, 3);
      const Nurbs_surface_3 s = random_surface(rng, p, q, nu, nv, kind, kind);
      for (Parameter_direction dir : {Parameter_direction::U, Parameter_direction::V}) {
        const bool in_u = dir == Parameter_direction::U;
        const double t = in_u ? uniform(rng, s.u_min(), s.u_max()) : uniform(rng, s.v_min(), s.v_max());
        SCOPED_TRACE(::testing::Message() << "degrees " << p << " x " << q << ", split "
                                          << (in_u ? "u" : "v") << " at " << t);
        const auto [a, b] = split(s, dir, t);
        if (in_u) {
          EXPECT_EQ(a.u_min(), s.u_min());
          EXPECT_EQ(a.u_max(), t);
          EXPECT_EQ(b.u_min(), t);
          EXPECT_EQ(b.u_max(), s.u_max());
          EXPECT_EQ(a.knots_v(), s.knots_v());
          expect_same_surface(a, s, s.u_min(), t, s.v_min(), s.v_max(), 16);
          expect_same_surface(b, s, t, s.u_max(), s.v_min(), s.v_max(), 16);
        } else {
          EXPECT_EQ(a.v_min(), s.v_min());
          EXPECT_EQ(a.v_max(), t);
          EXPECT_EQ(b.v_min(), t);
          EXPECT_EQ(b.v_max(), s.v_max());
          EXPECT_EQ(a.knots_u(), s.knots_u());
          expect_same_surface(a, s, s.u_min(), s.u_max(), s.v_min(), t, 16);
          expect_same_surface(b, s, s.u_min(), s.u_max(), t, s.v_max(), 16);
        }
        expect_hull_contains(a, 12);
        expect_hull_contains(b, 12);
        if (HasFailure()) return;
      }
    }
}

TEST(Split, AtAnExistingKnotAndOnShapes) {
  const Nurbs_surface_3 s = make_sphere(2.0);
  const auto [west, east] = split(s, Parameter_direction::U, k_pi);  // an existing double knot
  expect_same_surface(west, s, 0, k_pi, s.v_min(), s.v_max(), 24);
  expect_same_surface(east, s, k_pi, 2 * k_pi, s.v_min(), s.v_max(), 24);
  EXPECT_EQ(west.outward_sign(), s.outward_sign());
  const auto [south, north] = split(s, Parameter_direction::V, 0.3);
  expect_same_surface(south, s, s.u_min(), s.u_max(), s.v_min(), 0.3, 24);
  expect_same_surface(north, s, s.u_min(), s.u_max(), 0.3, s.v_max(), 24);
  const Nurbs_curve_3 c = make_circle(1.0);
  const auto [first, second] = split(c, 1.0);
  expect_same_curve(first, c, 0, 1.0, 100);
  expect_same_curve(second, c, 1.0, 2 * k_pi, 100);
}

TEST(Split, RejectsTheEndsAndOutside) {
  const Nurbs_curve_3 c = make_circle(1.0);
  EXPECT_THROW(split(c, 0.0), Precondition_violation);
  EXPECT_THROW(split(c, 2 * k_pi), Precondition_violation);
  EXPECT_THROW(split(c, -1.0), Precondition_violation);
  EXPECT_THROW(split(c, std::nan("")), Precondition_violation);
  const Nurbs_surface_3 s = make_plane(1, 1);
  EXPECT_THROW(split(s, Parameter_direction::U, 0.0), Precondition_violation);
  EXPECT_THROW(split(s, Parameter_direction::V, 1.0), Precondition_violation);
  EXPECT_THROW(split(s, Parameter_direction::V, 1.5), Precondition_violation);
}

// ---------------------------------------------------------------------------------------------
// Hull boxes.

TEST(HullBox, ContainsDenseSamples) {
  EXTREMAL_SEEDED_RNG(rng);
  for (const Nurbs_surface_3& s : {make_sphere(1.0), make_ellipsoid(3, 2, 1.5), make_torus(3, 1),
                                   make_cylinder_side(1, 2), make_disk(2, -1, false),
                                   make_plane(3, 4)}) {
    expect_hull_contains(s, 100);
    if (HasFailure()) return;
  }
  for (int k = 0; k < 10; ++k) {
    const int p = uniform_int(rng, 1, 5), q = uniform_int(rng, 1, 5);
    const Nurbs_surface_3 s = random_surface(rng, p, q, p + 1 + uniform_int(rng, 0, 4),
                                             q + 1 + uniform_int(rng, 0, 4),
                                             k % 2 ? Kind::Clamped : Kind::Unclamped, Kind::Clamped);
    expect_hull_contains(s, 60);
    if (HasFailure()) return;
  }
  expect_hull_contains(make_circle(3.0), 1000);
  const Bbox_3 sphere_box = make_sphere(2.0).hull_bbox();
  EXPECT_EQ(sphere_box, Bbox_3(-2, -2, -2, 2, 2, 2));
}

}  // namespace
}  // namespace extremal
