// A trial runs the three closed forms and CM on all pairs, then the batch
// refinement from each of ALS, ALSP-L, CM and the truth. The refinement's
// information (J^T J in the reported coordinates) is inverted by an
// eigen-decomposition; a non-positive-definite one leaves the B method
// without covariance (then it cannot be tested for divergence). Trials are
// distributed over the threads through an atomic counter and written to
// their own slot, so the aggregation, done afterwards in trial order, is
// bitwise independent of the thread count.

#include "odomcal/datasets/paper/paper_evaluation.h"

#include "odomcal/datasets/paper/chang_baseline.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/hand_eye_linear.h"
#include "odomcal/solver/hand_eye_refine.h"
#include "odomcal/solver/noise_refinement.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <thread>

namespace odomcal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The divergence bound, in standard deviations (Table I: "3 sigma").
constexpr double kDivergenceSigmas = 3.0;
// Information eigenvalues below this fraction of the largest: singular.
constexpr double kMinInformationRatio = 1e-15;
// BatchRefinement::kInlierRounds: refinements per B method, and the fewest
// motions (absolute, and as a fraction of all) a round's inlier test may keep
// before it is not trusted.
constexpr int kMaxInlierRounds = 6;
constexpr size_t kMinInlierMotions = 3;
constexpr double kMinInlierFraction = 0.5;

uint64_t SplitMix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

uint64_t Fnv1a(const std::string& text) {
  uint64_t hash = 0xcbf29ce484222325ULL;
  for (const char c : text) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

bool ValidScales(const std::vector<double>& scales, size_t num_segments) {
  if (scales.size() < num_segments) return false;
  for (size_t k = 0; k < num_segments; ++k) {
    if (!std::isfinite(scales[k])) return false;
  }
  return true;
}

MethodError Errors(const PaperSimulation& truth,
                   const Rigid3d& estimate,
                   const std::vector<double>& scales) {
  MethodError error;
  const size_t num_segments = truth.metric_scales.size();
  if (!IsFinite(estimate) || !ValidScales(scales, num_segments)) {
    error.failed = true;
    return error;
  }
  error.rotation_deg = RotationAngle(estimate.rotation.conjugate() *
                                     truth.odom_from_cam.rotation) *
                       kRadToDeg;
  error.translation_m = (estimate.translation.head<2>() -
                         truth.odom_from_cam.translation.head<2>())
                            .norm();
  double sum = 0.0;
  for (size_t k = 0; k < num_segments; ++k) {
    const double rel =
        (scales[k] - truth.metric_scales[k]) / truth.metric_scales[k];
    sum += rel * rel;
  }
  error.scale_rel = std::sqrt(sum / static_cast<double>(num_segments));
  return error;
}

// Divergence test of a refinement, see the header.
void TestDivergence(const PaperSimulation& truth,
                    const RefinementResult& refined,
                    int num_used,
                    bool variance_factor,
                    MethodError* error) {
  const Eigen::MatrixXd& information = refined.information;
  const int n = static_cast<int>(information.rows());
  if (n != 5 + static_cast<int>(refined.information_segments.size()) ||
      n == 0 || !information.allFinite()) {
    return;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(
      0.5 * (information + information.transpose()));
  const Eigen::VectorXd& values = eigen.eigenvalues();
  if (!(values(0) > kMinInformationRatio * values(n - 1))) return;
  Eigen::MatrixXd covariance = eigen.eigenvectors() *
                               values.cwiseInverse().asDiagonal() *
                               eigen.eigenvectors().transpose();
  if (variance_factor) {
    const double factor = PosteriorVarianceFactor(refined, num_used);
    if (factor > 1.0) covariance *= factor;
  }
  Eigen::VectorXd e(n);
  e.head<3>() = LogRotation(truth.odom_from_cam.rotation *
                            refined.odom_from_cam.rotation.conjugate());
  e.segment<2>(3) = truth.odom_from_cam.translation.head<2>() -
                    refined.odom_from_cam.translation.head<2>();
  for (size_t k = 0; k < refined.information_segments.size(); ++k) {
    const int segment = refined.information_segments[k];
    e(5 + k) =
        truth.metric_scales.at(segment) - refined.metric_scales.at(segment);
  }
  error->has_covariance = true;
  for (int k = 0; k < n; ++k) {
    if (std::abs(e(k)) > kDivergenceSigmas * std::sqrt(covariance(k, k))) {
      error->diverged = true;
    }
  }
}

// The B methods' error and divergence test.
MethodError Refined(const PaperSimulation& truth,
                    const Rigid3d& start,
                    const std::vector<double>& start_scales,
                    const CalibrationOptions& options,
                    const EvaluationOptions& evaluation) {
  MotionPairs core_pairs;
  if (evaluation.inlier_test_on_core_covariance &&
      truth.cam_core_covariances.size() == truth.pairs.size()) {
    core_pairs = truth.pairs;
    for (size_t k = 0; k < core_pairs.size(); ++k) {
      core_pairs[k].cam_covariance = truth.cam_core_covariances[k];
    }
  }
  const BatchRefined refined =
      RefineBatch(truth.pairs,
                  start,
                  start_scales,
                  options,
                  evaluation.batch_refinement,
                  core_pairs.empty() ? nullptr : &core_pairs);
  MethodError error;
  if (!refined.refinement.usable) {
    error.failed = true;
    return error;
  }
  error = Errors(truth,
                 refined.refinement.odom_from_cam,
                 refined.refinement.metric_scales);
  error.num_pairs_used = static_cast<int>(refined.used.size());
  if (!error.failed) {
    TestDivergence(truth,
                   refined.refinement,
                   error.num_pairs_used,
                   evaluation.variance_factor,
                   &error);
  }
  return error;
}

double Rmse(double sum_squares, int count) {
  return count > 0 ? std::sqrt(sum_squares / count) : kNaN;
}

}  // namespace

double PosteriorVarianceFactor(const RefinementResult& refined,
                               int num_motions_used) {
  const int degrees_of_freedom =
      6 * num_motions_used - 5 -
      static_cast<int>(refined.information_segments.size());
  if (degrees_of_freedom <= 0) return kNaN;
  return 2.0 * refined.final_cost / degrees_of_freedom;
}

std::string ToString(BatchRefinement batch) {
  return batch == BatchRefinement::kPaper ? "paper" : "inlier_rounds";
}

BatchRefinement BatchRefinementFromString(const std::string& text) {
  for (const BatchRefinement batch :
       {BatchRefinement::kPaper, BatchRefinement::kInlierRounds}) {
    if (text == ToString(batch)) return batch;
  }
  throw std::invalid_argument(
      "batch refinement must be paper or inlier_rounds, got '" + text + "'");
}

BatchRefined RefineBatch(const MotionPairs& pairs,
                         const Rigid3d& start,
                         const std::vector<double>& start_scales,
                         const CalibrationOptions& options,
                         BatchRefinement batch,
                         const MotionPairs* inlier_test_pairs) {
  std::vector<int> indices(pairs.size());
  std::iota(indices.begin(), indices.end(), 0);
  const bool rounds = batch == BatchRefinement::kInlierRounds;
  // The first refinement with a Cauchy loss: see BatchRefinement.
  CalibrationOptions first = options;
  if (rounds) first.robust_loss = RobustLoss::kCauchy;
  RefinementResult refined =
      RefineOdomFromCam(pairs, indices, start, start_scales, first);
  // Whether `refined` comes from a refinement without loss (its information,
  // and so the divergence test, then holds for the motions it used).
  bool without_loss = !rounds;
  for (int round = 1; rounds && refined.usable && round < kMaxInlierRounds;
       ++round) {
    std::vector<int> next =
        PairsWithinNoise(inlier_test_pairs ? *inlier_test_pairs : pairs,
                         refined.odom_from_cam,
                         refined.metric_scales,
                         options.noise);
    // A test that keeps too few motions is not trusted.
    if (next.size() < kMinInlierMotions ||
        next.size() < kMinInlierFraction * pairs.size()) {
      break;
    }
    const bool same_motions = next == indices;
    // From the last result, so with the weights evaluated there.
    RefinementResult again = RefineOdomFromCam(
        pairs, next, refined.odom_from_cam, refined.metric_scales, options);
    if (!again.usable) break;
    refined = std::move(again);
    indices = std::move(next);
    without_loss = true;
    if (same_motions) break;
  }
  // No round was trusted: every motion, without loss, from the robust result.
  if (refined.usable && !without_loss) {
    refined = RefineOdomFromCam(
        pairs, indices, refined.odom_from_cam, refined.metric_scales, options);
  }
  BatchRefined result;
  result.refinement = std::move(refined);
  result.used = std::move(indices);
  return result;
}

std::string ToString(EvaluationMethod method) {
  switch (method) {
    case EvaluationMethod::kAls:
      return "ALS";
    case EvaluationMethod::kAlspLengthPreserving:
      return "ALSP-L";
    case EvaluationMethod::kAlspOrthogonal:
      return "ALSP-orth";
    case EvaluationMethod::kCm:
      return "CM";
    case EvaluationMethod::kAlsB:
      return "ALS-B";
    case EvaluationMethod::kAlspLengthPreservingB:
      return "ALSP-L-B";
    case EvaluationMethod::kCmB:
      return "CM-B";
    case EvaluationMethod::kGtB:
      return "GT-B";
  }
  return "?";
}

bool IsBatchMethod(EvaluationMethod method) {
  return method == EvaluationMethod::kAlsB ||
         method == EvaluationMethod::kAlspLengthPreservingB ||
         method == EvaluationMethod::kCmB || method == EvaluationMethod::kGtB;
}

std::array<EvaluationMethod, kNumEvaluationMethods> AllEvaluationMethods() {
  return {EvaluationMethod::kAls,
          EvaluationMethod::kAlspLengthPreserving,
          EvaluationMethod::kAlspOrthogonal,
          EvaluationMethod::kCm,
          EvaluationMethod::kAlsB,
          EvaluationMethod::kAlspLengthPreservingB,
          EvaluationMethod::kCmB,
          EvaluationMethod::kGtB};
}

void EvaluationOptions::Check() const {
  if (cm_ransac_iterations < 1) {
    throw std::invalid_argument("cm_ransac_iterations must be >= 1, got " +
                                std::to_string(cm_ransac_iterations));
  }
  if (max_refinement_iterations < 1) {
    throw std::invalid_argument("max_refinement_iterations must be >= 1, got " +
                                std::to_string(max_refinement_iterations));
  }
}

TrialResult EvaluateTrial(const PaperSimulation& simulation,
                          const EvaluationOptions& options,
                          uint64_t seed) {
  options.Check();
  TrialResult trial;
  trial.num_pairs = static_cast<int>(simulation.pairs.size());
  const MotionPairs& pairs = simulation.pairs;
  std::vector<int> indices(pairs.size());
  std::iota(indices.begin(), indices.end(), 0);
  const double z = simulation.odom_from_cam.translation.z();
  auto slot = [&trial](EvaluationMethod method) -> MethodError& {
    return trial.methods[static_cast<int>(method)];
  };

  struct Start {
    bool ok = false;
    Rigid3d odom_from_cam;
    std::vector<double> scales;
  };
  auto linear = [&](LinearMethod method, PlaneProjection projection) {
    LinearOptions linear_options;
    linear_options.method = method;
    linear_options.alsp_projection = projection;
    linear_options.fixed_translation_z_m = z;
    const LinearEstimate estimate =
        EstimateOdomFromCamLinear(pairs, indices, linear_options);
    Start start;
    start.ok = estimate.success;
    start.odom_from_cam = estimate.odom_from_cam;
    start.scales = estimate.metric_scales;
    return start;
  };
  auto record = [&](EvaluationMethod method, const Start& start) {
    if (!start.ok) {
      slot(method).failed = true;
    } else {
      slot(method) = Errors(simulation, start.odom_from_cam, start.scales);
    }
  };

  const Start als =
      linear(LinearMethod::kAls, PlaneProjection::kLengthPreserving);
  const Start alsp_l =
      linear(LinearMethod::kAlsp, PlaneProjection::kLengthPreserving);
  const Start alsp_orth =
      linear(LinearMethod::kAlsp, PlaneProjection::kOrthogonal);
  record(EvaluationMethod::kAls, als);
  record(EvaluationMethod::kAlspLengthPreserving, alsp_l);
  record(EvaluationMethod::kAlspOrthogonal, alsp_orth);

  CalibrationOptions cm_options;
  cm_options.fixed_translation_z_m = z;
  cm_options.ransac_max_iterations = options.cm_ransac_iterations;
  cm_options.ransac_seed = SplitMix64(seed ^ 0x636d636d636d636dULL);
  const ChangEstimate chang = EstimateOdomFromCamChang(pairs, cm_options);
  Start cm;
  cm.ok = chang.success;
  cm.odom_from_cam = chang.odom_from_cam;
  cm.scales = chang.metric_scales;
  record(EvaluationMethod::kCm, cm);

  CalibrationOptions refine_options;
  refine_options.robust_loss = RobustLoss::kNone;
  refine_options.fixed_translation_z_m = z;
  refine_options.max_num_iterations = options.max_refinement_iterations;
  auto batch = [&](EvaluationMethod method, const Start& start) {
    if (!start.ok ||
        !(ValidScales(start.scales, simulation.metric_scales.size()))) {
      slot(method).failed = true;
      return;
    }
    slot(method) = Refined(
        simulation, start.odom_from_cam, start.scales, refine_options, options);
  };
  batch(EvaluationMethod::kAlsB, als);
  batch(EvaluationMethod::kAlspLengthPreservingB, alsp_l);
  batch(EvaluationMethod::kCmB, cm);
  Start truth;
  truth.ok = true;
  truth.odom_from_cam = simulation.odom_from_cam;
  truth.scales = simulation.metric_scales;
  batch(EvaluationMethod::kGtB, truth);
  return trial;
}

SweepPointResult SummarizeTrials(double value,
                                 const std::vector<TrialResult>& trials) {
  SweepPointResult result;
  result.value = value;
  result.num_trials = static_cast<int>(trials.size());
  for (const EvaluationMethod method : AllEvaluationMethods()) {
    MethodSummary& summary = result.methods[static_cast<int>(method)];
    summary.num_trials = result.num_trials;
    double sum_rotation = 0.0, sum_translation = 0.0, sum_scale = 0.0;
    double sum_used = 0.0;
    int num_ok = 0;
    for (const TrialResult& trial : trials) {
      const MethodError& error = trial[method];
      if (error.failed) {
        ++summary.num_failures;
        continue;
      }
      ++num_ok;
      sum_rotation += error.rotation_deg * error.rotation_deg;
      sum_translation += error.translation_m * error.translation_m;
      sum_scale += error.scale_rel * error.scale_rel;
      if (trial.num_pairs > 0) {
        sum_used += static_cast<double>(error.num_pairs_used) / trial.num_pairs;
      }
      if (error.has_covariance) {
        ++summary.num_with_covariance;
        if (error.diverged) ++summary.num_divergences;
      }
    }
    summary.rmse_rotation_deg = Rmse(sum_rotation, num_ok);
    summary.rmse_translation_m = Rmse(sum_translation, num_ok);
    summary.rmse_scale_rel = Rmse(sum_scale, num_ok);
    summary.motions_used =
        IsBatchMethod(method) && num_ok > 0 ? sum_used / num_ok : kNaN;
    summary.divergence_rate =
        IsBatchMethod(method) && summary.num_with_covariance > 0
            ? static_cast<double>(summary.num_divergences) /
                  summary.num_with_covariance
            : kNaN;
  }
  return result;
}

uint64_t TrialSeed(uint64_t base_seed,
                   const std::string& sweep_name,
                   int point_index,
                   int trial_index) {
  uint64_t hash = SplitMix64(base_seed ^ Fnv1a(sweep_name));
  hash = SplitMix64(hash ^ static_cast<uint64_t>(point_index));
  return SplitMix64(hash ^ static_cast<uint64_t>(trial_index));
}

std::vector<TrialResult> RunTrials(const PaperSimulationOptions& simulation,
                                   const EvaluationOptions& options,
                                   const std::string& sweep_name,
                                   int point_index,
                                   int num_trials,
                                   int num_threads,
                                   uint64_t base_seed,
                                   const EvaluationProgressCallback& progress) {
  simulation.Check();
  options.Check();
  if (num_trials < 0) {
    throw std::invalid_argument("num_trials must be >= 0, got " +
                                std::to_string(num_trials));
  }
  if (num_threads < 1) {
    throw std::invalid_argument("num_threads must be >= 1, got " +
                                std::to_string(num_threads));
  }
  std::vector<TrialResult> trials(num_trials);
  std::atomic<int> next{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;  // guards `finished`, `first_error` and the callback
  int finished = 0;
  std::exception_ptr first_error;
  auto worker = [&]() {
    while (!stop.load()) {
      const int t = next.fetch_add(1);
      if (t >= num_trials) return;
      try {
        const uint64_t seed = TrialSeed(base_seed, sweep_name, point_index, t);
        std::mt19937_64 rng(seed);
        const PaperSimulation data = SimulatePaperMotions(simulation, &rng);
        trials[t] = EvaluateTrial(data, options, seed);
        const std::lock_guard<std::mutex> lock(mutex);
        ++finished;
        if (progress) progress(finished, num_trials);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!first_error) first_error = std::current_exception();
        stop.store(true);
        return;
      }
    }
  };
  const int num_workers = std::min(num_threads, std::max(1, num_trials));
  std::vector<std::thread> threads;
  for (int k = 1; k < num_workers; ++k) threads.emplace_back(worker);
  worker();
  for (std::thread& thread : threads) thread.join();
  if (first_error) std::rethrow_exception(first_error);
  return trials;
}

SweepPointResult RunSweepPoint(const PaperSimulationOptions& simulation,
                               const EvaluationOptions& options,
                               const std::string& sweep_name,
                               int point_index,
                               double value,
                               int num_trials,
                               int num_threads,
                               uint64_t base_seed,
                               const EvaluationProgressCallback& progress) {
  const std::vector<TrialResult> trials = RunTrials(simulation,
                                                    options,
                                                    sweep_name,
                                                    point_index,
                                                    num_trials,
                                                    num_threads,
                                                    base_seed,
                                                    progress);
  SweepPointResult result = SummarizeTrials(value, trials);
  for (const TrialResult& trial : trials) {
    result.num_dropped_motions += simulation.num_motions - trial.num_pairs;
  }
  return result;
}

}  // namespace odomcal
