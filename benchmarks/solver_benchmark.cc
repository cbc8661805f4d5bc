// Timings of the solver on simulated motion pairs
// (datasets/simulation/motion_simulator.h): the closed form (ALSP and ALS,
// hand_eye_linear.h), the Ceres refinement from the closed-form estimate
// (hand_eye_refine.h), RANSAC with 30 % outliers (hand_eye_ransac.h) and the
// whole pipeline (calibrate.h), each at 10, 100, 1000 and 10 000 motion pairs;
// and, as in PoseLib's benchmark, the rate at which the closed form finds the
// ground truth of noise-free random problems.
//
// Every problem is simulated before the timing loop from a fixed seed, with
// one SfM segment and the default NoiseModel unless stated otherwise.
// items_per_second counts motion pairs (problems for the ground-truth rate).
// The project's target: 10 000 pairs through the closed form in < 10 ms on
// one core. Run pinned to one core, e.g.
//   taskset -c 0 solver_benchmark --benchmark_min_time=0.2

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"
#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/hand_eye_linear.h"
#include "odomcal/solver/hand_eye_ransac.h"
#include "odomcal/solver/hand_eye_refine.h"
#include "odomcal/solver/rigid3.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

namespace odomcal {
namespace {

constexpr uint64_t kSeed = 20120514;  // fixed: every run times the same data
constexpr double kOutlierFraction = 0.3;
// Noise-free recovery tolerances of the unit tests (hand_eye_linear_test.cc).
constexpr double kRotationToleranceDeg = 1e-6;
constexpr double kTranslationToleranceM = 1e-9;
constexpr double kScaleToleranceRel = 1e-9;
// Problems behind the "found ground truth" rate; PoseLib and STYLE.md use 1000.
constexpr int kNumGroundTruthProblems = 1000;
constexpr int kGroundTruthNumPairs = 10;

SimulatedMotions Simulate(int num_pairs,
                          int num_segments,
                          bool add_noise,
                          double outlier_fraction,
                          uint64_t seed) {
  MotionSimulatorOptions options;
  options.num_pairs = num_pairs;
  options.num_segments = num_segments;
  options.add_noise = add_noise;
  options.outlier_fraction = outlier_fraction;
  std::mt19937_64 rng(seed);
  return SimulateMotions(options, &rng);
}

std::vector<int> AllIndices(const MotionPairs& pairs) {
  std::vector<int> indices(pairs.size());
  std::iota(indices.begin(), indices.end(), 0);
  return indices;
}

double RotationErrorDeg(const Eigen::Quaterniond& a,
                        const Eigen::Quaterniond& b) {
  return RotationAngle(a.conjugate() * b) * kRadToDeg;
}

// Translation z is held fixed (unobservable under planar motion): x and y.
double TranslationXyErrorM(const Rigid3d& a, const Rigid3d& b) {
  return (a.translation.head<2>() - b.translation.head<2>()).norm();
}

// Accuracy of an estimate against the simulation's truth, as counters that
// are averaged over the benchmark's repetitions (kAvgThreads leaves them as
// set: they describe one fixed problem).
void SetAccuracyCounters(benchmark::State& state,
                         const SimulatedMotions& truth,
                         bool success,
                         const Rigid3d& estimate) {
  state.counters["success"] = success ? 1.0 : 0.0;
  if (success) {
    state.counters["rot_err_deg"] =
        RotationErrorDeg(truth.odom_from_cam.rotation, estimate.rotation);
    state.counters["xy_err_mm"] =
        1e3 * TranslationXyErrorM(truth.odom_from_cam, estimate);
  }
}

void ClosedForm(benchmark::State& state, LinearMethod method) {
  const int num_pairs = static_cast<int>(state.range(0));
  const int num_segments = static_cast<int>(state.range(1));
  const SimulatedMotions problem = Simulate(num_pairs,
                                            num_segments,
                                            /*add_noise=*/true,
                                            /*outlier_fraction=*/0.0,
                                            kSeed + num_pairs);
  const std::vector<int> indices = AllIndices(problem.pairs);
  LinearOptions options;
  options.method = method;
  LinearEstimate estimate;
  for (auto _ : state) {
    estimate = EstimateOdomFromCamLinear(problem.pairs, indices, options);
    benchmark::DoNotOptimize(estimate);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * num_pairs);
  SetAccuracyCounters(state, problem, estimate.success, estimate.odom_from_cam);
}

// ALSP: step 2 on camera translations rotated into the motion plane.
void BM_ClosedForm(benchmark::State& state) {
  ClosedForm(state, LinearMethod::kAlsp);
}

// ALS: step 2 on camera translations as measured.
void BM_ClosedFormAls(benchmark::State& state) {
  ClosedForm(state, LinearMethod::kAls);
}

// Ceres refinement from the closed-form estimate (computed outside the loop);
// the timing includes building the Ceres problem and the information matrix.
void BM_Refine(benchmark::State& state) {
  const int num_pairs = static_cast<int>(state.range(0));
  const SimulatedMotions problem = Simulate(num_pairs,
                                            /*num_segments=*/1,
                                            /*add_noise=*/true,
                                            /*outlier_fraction=*/0.0,
                                            kSeed + num_pairs);
  const std::vector<int> indices = AllIndices(problem.pairs);
  const CalibrationOptions options;
  LinearOptions linear_options;
  linear_options.method = options.method;
  linear_options.alsp_projection = options.alsp_projection;
  linear_options.fixed_translation_z_m = options.fixed_translation_z_m;
  const LinearEstimate initial =
      EstimateOdomFromCamLinear(problem.pairs, indices, linear_options);
  if (!initial.success) {
    state.SkipWithError(("closed form failed: " + initial.failure).c_str());
    return;
  }
  RefinementResult refined;
  for (auto _ : state) {
    refined = RefineOdomFromCam(problem.pairs,
                                indices,
                                initial.odom_from_cam,
                                initial.metric_scales,
                                options);
    benchmark::DoNotOptimize(refined);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * num_pairs);
  state.counters["ceres_iterations"] = refined.num_iterations;
  SetAccuracyCounters(state, problem, refined.usable, refined.odom_from_cam);
}

// RANSAC on noisy pairs of which 30 % have a random camera motion.
void BM_Ransac(benchmark::State& state) {
  const int num_pairs = static_cast<int>(state.range(0));
  const SimulatedMotions problem = Simulate(num_pairs,
                                            /*num_segments=*/1,
                                            /*add_noise=*/true,
                                            kOutlierFraction,
                                            kSeed + num_pairs);
  const std::vector<int> indices = AllIndices(problem.pairs);
  const CalibrationOptions options;
  RansacResult ransac;
  for (auto _ : state) {
    ransac = RansacOdomFromCam(problem.pairs, indices, options);
    benchmark::DoNotOptimize(ransac);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * num_pairs);
  state.counters["ransac_iterations"] = ransac.num_iterations;
  state.counters["inlier_ratio"] =
      static_cast<double>(ransac.num_inliers) / num_pairs;
  int num_outliers_accepted = 0;
  for (int i = 0; i < num_pairs; ++i) {
    num_outliers_accepted += ransac.inlier_mask[i] && problem.is_outlier[i];
  }
  state.counters["outliers_accepted"] = num_outliers_accepted;
  SetAccuracyCounters(state, problem, ransac.success, ransac.odom_from_cam);
}

// CalibrateOdomCam with the default options (RANSAC, closed form, Ceres
// refinement, covariance, diagnostics) on the same data as BM_Ransac.
void BM_Calibrate(benchmark::State& state) {
  const int num_pairs = static_cast<int>(state.range(0));
  const SimulatedMotions problem = Simulate(num_pairs,
                                            /*num_segments=*/1,
                                            /*add_noise=*/true,
                                            kOutlierFraction,
                                            kSeed + num_pairs);
  CalibrationOptions options;
  options.use_ransac = true;
  options.refine = true;
  CalibrationResult result;
  for (auto _ : state) {
    result = CalibrateOdomCam(problem.pairs, options);
    benchmark::DoNotOptimize(result);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * num_pairs);
  state.counters["ransac_iterations"] =
      result.diagnostics.ransac_num_iterations;
  state.counters["pairs_used"] = result.diagnostics.num_pairs_used;
  SetAccuracyCounters(state, problem, result.IsSuccess(), result.odom_from_cam);
}

bool FoundGroundTruth(const SimulatedMotions& truth,
                      const LinearEstimate& estimate) {
  if (!estimate.success ||
      estimate.metric_scales.size() != truth.metric_scales.size()) {
    return false;
  }
  for (size_t k = 0; k < truth.metric_scales.size(); ++k) {
    if (!(std::abs(estimate.metric_scales[k] / truth.metric_scales[k] - 1.0) <
          kScaleToleranceRel)) {
      return false;
    }
  }
  return RotationErrorDeg(truth.odom_from_cam.rotation,
                          estimate.odom_from_cam.rotation) <
             kRotationToleranceDeg &&
         std::abs(truth.odom_from_cam.translation.x() -
                  estimate.odom_from_cam.translation.x()) <
             kTranslationToleranceM &&
         std::abs(truth.odom_from_cam.translation.y() -
                  estimate.odom_from_cam.translation.y()) <
             kTranslationToleranceM;
}

// PoseLib's "found ground truth" rate: every iteration solves the same
// kNumGroundTruthProblems noise-free random problems of kGroundTruthNumPairs
// pairs; found_gt is the fraction recovered to kRotationToleranceDeg,
// kTranslationToleranceM (x, y) and kScaleToleranceRel. Arguments: method
// (0 ALSP, 1 ALS) and the number of segments.
void BM_ClosedFormFoundGroundTruth(benchmark::State& state) {
  const LinearMethod method =
      state.range(0) == 0 ? LinearMethod::kAlsp : LinearMethod::kAls;
  const int num_segments = static_cast<int>(state.range(1));
  std::vector<SimulatedMotions> problems;
  problems.reserve(kNumGroundTruthProblems);
  std::mt19937_64 rng(kSeed);
  MotionSimulatorOptions simulator_options;
  simulator_options.num_pairs = kGroundTruthNumPairs;
  simulator_options.num_segments = num_segments;
  for (int n = 0; n < kNumGroundTruthProblems; ++n) {
    problems.push_back(SimulateMotions(simulator_options, &rng));
  }
  LinearOptions options;
  options.method = method;
  int num_found = 0;
  int num_solved = 0;
  for (auto _ : state) {
    num_found = 0;
    num_solved = 0;
    for (const SimulatedMotions& problem : problems) {
      const LinearEstimate estimate =
          EstimateOdomFromCamLinear(problem.pairs, options);
      benchmark::DoNotOptimize(estimate);
      num_solved += estimate.success;
      num_found += FoundGroundTruth(problem, estimate);
    }
  }
  state.SetItemsProcessed(state.iterations() * kNumGroundTruthProblems);
  state.counters["found_gt"] =
      static_cast<double>(num_found) / kNumGroundTruthProblems;
  state.counters["solved"] =
      static_cast<double>(num_solved) / kNumGroundTruthProblems;
}

// Extremes over --benchmark_repetitions, next to the built-in mean, median
// and stddev: the 10 ms target is about the worst case, and a shared machine
// makes single runs noisy.
double MinOf(const std::vector<double>& values) {
  return values.empty() ? 0.0 : *std::min_element(values.begin(), values.end());
}
double MaxOf(const std::vector<double>& values) {
  return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

void PairSizes(benchmark::internal::Benchmark* benchmark) {
  for (const int num_pairs : {10, 100, 1000, 10000}) {
    benchmark->Arg(num_pairs);
  }
}

void PairSizesOneSegment(benchmark::internal::Benchmark* benchmark) {
  benchmark->ArgNames({"pairs", "segments"});
  for (const int num_pairs : {10, 100, 1000, 10000}) {
    benchmark->Args({num_pairs, 1});
  }
  benchmark->ComputeStatistics("min", MinOf);
  benchmark->ComputeStatistics("max", MaxOf);
}

void PairSizesThreeSegments(benchmark::internal::Benchmark* benchmark) {
  benchmark->ArgNames({"pairs", "segments"});
  for (const int num_pairs : {10, 100, 1000, 10000}) {
    benchmark->Args({num_pairs, 3});
  }
}

BENCHMARK(BM_ClosedForm)
    ->Apply(PairSizesOneSegment)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ClosedFormAls)
    ->Apply(PairSizesOneSegment)
    ->Unit(benchmark::kMicrosecond);
// The multi-segment step 2 (grid over alpha + Gauss-Newton) takes another
// code path; timed separately so that its cost is visible.
BENCHMARK(BM_ClosedForm)
    ->Name("BM_ClosedFormThreeSegments")
    ->Apply(PairSizesThreeSegments)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Refine)->Apply(PairSizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ransac)->Apply(PairSizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Calibrate)->Apply(PairSizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClosedFormFoundGroundTruth)
    ->ArgNames({"method", "segments"})
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({0, 3})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace odomcal
