// Forwarding header (docs/CHANGES.md): moved to algorithms/scene/Scene_stepper.h.
// Kept so that Extremal.h and code that includes the old path build unchanged.
#pragma once

#include "algorithms/scene/Scene_stepper.h"
