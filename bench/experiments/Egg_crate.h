// Scenario (b) of bench/compare, shared with the tests that audit it: a non-convex part of
// 3 x 3 bicubic faces over [-1.5, 1.5]^2 sampling the egg crate z = 0.25 sin(2x) cos(2y) at
// their control points (shared boundary poles: C0 joins).
#pragma once

#include "kernel/Body.h"

namespace extremal::experiments {

Body egg_crate();

}  // namespace extremal::experiments
