// What every reader's fuzz target does with a model it read: its boxes and, on a 5 x 5 grid of
// each face's parameter domain, its trims, so that a model that reads but cannot be used (a
// broken trim loop, a NaN bound) trips a sanitizer or a Precondition_violation here.
#pragma once

#include "io/Model_reader.h"

namespace extremal::fuzz {

inline void use_model(const io::Model& model) {
  for (const auto& body : model.bodies) {
    (void)body.trimmed_bbox();
    for (const auto& f : body.faces) {
      const auto& s = f.surface;
      for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j)
          (void)f.contains(s.u_min() + (s.u_max() - s.u_min()) * i / 4.0,
                           s.v_min() + (s.v_max() - s.v_min()) * j / 4.0);
    }
  }
}

}  // namespace extremal::fuzz
