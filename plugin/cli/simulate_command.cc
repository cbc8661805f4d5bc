// Parses the flags, checks every output path before any work, then for each
// selected sweep runs its points one after the other (each point's trials on
// --threads threads, see RunSweepPoint), collects the summaries, writes the
// sweep's CSV and SVG atomically and prints its table; the divergence table
// pools the B methods' counts over all points run. The random stream of a
// trial depends only on (--seed, sweep, point, trial), so a sweep run alone
// reproduces the same numbers as within --sweep all.

#include "odomcal/plugin/cli/simulate_command.h"

#include "odomcal/datasets/paper/paper_evaluation.h"
#include "odomcal/datasets/paper/paper_simulation.h"
#include "odomcal/datasets/paper/paper_sweeps.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/cli/command_line.h"
#include "odomcal/plugin/output/output_file.h"
#include "odomcal/plugin/output/output_folder.h"
#include "odomcal/plugin/report/svg_plot.h"
#include "odomcal/solver/format_number.h"

#include <unistd.h>

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace odomcal {
namespace {

// Methods in the plots: ALSP-orth is ALS exactly (see paper_evaluation.h),
// so it is left out of the figures (it stays in the CSV).
const EvaluationMethod kPlottedMethods[] = {
    EvaluationMethod::kAls,
    EvaluationMethod::kAlspLengthPreserving,
    EvaluationMethod::kCm,
    EvaluationMethod::kAlsB,
    EvaluationMethod::kAlspLengthPreservingB,
    EvaluationMethod::kCmB,
    EvaluationMethod::kGtB};

std::string CsvNumber(double value) {
  if (!std::isfinite(value)) return "";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.9g", value);
  return buffer;
}

std::string SweepCsv(const std::vector<SweepPointResult>& points) {
  std::ostringstream csv;
  csv << "value,method,rmse_rotation_deg,rmse_translation_m,rmse_scale_rel,"
         "divergence_rate,failures,trials,motions_used\n";
  for (const SweepPointResult& point : points) {
    for (const EvaluationMethod method : AllEvaluationMethods()) {
      const MethodSummary& s = point[method];
      csv << CsvNumber(point.value) << "," << ToString(method) << ","
          << CsvNumber(s.rmse_rotation_deg) << ","
          << CsvNumber(s.rmse_translation_m) << ","
          << CsvNumber(s.rmse_scale_rel) << "," << CsvNumber(s.divergence_rate)
          << "," << s.num_failures << "," << s.num_trials << ","
          << CsvNumber(s.motions_used) << "\n";
    }
  }
  return csv.str();
}

std::string SweepSvg(const PaperSweep& sweep,
                     const std::vector<SweepPointResult>& points,
                     int num_trials,
                     CameraNoiseMode mode) {
  PlotFigure figure;
  figure.title = "odomcal simulate: " + sweep.name + " (" +
                 std::to_string(num_trials) + " trials per point, " +
                 ToString(mode) + " camera noise)";
  struct PanelSpec {
    const char* title;
    const char* y_label;
    bool log_y;
    double (*get)(const MethodSummary&);
    bool batch_only;
  };
  const PanelSpec specs[] = {
      {"(a) rotation",
       "RMSE [deg]",
       true,
       [](const MethodSummary& s) { return s.rmse_rotation_deg; },
       false},
      {"(b) x/y translation",
       "RMSE [m]",
       true,
       [](const MethodSummary& s) { return s.rmse_translation_m; },
       false},
      {"(c) metric scale",
       "relative RMSE",
       true,
       [](const MethodSummary& s) { return s.rmse_scale_rel; },
       false},
      {"(d) divergence (truth outside 3 sigma)",
       "rate [%]",
       false,
       [](const MethodSummary& s) { return 100.0 * s.divergence_rate; },
       true},
  };
  for (const PanelSpec& spec : specs) {
    PlotPanel& panel = figure.panels.emplace_back();
    panel.title = spec.title;
    panel.x_label = sweep.x_label;
    panel.y_label = spec.y_label;
    panel.log_y = spec.log_y;
    int color = 0;
    for (const EvaluationMethod method : kPlottedMethods) {
      PlotSeries series;
      series.label = ToString(method);
      series.color = DefaultSeriesColor(color++);
      series.dashed = IsBatchMethod(method);
      if (!spec.batch_only || IsBatchMethod(method)) {
        for (const SweepPointResult& point : points) {
          series.x.push_back(point.value);
          series.y.push_back(spec.get(point[method]));
        }
      }
      panel.series.push_back(series);
    }
  }
  return RenderSvg(figure);
}

void PrintSweepTable(const PaperSweep& sweep,
                     const std::vector<SweepPointResult>& points,
                     int num_trials,
                     BatchRefinement batch) {
  std::printf("%s: %s, %d trials per point, B methods: %s\n",
              sweep.name.c_str(),
              sweep.x_label.c_str(),
              num_trials,
              ToString(batch).c_str());
  std::printf("  %8s  %-9s %10s %10s %9s %7s %7s %5s\n",
              "value",
              "method",
              "rot[deg]",
              "xy[mm]",
              "scale[%]",
              "div[%]",
              "used[%]",
              "fail");
  for (const SweepPointResult& point : points) {
    for (const EvaluationMethod method : AllEvaluationMethods()) {
      const MethodSummary& s = point[method];
      char divergence[16] = "-";
      if (std::isfinite(s.divergence_rate)) {
        std::snprintf(
            divergence, sizeof(divergence), "%.2f", 100.0 * s.divergence_rate);
      }
      char used[16] = "-";
      if (std::isfinite(s.motions_used)) {
        std::snprintf(used, sizeof(used), "%.1f", 100.0 * s.motions_used);
      }
      std::printf("  %8g  %-9s %10.4f %10.3f %9.4f %7s %7s %5d\n",
                  point.value,
                  ToString(method).c_str(),
                  s.rmse_rotation_deg,
                  1000.0 * s.rmse_translation_m,
                  100.0 * s.rmse_scale_rel,
                  divergence,
                  used,
                  s.num_failures);
    }
  }
  std::fflush(stdout);
}

struct DivergenceTotals {
  int divergences = 0;
  int with_covariance = 0;
  int failures = 0;
  int trials = 0;
};

}  // namespace

int RunSimulate(int argc, char** argv) {
  CLI::App app{
      "Monte Carlo evaluation of Guo et al. (ICRA 2012), Section V: RMSE of "
      "ALS, ALSP-L, ALSP-orth, CM and their batch refinements (and GT-B) over "
      "parameter "
      "sweeps (Fig. 2), and the divergence rates (Table I).",
      "odomcal simulate"};
  std::string output_path;
  int num_trials = 1000;
  uint64_t seed = 1;
  std::string sweep_name = "all";
  int num_threads = 2;
  std::string camera_noise = "landmarks";
  std::string two_view_starts = "all";
  EvaluationOptions evaluation;
  std::string batch_refinement = ToString(evaluation.batch_refinement);
  std::string batch_variance_factor = evaluation.variance_factor ? "on" : "off";
  const PaperSimulationOptions landmark_defaults =
      NominalPaperSimulation(CameraNoiseMode::kLandmarks);
  double landmark_max_depth_m = landmark_defaults.max_depth_m;
  bool overwrite = false;
  app.add_option("--output_path",
                 output_path,
                 "folder for <sweep>.csv, <sweep>.svg and divergence.csv "
                 "(created if missing)")
      ->required();
  app.add_option("--trials", num_trials, "Monte Carlo trials per sweep point")
      ->check(InRange(1, 1000000))
      ->capture_default_str();
  app.add_option("--seed", seed, "base seed of every trial")
      ->check(AtLeast(0))
      ->capture_default_str();
  app.add_option("--sweep", sweep_name, "the sweep to run")
      ->check(CLI::IsMember({"rotation_noise",
                             "translation_noise",
                             "pixel_noise",
                             "num_motions",
                             "all"}))
      ->capture_default_str();
  app.add_option("--threads", num_threads, "worker threads")
      ->check(InRange(1, 256))
      ->capture_default_str();
  app.add_option("--camera_noise",
                 camera_noise,
                 "landmarks: 12 points, pixel noise, 8-point + bundle "
                 "adjustment (the paper's); parametric: Gaussian rotation and "
                 "direction noise (fast)")
      ->check(CLI::IsMember({"landmarks", "parametric"}))
      ->capture_default_str();
  app.add_option("--two_view_starts",
                 two_view_starts,
                 "landmarks: bundle adjustments from every viable start and "
                 "the lowest cost (all), or from the 8-point solution only "
                 "(eight_point: the estimator before multi-start)")
      ->check(CLI::IsMember({"all", "eight_point"}))
      ->capture_default_str();
  app.add_option("--landmark_max_depth_m",
                 landmark_max_depth_m,
                 "landmarks: the farthest landmark depth [m] (the nearest: " +
                     FormatNumber(landmark_defaults.min_depth_m) + " m)")
      ->check(InRange(1.0, 100.0))
      ->capture_default_str();
  app.add_option("--batch_refinement",
                 batch_refinement,
                 "B methods: paper (one refinement on every motion) or "
                 "inlier_rounds (a Cauchy loss, then rounds on the motions "
                 "within noise, the weights evaluated again at each result)")
      ->check(CLI::IsMember({ToString(BatchRefinement::kPaper),
                             ToString(BatchRefinement::kInlierRounds)}))
      ->capture_default_str();
  app.add_option("--batch_variance_factor",
                 batch_variance_factor,
                 "B methods' divergence test: on (the covariance widened by "
                 "the trial's a posteriori variance factor when above 1) or "
                 "off (the paper's test on the covariance alone)")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  app.add_option("--cm_iterations",
                 evaluation.cm_ransac_iterations,
                 "RANSAC samples of the CM baseline (fixed budget)")
      ->check(InRange(1, 1000000))
      ->capture_default_str();
  app.add_flag("--overwrite", overwrite, "replace existing output files");
  if (const auto exit_code = ParseFlags(&app, argc, argv)) {
    return *exit_code;
  }

  try {
    const CameraNoiseMode mode = CameraNoiseModeFromString(camera_noise);
    std::vector<PaperSweep> sweeps;
    if (sweep_name == "all") {
      sweeps = PaperSweeps();
    } else {
      sweeps.push_back(FindPaperSweep(sweep_name));
    }
    const std::filesystem::path root(output_path);
    const std::string divergence_path = (root / "divergence.csv").string();
    std::vector<std::string> entries = {"divergence.csv"};
    for (const PaperSweep& sweep : sweeps) {
      entries.push_back(sweep.name + ".csv");
      entries.push_back(sweep.name + ".svg");
    }
    ClaimOutputFolder(output_path,
                      entries,
                      overwrite ? ExistingOutputs::kReplaceOwn
                                : ExistingOutputs::kRefuseExistingEntry);

    const bool show_progress = isatty(STDERR_FILENO) != 0;
    PaperSimulationOptions nominal = NominalPaperSimulation(mode);
    nominal.two_view_multi_start = two_view_starts == "all";
    nominal.max_depth_m = landmark_max_depth_m;
    evaluation.batch_refinement = BatchRefinementFromString(batch_refinement);
    evaluation.variance_factor = batch_variance_factor == "on";
    std::vector<DivergenceTotals> totals(kNumEvaluationMethods);
    const auto start = std::chrono::steady_clock::now();
    int total_trials = 0;
    for (const PaperSweep& sweep : sweeps) {
      std::vector<SweepPointResult> points;
      for (size_t p = 0; p < sweep.values.size(); ++p) {
        const double value = sweep.values[p];
        const PaperSimulationOptions simulation =
            ApplySweepValue(nominal, sweep.name, value);
        EvaluationProgressCallback progress;
        if (show_progress) {
          progress = [&sweep, p, value](int done, int total) {
            if (done != total && done % 10 != 0) return;
            std::fprintf(stderr,
                         "\r%s point %zu/%zu (%g): %d/%d trials   ",
                         sweep.name.c_str(),
                         p + 1,
                         sweep.values.size(),
                         value,
                         done,
                         total);
            std::fflush(stderr);
          };
        }
        points.push_back(RunSweepPoint(simulation,
                                       evaluation,
                                       sweep.name,
                                       static_cast<int>(p),
                                       value,
                                       num_trials,
                                       num_threads,
                                       seed,
                                       progress));
        total_trials += num_trials;
        for (const EvaluationMethod method : AllEvaluationMethods()) {
          const MethodSummary& s = points.back()[method];
          DivergenceTotals& t = totals[static_cast<int>(method)];
          t.divergences += s.num_divergences;
          t.with_covariance += s.num_with_covariance;
          t.failures += s.num_failures;
          t.trials += s.num_trials;
        }
      }
      if (show_progress) std::fprintf(stderr, "\r%78s\r", "");
      WriteFileAtomically((root / (sweep.name + ".csv")).string(),
                          SweepCsv(points));
      WriteFileAtomically((root / (sweep.name + ".svg")).string(),
                          SweepSvg(sweep, points, num_trials, mode));
      PrintSweepTable(sweep, points, num_trials, evaluation.batch_refinement);
    }

    std::ostringstream csv;
    csv << "method,divergences,trials_with_covariance,divergence_rate,"
           "failures,trials\n";
    std::printf("divergence (Table I), pooled over %d trials per method\n",
                total_trials);
    for (const EvaluationMethod method : AllEvaluationMethods()) {
      if (!IsBatchMethod(method)) continue;
      const DivergenceTotals& t = totals[static_cast<int>(method)];
      const double rate =
          t.with_covariance > 0
              ? static_cast<double>(t.divergences) / t.with_covariance
              : std::nan("");
      csv << ToString(method) << "," << t.divergences << ","
          << t.with_covariance << "," << CsvNumber(rate) << "," << t.failures
          << "," << t.trials << "\n";
      std::printf("  %-7s %6.2f %%  (%d of %d; %d failures)\n",
                  ToString(method).c_str(),
                  100.0 * rate,
                  t.divergences,
                  t.with_covariance,
                  t.failures);
    }
    WriteFileAtomically(divergence_path, csv.str());
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    std::printf("%d trials in %.1f s (%.1f trials/s on %d threads); wrote %s\n",
                total_trials,
                seconds,
                total_trials / seconds,
                num_threads,
                output_path.c_str());
    return kExitSuccess;
  } catch (const OutputError& error) {
    std::cerr << "odomcal simulate: error: " << error.what() << "\n";
  } catch (const std::invalid_argument& error) {
    std::cerr << "odomcal simulate: error: " << error.what() << "\n";
  }
  return kExitBadInput;
}

}  // namespace odomcal
