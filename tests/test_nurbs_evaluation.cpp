#include <gtest/gtest.h>
#include "kernel/Shapes.h"
using namespace extremal;
TEST(Smoke, Sphere) {
  auto s = make_sphere(2.0);
  Surface_point sp;
  s.evaluate(1.0, 0.3, sp);
  EXPECT_NEAR(sp.p.norm(), 2.0, 1e-14);
}
