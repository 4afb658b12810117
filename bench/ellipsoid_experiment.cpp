// The seed's experiment (Figures 6 and 7) reproduced: prints decay rates against the gain and
// the distance error against the certified reference, and writes the Figure 7 plot.
// Usage: ellipsoid_experiment [OUT_DIR]   (writes OUT_DIR/ellipsoid_errors.svg and .csv)
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "experiments/Ellipsoid_experiment.h"
#include "io/Svg_plot.h"

using namespace extremal;
using namespace extremal::experiments;

int main(int argc, char** argv) {
  const std::string out_dir = argc > 1 ? argv[1] : ".";
  const Ellipsoid_setup setup = default_ellipsoid_setup();

  std::printf("Decay of the normalised projection errors (1 kHz, Euler)\n");
  std::printf("%10s %14s %10s\n", "gain K", "measured rate", "ratio");
  io::Svg_plot plot;
  plot.title = "Normalised projection errors, two moving ellipsoids (1 kHz)";
  plot.x_label = "time [s]";
  plot.y_label = "max |normalised projection error|";
  plot.log_y = true;
  std::ofstream csv(out_dir + "/ellipsoid_errors.csv");
  csv << "gain,t,e_u,e_v,e_r,e_s\n";
  for (double K : {5.0, 10.0, 20.0}) {
    const Ellipsoid_run run =
        run_ellipsoid_experiment(setup, Tracker_options::with_gain(K), 1e-3, 3.0);
    const double rate = run.decay_rate();
    std::printf("%10.1f %14.4f %10.4f\n", K, rate, rate / K);
    io::Svg_series series;
    series.label = "K = " + std::to_string(static_cast<int>(K)) + " 1/s";
    for (const auto& s : run.samples) {
      const double e = s.normalised_errors.cwiseAbs().maxCoeff();
      series.x.push_back(s.t);
      series.y.push_back(std::max(e, 1e-17));
      csv << K << "," << s.t << "," << s.normalised_errors[0] << "," << s.normalised_errors[1]
          << "," << s.normalised_errors[2] << "," << s.normalised_errors[3] << "\n";
    }
    plot.series.push_back(std::move(series));
  }
  plot.write(out_dir + "/ellipsoid_errors.svg");

  std::printf("\nDistance error against the certified reference after the transient (K dt = 1)\n");
  std::printf("%8s %12s %14s %16s\n", "rate", "max error", "error / size", "certificate gap");
  const double size = setup.axes_a.maxCoeff();
  for (double dt : {1e-2, 1e-3}) {
    const Ellipsoid_run run =
        run_ellipsoid_experiment(setup, Tracker_options::with_gain(1.0 / dt), dt, 6.0);
    double gap = 0.0;
    for (const auto& s : run.samples) gap = std::max(gap, s.reference_gap);
    const double err = run.max_error_after(0.5);
    std::printf("%6.0fHz %12.3e %14.3e %16.3e\n", 1.0 / dt, err, err / size, gap);
  }
  std::printf("\nwrote %s/ellipsoid_errors.svg and .csv\n", out_dir.c_str());
  return 0;
}
