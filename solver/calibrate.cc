// CalibrateOdomCam(): validation, excitation and consistency diagnostics,
// pair selection, closed form, refinement, covariance and observability,
// residuals. Each refusal returns early with a status that names the cause.

#include "odomcal/solver/calibrate.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate_translation_z_internal.h"
#include "odomcal/solver/covariance_analysis_internal.h"
#include "odomcal/solver/hand_eye_linear.h"
#include "odomcal/solver/hand_eye_ransac.h"
#include "odomcal/solver/hand_eye_refine.h"
#include "odomcal/solver/hand_eye_residual.h"
#include "odomcal/solver/noise_refinement.h"
#include "odomcal/solver/planarity_check.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace odomcal {
namespace {

using internal::AnalyseInformation;
using internal::EstimateTranslationZ;
using internal::EstimateTranslationZUnderPrior;
using internal::InvertInformation;
using internal::MarginalInformationOfLast;
using internal::OdometryTilts;

// Odometry steps all shorter than this are rotation in place: a robot turning
// on the spot reports (close to) zero translation, a forward step is
// centimetres long.
constexpr double kMinOdometryStepM = 1e-3;

std::string Join(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) {
    joined += (joined.empty() ? "" : ", ") + name;
  }
  return joined;
}

std::string FormatDouble(double value, int precision = 3) {
  std::ostringstream stream;
  stream.precision(precision);
  stream << value;
  return stream.str();
}

void ValidatePairs(const MotionPairs& pairs) {
  for (size_t i = 0; i < pairs.size(); ++i) {
    const MotionPair& pair = pairs[i];
    const std::string where = "motion pair " + std::to_string(i);
    if (!IsFinite(pair.odom_i_from_odom_j) ||
        !IsFinite(pair.cam_i_from_cam_j)) {
      throw std::invalid_argument(where + " has a non-finite value");
    }
    // Least squares squares the translations; beyond ~1e154 that overflows.
    if (!std::isfinite(pair.odom_i_from_odom_j.translation.squaredNorm()) ||
        !std::isfinite(pair.cam_i_from_cam_j.translation.squaredNorm())) {
      throw std::invalid_argument(where +
                                  " has a translation too large to square in "
                                  "double precision (check the units)");
    }
    if (std::abs(pair.odom_i_from_odom_j.rotation.norm() - 1.0) > 1e-6 ||
        std::abs(pair.cam_i_from_cam_j.rotation.norm() - 1.0) > 1e-6) {
      throw std::invalid_argument(where + " has a non-unit quaternion");
    }
    if (pair.segment < 0) {
      throw std::invalid_argument(where + " has a negative segment index " +
                                  std::to_string(pair.segment));
    }
    for (const auto* covariance : {&pair.odom_covariance,
                                   &pair.cam_covariance,
                                   &pair.odom_interpolation_covariance}) {
      if (*covariance && !(*covariance)->allFinite()) {
        throw std::invalid_argument(where + " has a non-finite covariance");
      }
    }
  }
}

double YawDeg(const MotionPair& pair) {
  return LogRotation(pair.odom_i_from_odom_j.rotation).z() * kRadToDeg;
}

void MeasureExcitation(const MotionPairs& pairs,
                       const CalibrationOptions& options,
                       CalibrationDiagnostics* diagnostics) {
  std::vector<double> yaws;
  for (const MotionPair& pair : pairs) yaws.push_back(YawDeg(pair));
  if (yaws.empty()) return;
  diagnostics->yaw_increment_min_deg =
      *std::min_element(yaws.begin(), yaws.end());
  diagnostics->yaw_increment_max_deg =
      *std::max_element(yaws.begin(), yaws.end());
  const double mean =
      std::accumulate(yaws.begin(), yaws.end(), 0.0) / yaws.size();
  double variance = 0.0;
  for (const double yaw : yaws) variance += (yaw - mean) * (yaw - mean);
  diagnostics->yaw_increment_stddev_deg = std::sqrt(variance / yaws.size());
  for (const double yaw : yaws) {
    diagnostics->num_left_turns += yaw >= options.min_rotation_deg;
    diagnostics->num_right_turns += yaw <= -options.min_rotation_deg;
  }
  diagnostics->num_rotating_pairs =
      diagnostics->num_left_turns + diagnostics->num_right_turns;

  // The rotation angle is invariant under conjugation by the extrinsic.
  for (const MotionPair& pair : pairs) {
    const double mismatch =
        std::abs(RotationAngle(pair.odom_i_from_odom_j.rotation) -
                 RotationAngle(pair.cam_i_from_cam_j.rotation)) *
        kRadToDeg;
    diagnostics->angle_mismatch_deg.push_back(mismatch);
    diagnostics->num_angle_mismatches +=
        mismatch > options.max_angle_mismatch_deg;
  }
}

// Planar odometry sees neither the ground's tilt nor its mean over the
// drive, which moves the extrinsic as a whole (GroundTiltCovariance): its
// covariance joins the information's inverse, for a camera height of the
// held z within its prior's 2 sigma. Named when it widens roll or pitch beyond
// their standard deviations without it.
void AddGroundTiltCovariance(const CalibrationOptions& options,
                             PlanarityCheck* check,
                             Eigen::MatrixXd* information,
                             CalibrationResult* result) {
  const Eigen::Index n = information->rows();
  if (n < 5 || !information->allFinite()) return;
  // Inverted at unit diagonal: the scales' rows differ by orders of
  // magnitude from the rotation's.
  const Eigen::VectorXd diagonal = information->diagonal();
  if (!(diagonal.minCoeff() > 0.0)) return;
  const Eigen::VectorXd unit = diagonal.cwiseSqrt().cwiseInverse();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(unit.asDiagonal() * *information *
                                          unit.asDiagonal());
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return;
  Eigen::MatrixXd covariance = unit.asDiagonal() *
                               ldlt.solve(Eigen::MatrixXd::Identity(n, n)) *
                               unit.asDiagonal();
  if (!covariance.allFinite()) return;
  // The camera's height at the prior's 2 sigma bound: its second moment
  // (1 m^2 under the default prior) would cover a car's roof camera (1.65 m)
  // in x and y under a tilt of one standard deviation only.
  const double height = options.fixed_translation_z_m;
  const double height_bound =
      std::abs(height) + 2.0 * options.translation_z_prior_sigma_m;
  const Eigen::Matrix4d ground =
      GroundTiltCovariance(*check, height, height_bound * height_bound);
  const Eigen::Index index[4] = {0, 1, 3, 4};  // rx, ry, tx, ty
  const Eigen::Vector2d before_deg(std::sqrt(covariance(0, 0)) * kRadToDeg,
                                   std::sqrt(covariance(1, 1)) * kRadToDeg);
  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b < 4; ++b) covariance(index[a], index[b]) += ground(a, b);
  }
  const Eigen::Vector2d after_deg(std::sqrt(covariance(0, 0)) * kRadToDeg,
                                  std::sqrt(covariance(1, 1)) * kRadToDeg);
  const Eigen::VectorXd diagonal_after = covariance.diagonal();
  const Eigen::VectorXd unit_after = diagonal_after.cwiseSqrt().cwiseInverse();
  *information =
      unit_after.asDiagonal() *
      (unit_after.asDiagonal() * covariance * unit_after.asDiagonal())
          .ldlt()
          .solve(Eigen::MatrixXd::Identity(n, n)) *
      unit_after.asDiagonal();
  check->ground_named = check->ground_roll_rms_deg > before_deg(0) ||
                        check->ground_pitch_rms_deg > before_deg(1);
  if (check->ground_named) {
    result->warnings.push_back(
        GroundTiltWarning(*check, before_deg, after_deg));
  }
}

// The held z's prior joins the data's information (z last); then the
// scale's wander inside a segment, which one scale per segment does not
// follow (scale_drift_covariance.h), joins its covariance.
void AddZPriorAndScaleDrift(const MotionPairs& weighted_pairs,
                            const std::vector<int>& used,
                            const CalibrationOptions& options,
                            const CalibrationOptions& weighted,
                            const std::vector<int>& information_segments,
                            Eigen::MatrixXd* information,
                            CalibrationResult* result) {
  TranslationZPrior& z_prior = result->translation_z_prior;
  double z_prior_information = 0.0;
  if (z_prior.moved_by_data) {
    const Eigen::Index z = information->rows() - 1;
    z_prior.data_stddev_m =
        1.0 / std::sqrt(MarginalInformationOfLast(*information));
    z_prior_information = 1.0 / (options.translation_z_prior_sigma_m *
                                 options.translation_z_prior_sigma_m);
    (*information)(z, z) += z_prior_information;
  }
  CalibrationDiagnostics& d = result->diagnostics;
  if (!d.refined) return;
  d.scale_drift = AddScaleDriftCovariance(weighted_pairs,
                                          used,
                                          result->odom_from_cam,
                                          result->metric_scales,
                                          weighted,
                                          information_segments,
                                          z_prior_information,
                                          information);
  if (d.scale_drift.named) {
    result->warnings.push_back(ScaleDriftWarning(d.scale_drift));
  }
}

void ComputeResiduals(const MotionPairs& pairs,
                      const std::vector<int>& used,
                      const CalibrationOptions& options,
                      CalibrationResult* result) {
  CalibrationDiagnostics& d = result->diagnostics;
  d.rotation_residual_deg.assign(pairs.size(), 0.0);
  d.translation_residual_m.assign(pairs.size(), 0.0);
  for (size_t i = 0; i < pairs.size(); ++i) {
    const double scale = result->metric_scales[pairs[i].segment];
    if (!std::isfinite(scale)) continue;
    const PairError error =
        EvaluatePair(pairs[i], result->odom_from_cam, scale);
    d.rotation_residual_deg[i] = error.rotation_deg;
    d.translation_residual_m[i] = error.translation_m;
  }
  double sum_rot2 = 0.0, sum_t2 = 0.0, sum_step2 = 0.0, chi2 = 0.0;
  for (const int i : used) {
    const MotionPair& pair = pairs[i];
    const double scale = result->metric_scales[pair.segment];
    sum_rot2 += d.rotation_residual_deg[i] * d.rotation_residual_deg[i];
    sum_t2 += d.translation_residual_m[i] * d.translation_residual_m[i];
    sum_step2 += pair.odom_i_from_odom_j.translation.squaredNorm();
    d.max_rotation_residual_deg =
        std::max(d.max_rotation_residual_deg, d.rotation_residual_deg[i]);
    d.max_translation_residual_m =
        std::max(d.max_translation_residual_m, d.translation_residual_m[i]);
    chi2 += (HandEyeSqrtInformation(
                 pair, result->odom_from_cam, scale, options.noise) *
             HandEyeResidual(pair, result->odom_from_cam, scale))
                .squaredNorm();
  }
  const double count = static_cast<double>(std::max<size_t>(1, used.size()));
  d.rms_rotation_residual_deg = std::sqrt(sum_rot2 / count);
  d.rms_translation_residual_m = std::sqrt(sum_t2 / count);
  d.relative_translation_residual =
      sum_step2 > 0.0 ? std::sqrt(sum_t2 / sum_step2) : 0.0;
  const bool z_free =
      result->observability.translation_z == Determination::kEstimated ||
      result->translation_z_prior.moved_by_data;
  const double dof =
      6.0 * used.size() - (5.0 + d.num_pairs_per_segment.size() + z_free);
  d.reduced_chi_square = dof > 0.0 ? chi2 / dof : 0.0;
}

// The refinement estimates the noise and makes the final inlier test
// (noise_refinement.h).
bool EstimatesNoise(const CalibrationOptions& options) {
  return options.estimate_noise && options.refine;
}

// Used pairs per segment; a segment left without pairs is undetermined.
void CountPairsPerSegment(const MotionPairs& pairs,
                          const std::vector<int>& used,
                          CalibrationResult* result) {
  std::vector<int>& count = result->diagnostics.num_pairs_per_segment;
  count.assign(count.size(), 0);
  for (const int i : used) ++count[pairs[i].segment];
  for (size_t k = 0; k < count.size(); ++k) {
    if (count[k] == 0) {
      result->observability.metric_scales[k] = Determination::kUndetermined;
    }
  }
}

CalibrationResult Refuse(CalibrationResult result,
                         CalibrationStatus status,
                         const std::string& message) {
  result.status = status;
  result.message = message;
  return result;
}

}  // namespace

CalibrationResult CalibrateOdomCam(const MotionPairs& pairs,
                                   const CalibrationOptions& options) {
  options.Check();
  ValidatePairs(pairs);

  CalibrationResult result;
  CalibrationDiagnostics& d = result.diagnostics;
  const int num_pairs = static_cast<int>(pairs.size());
  auto TooFewInliers = [num_pairs](const std::vector<int>& inliers) {
    return "only " + std::to_string(inliers.size()) + " of " +
           std::to_string(num_pairs) +
           " motion pairs agree on one extrinsic (RANSAC); check the pose "
           "convention (world_from_cam), the time association and the noise "
           "parameters";
  };
  const int num_segments = NumSegments(pairs);
  result.observability.metric_scales.assign(num_segments,
                                            Determination::kEstimated);
  d.num_pairs_in = num_pairs;
  d.inlier_mask.assign(pairs.size(), 0);
  TranslationZPrior& z_prior = result.translation_z_prior;
  z_prior.used = options.translation_z_prior_sigma_m > 0.0;
  z_prior.held_m = options.fixed_translation_z_m;
  z_prior.prior_stddev_m = options.translation_z_prior_sigma_m;
  z_prior.data_stddev_m = std::numeric_limits<double>::infinity();
  z_prior.estimate_m = options.fixed_translation_z_m;
  z_prior.stddev_m = options.translation_z_prior_sigma_m;
  MeasureExcitation(pairs, options, &d);

  if (num_pairs < options.min_num_pairs) {
    return Refuse(result,
                  CalibrationStatus::kNotEnoughMotion,
                  "only " + std::to_string(num_pairs) +
                      " motion pairs; at least " +
                      std::to_string(options.min_num_pairs) + " are needed");
  }
  if (d.num_rotating_pairs == 0) {
    result.observability = Observability::Nothing(0);
    return Refuse(
        result,
        CalibrationStatus::kUnobservable,
        "no motion pair rotates by more than " +
            FormatDouble(options.min_rotation_deg) +
            " deg (straight driving or no motion): the rotation and the x/y "
            "translation of the extrinsic cannot be determined; drive turns "
            "in both directions");
  }
  if (d.num_rotating_pairs < options.min_num_rotating_pairs) {
    return Refuse(result,
                  CalibrationStatus::kNotEnoughMotion,
                  "only " + std::to_string(d.num_rotating_pairs) +
                      " motion pairs rotate by more than " +
                      FormatDouble(options.min_rotation_deg) + " deg; " +
                      std::to_string(options.min_num_rotating_pairs) +
                      " are needed");
  }
  if (2 * d.num_angle_mismatches > num_pairs) {
    return Refuse(
        result,
        CalibrationStatus::kInconsistentData,
        std::to_string(d.num_angle_mismatches) + " of " +
            std::to_string(num_pairs) +
            " pairs have camera and odometry rotation angles differing by "
            "more than " +
            FormatDouble(options.max_angle_mismatch_deg) +
            " deg, which no extrinsic can explain: check the time "
            "association (clock offset, time unit) and the pose inputs");
  }

  // Turning on the spot: the camera's circle gives the lever arm only in
  // reconstruction units, so the lever arm and the scale trade off (and
  // RANSAC's minimal samples all fail, which would read as inconsistency).
  double max_step_m = 0.0;
  for (const MotionPair& pair : pairs) {
    max_step_m =
        std::max(max_step_m, pair.odom_i_from_odom_j.translation.norm());
  }
  if (max_step_m < kMinOdometryStepM) {
    result.observability = Observability::Nothing(num_segments);
    result.observability.rotation = Determination::kEstimated;
    return Refuse(result,
                  CalibrationStatus::kUnobservable,
                  "the odometry never translates (largest step " +
                      FormatDouble(max_step_m) +
                      " m: rotation in place only): the metric scale and the "
                      "x/y translation cannot be determined; drive forward "
                      "while turning");
  }

  // Pair selection.
  std::vector<int> all(pairs.size());
  std::iota(all.begin(), all.end(), 0);
  std::vector<int> used;
  if (options.use_ransac) {
    const RansacResult ransac = RansacOdomFromCam(pairs, all, options);
    d.ransac_num_iterations = ransac.num_iterations;
    if (!ransac.success || ransac.num_inliers < options.min_num_pairs) {
      return Refuse(result,
                    CalibrationStatus::kInconsistentData,
                    "RANSAC found no consistent set of at least " +
                        std::to_string(options.min_num_pairs) +
                        " motion pairs");
    }
    for (int i = 0; i < num_pairs; ++i) {
      if (ransac.inlier_mask[i]) used.push_back(i);
    }
    // With the noise estimated from the data, the final inlier test decides
    // (RANSAC's choice under a given noise that is too small is partial).
    if (ransac.num_inliers < options.ransac_min_inlier_ratio * num_pairs &&
        !EstimatesNoise(options)) {
      for (const int i : used) d.inlier_mask[i] = 1;
      return Refuse(
          result, CalibrationStatus::kInconsistentData, TooFewInliers(used));
    }
  } else {
    used = all;
  }

  // Closed form.
  LinearOptions linear_options;
  linear_options.method = options.method;
  linear_options.alsp_projection = options.alsp_projection;
  linear_options.fixed_translation_z_m = options.fixed_translation_z_m;
  const LinearEstimate linear =
      EstimateOdomFromCamLinear(pairs, used, linear_options);
  d.rotation_step_eigenvalues = linear.rotation_step_eigenvalues;
  d.rotation_step_ratio = linear.rotation_step_ratio;
  d.rotation_step_gimbal = linear.rotation_step_gimbal;
  d.translation_step_condition_number =
      linear.translation_step_condition_number;
  if (!linear.success) {
    result.observability = Observability::Nothing(0);
    return Refuse(result,
                  CalibrationStatus::kUnobservable,
                  "closed form failed: " + linear.failure);
  }
  // Finite inputs can still overflow inside the least squares: a closed form
  // that is not finite is no estimate, whatever the solver reported.
  bool linear_finite = IsFinite(linear.odom_from_cam);
  for (const int i : used) {
    const size_t segment = static_cast<size_t>(pairs[i].segment);
    linear_finite &= segment < linear.metric_scales.size() &&
                     std::isfinite(linear.metric_scales[segment]);
  }
  if (!linear_finite) {
    result.observability = Observability::Nothing(num_segments);
    return Refuse(result,
                  CalibrationStatus::kUnobservable,
                  "the closed form is not finite (numerical overflow): the "
                  "rotation, translation and metric scale cannot be "
                  "determined; check the units of the translations");
  }
  d.linear_odom_from_cam = linear.odom_from_cam;
  d.linear_metric_scales = linear.metric_scales;
  result.odom_from_cam = linear.odom_from_cam;
  result.metric_scales = linear.metric_scales;
  result.metric_scales.resize(num_segments, std::nan(""));
  result.has_estimate = true;

  d.num_pairs_per_segment.assign(num_segments, 0);
  for (const int i : used) ++d.num_pairs_per_segment[pairs[i].segment];
  for (int k = 0; k < num_segments; ++k) {
    if (d.num_pairs_per_segment[k] == 0) {
      result.observability.metric_scales[k] = Determination::kUndetermined;
    } else if (!(result.metric_scales[k] > 0.0)) {
      return Refuse(result,
                    CalibrationStatus::kInconsistentData,
                    "segment " + std::to_string(k) +
                        " has a non-positive metric scale (" +
                        FormatDouble(result.metric_scales[k]) +
                        "): its camera moves against the odometry");
    }
  }

  // Refinement.
  std::vector<int> information_segments;
  Eigen::MatrixXd information;
  // With the noise estimated from the data, everything below weighs the
  // pairs with it: `weighted_pairs` / `weighted` (covariances scaled). The
  // scaled copy is made only then: at 10 000 pairs a copy is 12 MB.
  std::optional<MotionPairs> scaled_pairs;
  CalibrationOptions weighted = options;
  if (options.refine) {
    RefinementResult refined;
    if (EstimatesNoise(options)) {
      const NoiseRefinement noise_refinement = RefineWithNoiseEstimation(
          pairs, used, result.odom_from_cam, result.metric_scales, options);
      refined = noise_refinement.refinement;
      if (refined.usable) {
        used = noise_refinement.used;
        result.noise_estimate = noise_refinement.noise;
        weighted.noise = noise_refinement.noise.noise;
        scaled_pairs = ScaleCovariances(pairs, noise_refinement.noise);
        CountPairsPerSegment(pairs, used, &result);
      }
      if (used.size() < options.ransac_min_inlier_ratio * num_pairs) {
        for (const int i : used) d.inlier_mask[i] = 1;
        return Refuse(result,
                      CalibrationStatus::kInconsistentData,
                      TooFewInliers(used) +
                          " (under the noise estimated "
                          "from the data)");
      }
    } else {
      refined = RefineOdomFromCam(
          pairs, used, result.odom_from_cam, result.metric_scales, options);
    }
    d.refinement_report = refined.report;
    d.refinement_num_iterations = refined.num_iterations;
    bool refined_finite = IsFinite(refined.odom_from_cam);
    for (const int i : used) {
      refined_finite &= std::isfinite(refined.metric_scales[pairs[i].segment]);
    }
    if (!refined.usable || !refined_finite) {
      result.status = CalibrationStatus::kRefinementFailed;
      result.message = "refinement failed (" + refined.report +
                       "); the closed-form estimate is reported";
    } else {
      d.refined = true;
      result.odom_from_cam = refined.odom_from_cam;
      result.metric_scales = refined.metric_scales;
      information = refined.information;
      information_segments = refined.information_segments;
    }
  }
  const MotionPairs& weighted_pairs = scaled_pairs ? *scaled_pairs : pairs;
  if (information.size() == 0) {
    information = HandEyeInformation(weighted_pairs,
                                     used,
                                     result.odom_from_cam,
                                     result.metric_scales,
                                     weighted,
                                     &information_segments);
  }
  // SE(3) odometry: z may be determined as well.
  if (result.status != CalibrationStatus::kRefinementFailed &&
      OdometryTilts(pairs, used)) {
    if (!EstimateTranslationZ(weighted_pairs,
                              &used,
                              weighted,
                              &result,
                              &information,
                              &information_segments)) {
      EstimateTranslationZUnderPrior(weighted_pairs,
                                     &used,
                                     weighted,
                                     &result,
                                     &information,
                                     &information_segments);
    }
    CountPairsPerSegment(pairs, used, &result);
  }
  for (const int i : used) d.inlier_mask[i] = 1;
  d.num_pairs_used = static_cast<int>(used.size());
  // The weights are estimated, not known: widen for their uncertainty (after
  // the z step, which replaces the information for SE(3) odometry).
  if (result.noise_estimate && d.refined) {
    information =
        WidenForEstimatedNoise(information,
                               information_segments,
                               *result.noise_estimate,
                               &result.noise_estimate->stddev_widening);
    const double misfit = result.noise_estimate->misfit_widening;
    information /= misfit * misfit;
  }

  ComputeResiduals(weighted_pairs, used, weighted, &result);
  // Planar odometry cannot see slopes: a camera motion that leaves the plane
  // biases roll/pitch and x/y beyond the planar covariance. Named, and the
  // covariance inflated by the measured excess (planarity_check.h) before
  // the standard deviations are tested against their limits.
  // The check uses the camera's estimated noise level in the given shape:
  // its shape components (translation across the motion, which includes the
  // vertical) could otherwise take the form of the slope and hide it. The
  // odometry's components stay as estimated: of a planar log only the
  // constant translation part reaches the height, and no slope (a height
  // proportional to the step) can take its form.
  NoiseModel planarity_noise = weighted.noise;
  if (result.noise_estimate) {
    planarity_noise =
        ScaleNoise(options.noise, result.noise_estimate->variance_factors);
    planarity_noise.odom_yaw_sigma_deg = weighted.noise.odom_yaw_sigma_deg;
    planarity_noise.odom_yaw_sigma_rel = weighted.noise.odom_yaw_sigma_rel;
    planarity_noise.odom_translation_sigma_m =
        weighted.noise.odom_translation_sigma_m;
    planarity_noise.odom_translation_sigma_rel =
        weighted.noise.odom_translation_sigma_rel;
  }
  // The tilt noise is the assumption under test: as given, not scaled with
  // the odometry rotation's (yaw-dominated) level.
  planarity_noise.odom_tilt_sigma_deg = options.noise.odom_tilt_sigma_deg;
  d.planarity = CheckPlanarity(weighted_pairs,
                               used,
                               result.odom_from_cam,
                               result.metric_scales,
                               planarity_noise);
  if (d.planarity.checked && !d.planarity.consistent) {
    if (d.planarity.named) {
      // Seconds since the drive's start: the earliest pair of any segment.
      int64_t first_stamp_ns = pairs.front().stamp_i_ns;
      for (const MotionPair& pair : pairs)
        first_stamp_ns = std::min(first_stamp_ns, pair.stamp_i_ns);
      result.warnings.push_back(PlanarityWarning(d.planarity, first_stamp_ns));
    }
    information /= d.planarity.covariance_inflation;
  }
  if (d.planarity.checked && d.planarity.ground_tilt_seen) {
    AddGroundTiltCovariance(options, &d.planarity, &information, &result);
  }
  AddZPriorAndScaleDrift(weighted_pairs,
                         used,
                         options,
                         weighted,
                         information_segments,
                         &information,
                         &result);
  AnalyseInformation(
      information, information_segments, num_segments, options, &result);
  if (result.observability.translation_z == Determination::kEstimated) {
    z_prior.used = false;
  } else if (z_prior.moved_by_data) {
    z_prior.estimate_m = result.odom_from_cam.translation.z();
    z_prior.stddev_m = result.stddev_translation_z_m;
  }

  // Warnings a user should read even when the answer is usable.
  if (num_pairs - d.num_pairs_used > 0) {
    result.warnings.push_back(std::to_string(num_pairs - d.num_pairs_used) +
                              " of " + std::to_string(num_pairs) +
                              " motion pairs rejected as outliers");
  }
  if (d.num_angle_mismatches > 0) {
    result.warnings.push_back(
        std::to_string(d.num_angle_mismatches) +
        " pairs have camera/odometry rotation angles differing by more than " +
        FormatDouble(options.max_angle_mismatch_deg) + " deg");
  }
  if (d.num_left_turns == 0 || d.num_right_turns == 0) {
    result.warnings.push_back("all turns are in one direction");
  }
  if (d.reduced_chi_square > 4.0) {
    result.warnings.push_back(
        "residuals are " + FormatDouble(std::sqrt(d.reduced_chi_square), 2) +
        "x larger than the noise model predicts: the standard deviations are "
        "optimistic; raise the noise parameters");
  }

  if (result.status == CalibrationStatus::kRefinementFailed) {
    return result;
  }
  if (d.relative_translation_residual >
      options.max_relative_translation_residual) {
    return Refuse(
        result,
        CalibrationStatus::kInconsistentData,
        "post-fit translation residuals are " +
            FormatDouble(100.0 * d.relative_translation_residual, 3) +
            " % of the odometry step lengths: the camera poses do not fit "
            "any extrinsic (are they cam_from_world instead of "
            "world_from_cam? is the time association right?)");
  }
  // With several segments, one segment's undetermined scale does not make
  // the extrinsic or the other scales wrong: it is reported (null in the
  // outputs, named in `unobservable`) with a warning.
  Observability extrinsic = result.observability;
  extrinsic.metric_scales.clear();
  std::vector<std::string> essential = UndeterminedNames(extrinsic);
  std::vector<std::string> segment_scales;
  for (int k = 0; k < num_segments; ++k) {
    if (!result.observability.ScaleDetermined(k)) {
      segment_scales.push_back(ScaleName(k, num_segments));
    }
  }
  if (num_segments == 1 ||
      static_cast<int>(segment_scales.size()) == num_segments) {
    essential.insert(
        essential.end(), segment_scales.begin(), segment_scales.end());
    segment_scales.clear();
  }
  if (!essential.empty()) {
    return Refuse(result,
                  CalibrationStatus::kUnobservable,
                  "the motion does not determine: " + Join(essential) +
                      " (standard deviation above the limit or no "
                      "information; drive turns of different sizes in both "
                      "directions)" +
                      (d.planarity.ground_named
                           ? "; the ground's tilt, which planar odometry "
                             "cannot see, widens roll, pitch, x and y (see "
                             "the warnings)"
                           : ""));
  }
  if (!segment_scales.empty()) {
    result.warnings.push_back("undetermined scale of " + Join(segment_scales) +
                              " (too few or too weak motions in that segment)");
  }
  result.status = CalibrationStatus::kSuccess;
  result.message = "calibrated from " + std::to_string(d.num_pairs_used) +
                   " of " + std::to_string(num_pairs) + " motion pairs";
  return result;
}

}  // namespace odomcal
