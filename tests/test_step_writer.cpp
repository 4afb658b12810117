// STEP writing (io/Step_writer.h) and the generated demo part (kernel/Bracket.h):
//  - the bracket is closed and outward: its divergence-theorem volume equals the profile area
//    times the length, every edge is used twice in opposite directions, trims match the edges;
//  - written and read back through our reader (OpenCASCADE): one body, the face and edge counts,
//    the bounding box, points and outward normals at the same parameters equal to 1e-9, and
//    the reader's OpenCASCADE checks (valid, closed, consistently oriented, positive volume)
//    raise no warning; a face removed from the shell in the text is caught by them;
//  - a real part from ../shared/data round-trips the same way;
//  - bodies that are not closed oriented B-rep solids are refused with the reason;
//  - data/demo/bracket.step, written by the build, is exactly what the generator writes now.
#include "io/Model_reader.h"
#include "io/Step_writer.h"
#include "kernel/Bracket.h"
#include "kernel/Error.h"
#include "kernel/Shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace extremal {
namespace {

const std::string source_dir = EXTREMAL_SOURCE_DIR;
const std::string binary_dir = EXTREMAL_BINARY_DIR;

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

// Gauss-Legendre nodes and weights on [0, 1], 8 points (exact for degree 15).
void gauss8(double* x, double* w) {
  const double n[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                       0.9602898564975363};
  const double c[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                       0.1012285362903763};
  for (int i = 0; i < 4; ++i) {
    x[2 * i] = 0.5 - 0.5 * n[i], w[2 * i] = 0.5 * c[i];
    x[2 * i + 1] = 0.5 + 0.5 * n[i], w[2 * i + 1] = 0.5 * c[i];
  }
}

// Integral of x n_x over an untrimmed face (outward normal): its share of the volume.
double x_flux(const Face& f) {
  const Nurbs_surface_3& s = f.surface;
  double x[8], w[8];
  gauss8(x, w);
  double sum = 0.0;
  Surface_point sp;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      const double u = s.u_min() + (s.u_max() - s.u_min()) * x[i];
      const double v = s.v_min() + (s.v_max() - s.v_min()) * x[j];
      s.evaluate(u, v, sp, 1);
      const Vec3 n = sp.du.cross(sp.dv) * s.outward_sign();  // area element times unit normal
      sum += w[i] * w[j] * sp.p.x() * n.x() * (s.u_max() - s.u_min()) * (s.v_max() - s.v_min());
    }
  return sum;
}

TEST(Bracket, ClosedOutwardAndTrimsOnEdges) {
  const Bracket_size size;
  const Body b = make_bracket_body(size);
  ASSERT_EQ(b.faces.size(), 14u);
  ASSERT_EQ(b.edges.size(), 36u);
  // Caps have n_x = 0, so the sides alone give the volume; a side facing inwards, or a missing
  // side, changes it.
  double volume = 0.0;
  for (int k = 0; k < 12; ++k) volume += x_flux(b.faces[k]);
  EXPECT_NEAR(volume, bracket_volume(size), 1e-9 * bracket_volume(size));
  EXPECT_GT(bracket_volume(size), 0.0);
  // The caps' outward normals are -y and +y.
  for (int cap = 0; cap < 2; ++cap) {
    const Face& f = b.faces[12 + cap];
    Surface_point sp;
    f.surface.evaluate(0.5, 0.1, sp, 1);  // inside the profile (the floor)
    EXPECT_TRUE(f.contains(0.5, 0.1));
    EXPECT_FALSE(f.contains(0.5, 0.9));  // in the slot
    EXPECT_NEAR(f.surface.outward_normal(sp).y(), cap == 0 ? -1.0 : 1.0, 1e-15);
  }
  // Every trim curve maps onto its edge's 3D curve at the same parameter; each edge is used by
  // two faces.
  for (std::size_t e = 0; e < b.edges.size(); ++e) {
    const Edge& edge = b.edges[e];
    ASSERT_EQ(edge.uses.size(), 2u) << "edge " << e;
    for (const Edge_use& use : edge.uses) {
      const Face& f = b.faces[use.face];
      const Trim_curve& tc = f.trims[use.loop].curves[use.curve];
      EXPECT_EQ(tc.edge, static_cast<int>(e));
      for (int k = 0; k <= 10; ++k) {
        const double t = k / 10.0;
        const Point_3 uv = tc.uv.point(t);
        const Vec3 on_face = to_vec3(f.surface.point(uv.x(), uv.y()));
        EXPECT_LT((on_face - to_vec3(edge.curve->point(t))).norm(), 1e-14) << "edge " << e;
      }
    }
  }
}

TEST(Bracket, BadSizesAreRefusedWithTheReason) {
  Bracket_size s;
  s.slot_width = 9.0;
  try {
    make_bracket_body(s);
    FAIL() << "no exception";
  } catch (const Invalid_input& e) {
    EXPECT_NE(std::string(e.what()).find("slot_width"), std::string::npos) << e.what();
  }
  s = Bracket_size();
  s.fillet = std::nan("");
  EXPECT_THROW(make_bracket_body(s), Invalid_input);
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = binary_dir + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(StepWriter, BracketRoundTripsThroughOpenCascade) {
  const Body original = make_bracket_body();
  const std::string path = binary_dir + "/test_step_writer_bracket.step";
  io::write_step(path, {original});
  const io::Model m = io::read_model(path);
  EXPECT_EQ(m.format_name, "STEP AP214");
  EXPECT_EQ(m.file_unit, "millimetre");
  EXPECT_TRUE(m.skipped.empty());
  for (const auto& w : m.warnings) ADD_FAILURE() << "warning: " << w;
  ASSERT_EQ(m.bodies.size(), 1u);
  const Body& b = m.bodies[0];
  EXPECT_EQ(b.source_name, "bracket");
  ASSERT_EQ(b.faces.size(), original.faces.size());
  EXPECT_EQ(b.edges.size(), original.edges.size());
  for (const Edge& e : b.edges) EXPECT_EQ(e.uses.size(), 2u);

  const Bbox_3 box = b.trimmed_bbox(b.placement);
  const double expected[6] = {-4, -5, 0, 4, 5, 4};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(box.min(k), expected[k], 1e-9);
    EXPECT_NEAR(box.max(k), expected[k + 3], 1e-9);
  }

  // Points and outward normals at the same parameters, inside the trims.
  for (std::size_t f = 0; f < original.faces.size(); ++f) {
    const Face& a = original.faces[f];
    const Face& r = b.faces[f];
    EXPECT_EQ(r.surface.degree_u(), a.surface.degree_u()) << "face " << f;
    EXPECT_EQ(r.surface.is_rational(), a.surface.is_rational()) << "face " << f;
    int checked = 0;
    for (int i = 0; i <= 12; ++i)
      for (int j = 0; j <= 12; ++j) {
        const double u = i / 12.0, v = j / 12.0;
        if (!a.contains(u, v)) continue;
        EXPECT_TRUE(r.contains(u, v)) << "face " << f << " at " << u << ", " << v;
        Surface_point pa, pr;
        a.surface.evaluate(u, v, pa, 1);
        r.surface.evaluate(u, v, pr, 1);
        const Vec3 placed = b.placement.apply_point(pr.p);
        EXPECT_LT((placed - pa.p).norm(), 1e-9) << "face " << f;
        const Vec3 na = a.surface.outward_normal(pa);
        const Vec3 nr = b.placement.apply_vector(r.surface.outward_normal(pr));
        EXPECT_GT(na.dot(nr), 1.0 - 1e-12) << "face " << f;
        ++checked;
      }
    EXPECT_GT(checked, 20) << "face " << f;
  }
}

TEST(StepWriter, OpenCascadeChecksCatchAnOpenShell) {
  std::string text = io::write_step_string({make_bracket_body()});
  // Drop the first face from the shell in the file only.
  const auto shell = text.find("CLOSED_SHELL('',(");
  ASSERT_NE(shell, std::string::npos);
  const auto first = shell + std::string("CLOSED_SHELL('',(").size();
  text.erase(first, text.find(',', first) + 1 - first);
  const io::Model m = io::read_model(write_temp("test_step_writer_open.step", text));
  std::string all;
  for (const auto& w : m.warnings) all += w + "\n";
  EXPECT_NE(all.find("the boundary is not closed"), std::string::npos) << all;
}

TEST(StepWriter, RefusesWhatIsNotAClosedOrientedSolid) {
  auto message = [](const std::vector<Body>& bodies) {
    try {
      io::write_step_string(bodies);
    } catch (const Invalid_input& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_NE(message({make_ellipsoid_body(3, 2, 1.5, "A")}).find("'A' has no B-rep"),
            std::string::npos);
  Body flipped = make_bracket_body();
  flipped.faces[3].surface.set_outward_sign(-1);
  EXPECT_NE(message({flipped}).find("once each way"), std::string::npos) << message({flipped});
  Body open = make_bracket_body();
  open.faces.pop_back();
  for (auto& e : open.edges) e.uses.clear();
  EXPECT_NE(message({open}).find("once each way"), std::string::npos) << message({open});
  EXPECT_NE(message({}).find("no body"), std::string::npos);
}

TEST(StepWriter, PlacementIsApplied) {
  Body placed = make_bracket_body();
  placed.placement = Rigid_pose_3::from_quaternion(Vec3(10, -2, 5), std::cos(0.3), 0, 0,
                                                   std::sin(0.3));
  const io::Model m =
      io::read_model(write_temp("test_step_writer_placed.step", io::write_step_string({placed})));
  ASSERT_EQ(m.bodies.size(), 1u);
  const Body& b = m.bodies[0];
  for (std::size_t f = 0; f < placed.faces.size(); ++f) {
    const Vec3 expected =
        placed.placement.apply_point(to_vec3(placed.faces[f].surface.point(0.5, 0.5)));
    const Vec3 got = b.placement.apply_point(to_vec3(b.faces[f].surface.point(0.5, 0.5)));
    EXPECT_LT((got - expected).norm(), 1e-9) << "face " << f;
  }
}

// A real part read from ../shared/data (screw.step: 10 faces, B-spline and periodic surfaces
// with seam edges), written by us and read back: the same solids, and every face's points (at
// the same parameters, inside the trims) where they were, placements included (the writer
// applies each body's placement to its geometry).
TEST(StepWriter, RealPartRoundTrips) {
  const io::Model in =
      io::read_model(std::string(EXTREMAL_SHARED_DATA) + "/step/screw.step");
  ASSERT_FALSE(in.bodies.empty());
  const io::Model out =
      io::read_model(write_temp("test_step_writer_as1.step", io::write_step_string(in.bodies)));
  for (const auto& w : out.warnings) ADD_FAILURE() << "warning: " << w;
  ASSERT_EQ(out.bodies.size(), in.bodies.size());
  int checked = 0;
  for (std::size_t k = 0; k < in.bodies.size(); ++k) {
    const Body& a = in.bodies[k];
    const Body& b = out.bodies[k];
    ASSERT_EQ(b.faces.size(), a.faces.size()) << "body " << k;
    for (std::size_t f = 0; f < a.faces.size(); ++f) {
      const Nurbs_surface_3& s = a.faces[f].surface;
      for (int i = 0; i <= 6; ++i)
        for (int j = 0; j <= 6; ++j) {
          const double u = s.u_min() + (s.u_max() - s.u_min()) * i / 6.0;
          const double v = s.v_min() + (s.v_max() - s.v_min()) * j / 6.0;
          if (!a.faces[f].contains(u, v)) continue;
          const Vec3 pa = a.placement.apply_point(to_vec3(s.point(u, v)));
          const Vec3 pb = b.placement.apply_point(to_vec3(b.faces[f].surface.point(u, v)));
          EXPECT_LT((pa - pb).norm(), 1e-9) << "body " << k << " face " << f;
          ++checked;
        }
    }
  }
  EXPECT_GT(checked, 50);
}

// The demo part the build wrote (target demo_part) is what the generator writes now: a build
// that did not rewrite it after a change of the generator or the writer shows here.
TEST(StepWriter, DemoPartIsUpToDate) {
  io::Step_write_options options;
  options.file_name = "bracket.step";
  const std::string now = io::write_step_string({make_bracket_body()}, options);
  const std::string on_disk = slurp(source_dir + "/data/demo/bracket.step");
  EXPECT_TRUE(now == on_disk)
      << "data/demo/bracket.step is stale or missing: the build's target demo_part writes it";
}

}  // namespace
}  // namespace extremal
