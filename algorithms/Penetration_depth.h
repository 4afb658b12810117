// Forwarding header (docs/CHANGES.md): moved to algorithms/distance/Penetration_depth.h.
// Kept so that Extremal.h and code that includes the old path build unchanged.
#pragma once

#include "algorithms/distance/Penetration_depth.h"
