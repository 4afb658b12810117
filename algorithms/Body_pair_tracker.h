// Forwarding header (docs/CHANGES.md): moved to algorithms/body_pair/Body_pair_tracker.h.
// Kept so that Extremal.h and code that includes the old path build unchanged.
#pragma once

#include "algorithms/body_pair/Body_pair_tracker.h"
