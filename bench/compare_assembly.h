// bench/compare scenario (d), a moving body over the as1 assembly (compare_assembly.cpp).
#pragma once

#include <string>

namespace extremal::bench {

// Prints the scenario's table: a ball passing above the 18 solids of `data`/step/as1-oc-214-mat.stp
// (d1) and a point probe passing one of them at close range (d2), stepped by Scene_stepper over
// the moving body's 18 pairs at 100 Hz and 1 kHz; time per scene step and the tracked minimum's
// error against the certified solver. Returns 0, also when the file is missing (noted as skipped).
int run_assembly_scenario(bool quick, const std::string& data);

// --budget-sweep (compare_budget.h): the ball's and the probe's passes over all solids at 1 kHz
// at each swept budget, and FCL on tessellations of the ball and the solids at the same poses;
// prints the table and, with an `out_dir`, writes out_dir/compare_budget_d.svg. Returns 0, also
// when the file is missing (noted as skipped).
int run_assembly_budget_sweep(bool quick, const std::string& data, const std::string& out_dir);

}  // namespace extremal::bench
