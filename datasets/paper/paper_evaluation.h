// The Monte Carlo evaluation of Guo, Mirzaei & Roumeliotis (ICRA 2012),
// Section V (Fig. 2, Table I): per trial, every method estimates
// odom_from_cam and the metric scale(s) from one PaperSimulation; errors
// against the truth are aggregated into RMSEs and divergence rates.
//
// Methods (EvaluationMethod):
//   ALS        closed form, camera translations as measured (kAls)
//   ALSP-L     closed form, length-preserving plane projection
//              (`--alsp_projection length_preserving`)
//   ALSP-orth  closed form, the paper's orthogonal projection (== ALS, see
//              calibration_options.h; kept to measure that): what the CLI's
//              `--method alsp` computes by default
//   CM         Chang et al., minimal solution + RANSAC with a fixed budget
//              (chang_baseline.h)
//   ALS-B, ALSP-L-B, CM-B   batch refinement (RefineOdomFromCam) started
//              at ALS, ALSP-L, CM
//   GT-B       batch refinement started at the truth
// The closed forms use all pairs (no outlier rejection besides CM's own
// RANSAC), the B methods as EvaluationOptions::batch_refinement says (the
// paper's: every motion, no robust loss; the default: an inlier test); the
// refinement weighs each pair by its odom_covariance and cam_covariance and
// holds translation z at its true value (unobservable under planar motion),
// as do the closed forms.
//
// Errors of an estimate (q_hat, p_hat, s_hat) against the truth (q, p, s):
//   rotation_deg  = angle of dq = q_hat^-1 ⊗ q, in degrees (the paper's
//                   "tilt angle" |delta theta| with dq ~ [delta theta / 2, 1])
//   translation_m = |p_hat.xy - p.xy|
//   scale_rel     = RMS over segments of (s_hat_k - s_k) / s_k
// Divergence (Table I), B methods only: with C the inverse of the
// refinement's information (order [rx, ry, rz, tx, ty, s_k...], rotation a
// left perturbation R = Exp(phi) R_hat), the error
//   e = [Log(q ⊗ q_hat^-1), p.xy - p_hat.xy, s - s_hat]
// is a divergence when |e_k| > 3 sqrt(C_kk) for any k (C widened by the
// trial's variance factor unless EvaluationOptions::variance_factor is
// off). (For a consistent Gaussian estimate this happens by chance with
// probability up to 1 - 0.9973^(5+K), 1.6 % for one segment.)
//
// A method that returns no estimate (closed form or CM failing, refinement
// not usable, or a B method whose start failed) is a failure: counted, and
// left out of the RMSEs, never counted as zero error.
#pragma once

#include "odomcal/datasets/paper/paper_simulation.h"
#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/hand_eye_refine.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace odomcal {

enum class EvaluationMethod {
  kAls,
  kAlspLengthPreserving,
  kAlspOrthogonal,
  kCm,
  kAlsB,
  kAlspLengthPreservingB,
  kCmB,
  kGtB,
};
constexpr int kNumEvaluationMethods = 8;

// "ALS", "ALSP-L", "ALSP-orth", "CM", "ALS-B", "ALSP-L-B", "CM-B", "GT-B".
std::string ToString(EvaluationMethod method);
bool IsBatchMethod(EvaluationMethod method);
// All methods in the order above.
std::array<EvaluationMethod, kNumEvaluationMethods> AllEvaluationMethods();

// How the B methods refine (W_i, the weights, are evaluated at the start of
// each refinement: hand_eye_refine.h).
enum class BatchRefinement {
  // One refinement from the method's start on every motion: the paper's.
  kPaper,
  // Rounds: first from the start on every motion with a Cauchy loss
  // (robust_loss_scale 3 whitened units), then from each result, with the
  // weights evaluated there and no loss, on the motions that pass odomcal's
  // final inlier test at it (IsWithinNoise: chi-square, 6 dof, 99.9 %,
  // under the motions' own covariances), until a round keeps the motions of
  // the one before (at most 6 refinements). A round whose test keeps fewer
  // than half of the motions (or fewer than 3) is not trusted; when no round
  // is, the result is one refinement without loss on every motion from the
  // robust one. So the result, its information and the divergence test
  // always come from a refinement without loss. Similar to odomcal's final
  // inlier test (noise_refinement.h) without its noise estimation. The first
  // loss keeps a grossly wrong camera direction, whose length is exact
  // (paper_simulation.h), from pulling the estimate so far that it passes
  // the test and good motions fail it; the later rounds make the estimate
  // independent of where the weights were first evaluated (GT-B's start is
  // the truth).
  kInlierRounds,
};

// The B methods' refinement of `pairs` from (start, start_scales): the
// refinement kept (usable: see its field) and the motions it used.
// `options` is the refinement's (no robust loss; the first inlier round
// adds the Cauchy loss). The inlier rounds test the motions of
// `inlier_test_pairs` (the same motions, other covariances) when given.
struct BatchRefined {
  RefinementResult refinement;
  std::vector<int> used;
};
BatchRefined RefineBatch(const MotionPairs& pairs,
                         const Rigid3d& start,
                         const std::vector<double>& start_scales,
                         const CalibrationOptions& options,
                         BatchRefinement batch,
                         const MotionPairs* inlier_test_pairs = nullptr);

// The a posteriori variance factor of a refinement without loss on
// `num_motions_used` motions: its chi-square 2 * final_cost over the degrees
// of freedom, 6 per motion minus the 5 + K parameters (K scales); about 1
// when the motions scatter as their covariances say, k^2 when they scatter k
// times wider. NaN without degrees of freedom.
double PosteriorVarianceFactor(const RefinementResult& refined,
                               int num_motions_used);

// "paper", "inlier_rounds"; FromString throws std::invalid_argument.
std::string ToString(BatchRefinement batch);
BatchRefinement BatchRefinementFromString(const std::string& text);

struct EvaluationOptions {
  // CM's RANSAC: a fixed number of minimal samples (no adaptive stopping).
  int cm_ransac_iterations = 200;
  int max_refinement_iterations = 100;
  BatchRefinement batch_refinement = BatchRefinement::kInlierRounds;
  // The divergence test's covariance C scaled by the trial's
  // PosteriorVarianceFactor f when f > 1: a trial whose motions scatter
  // wider than their (first-order) covariances say is tested against what
  // its residuals show, as odomcal's own calibration estimates its noise
  // from the data. Never narrowed (f < 1 keeps C), and the estimate is
  // unchanged. false: the paper's test on C alone.
  bool variance_factor = true;
  // The inlier rounds test each motion under its core camera covariance
  // (PaperSimulation::cam_core_covariances, before the two-view direction
  // scan) and weight it with the full one: a motion whose residual puts its
  // truth outside the core sits in the wide part of a far from Gaussian
  // error, where its estimate pulls the batch rather than informs it.
  // false: tested and weighted with the full covariance.
  bool inlier_test_on_core_covariance = true;
  void Check() const;  // throws std::invalid_argument naming the field
};

struct MethodError {
  bool failed = false;
  double rotation_deg = 0.0;
  double translation_m = 0.0;
  double scale_rel = 0.0;
  // B methods: whether the information was invertible, and the divergence
  // test's outcome (false when there is no covariance).
  bool has_covariance = false;
  bool diverged = false;
  int num_pairs_used = 0;  // B methods: the motions of the final refinement
};

struct TrialResult {
  std::array<MethodError, kNumEvaluationMethods> methods;
  int num_pairs = 0;  // after dropped two-view failures
  const MethodError& operator[](EvaluationMethod method) const {
    return methods[static_cast<int>(method)];
  }
};

// Runs every method on `simulation`; `seed` drives CM's RANSAC.
TrialResult EvaluateTrial(const PaperSimulation& simulation,
                          const EvaluationOptions& options,
                          uint64_t seed);

struct MethodSummary {
  int num_trials = 0;
  int num_failures = 0;
  // Over the trials without failure; NaN when there are none.
  double rmse_rotation_deg = 0.0;
  double rmse_translation_m = 0.0;
  double rmse_scale_rel = 0.0;
  // B methods: trials with a covariance, divergences among them, and their
  // ratio (NaN for the other methods or without any covariance).
  int num_with_covariance = 0;
  int num_divergences = 0;
  double divergence_rate = 0.0;
  // B methods: the mean fraction of a trial's motions in the final
  // refinement (1 with BatchRefinement::kPaper); NaN for the other methods.
  double motions_used = 0.0;
};

struct SweepPointResult {
  double value = 0.0;  // the swept parameter's value
  int num_trials = 0;
  int num_dropped_motions = 0;  // two-view failures over all trials
  std::array<MethodSummary, kNumEvaluationMethods> methods;
  const MethodSummary& operator[](EvaluationMethod method) const {
    return methods[static_cast<int>(method)];
  }
};

// Aggregates trials (in their order) into a sweep point.
SweepPointResult SummarizeTrials(double value,
                                 const std::vector<TrialResult>& trials);

// Seed of one trial, a hash of (base seed, sweep name, point index, trial
// index): independent of the thread count and of the other sweeps.
uint64_t TrialSeed(uint64_t base_seed,
                   const std::string& sweep_name,
                   int point_index,
                   int trial_index);

// Called after each finished trial with (finished, total), from the worker
// threads, one call at a time.
using EvaluationProgressCallback = std::function<void(int, int)>;

// Runs num_trials trials of `simulation` on num_threads std::threads; trial
// t simulates with std::mt19937_64(TrialSeed(...)) and evaluates with a
// seed derived from it. Results do not depend on num_threads. Throws
// std::invalid_argument for invalid options; rethrows the first exception a
// worker raised.
SweepPointResult RunSweepPoint(
    const PaperSimulationOptions& simulation,
    const EvaluationOptions& options,
    const std::string& sweep_name,
    int point_index,
    double value,
    int num_trials,
    int num_threads,
    uint64_t base_seed,
    const EvaluationProgressCallback& progress = nullptr);

// The per-trial results behind RunSweepPoint (same seeds), in trial order.
std::vector<TrialResult> RunTrials(
    const PaperSimulationOptions& simulation,
    const EvaluationOptions& options,
    const std::string& sweep_name,
    int point_index,
    int num_trials,
    int num_threads,
    uint64_t base_seed,
    const EvaluationProgressCallback& progress = nullptr);

}  // namespace odomcal
