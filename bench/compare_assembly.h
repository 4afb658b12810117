// bench/compare scenario (d), a moving body over the as1 assembly (compare_assembly.cpp).
#pragma once

#include <string>

namespace extremal::bench {

// Prints the scenario's table: a ball passing above the 18 solids of `data`/step/as1-oc-214-mat.stp
// (d1) and a point probe passing one of them at close range (d2), stepped by Scene_stepper over
// the moving body's 18 pairs at 100 Hz and 1 kHz; time per scene step and the tracked minimum's
// error against the certified solver. Returns 0, also when the file is missing (noted as skipped).
int run_assembly_scenario(bool quick, const std::string& data);

}  // namespace extremal::bench
