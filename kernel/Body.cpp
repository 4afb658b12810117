#include "kernel/Body.h"

namespace extremal {

Bbox_3 Body::hull_bbox() const {
  Bbox_3 box;
  if (is_point) box += Point_3(0, 0, 0).bbox();
  for (const auto& f : faces) box += f.surface.hull_bbox();
  for (const auto& c : curves) box += c.hull_bbox();
  return box;
}

}  // namespace extremal
