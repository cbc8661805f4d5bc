// See the header for the loop. Held intrinsics return to identity for the
// next round, so that a parameter the motion does not determine never keeps
// a value from an earlier round.
#include "odomcal/adapters/systematics_estimation.h"

#include "odomcal/adapters/odometry_increments.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/solver/format_number.h"
#include "odomcal/solver/noise_estimation.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

namespace odomcal {
namespace {

// wheel_track_m alone changes nothing (the forward term scales with
// yaw_per_metre_rad).
bool IsIdentity(const OdometryIntrinsics& intrinsics) {
  return intrinsics.yaw_scale == 1.0 && intrinsics.yaw_per_metre_rad == 0.0 &&
         intrinsics.yaw_rate_bias_rad_s == 0.0;
}

// Inflates the result's standard deviations and covariance by what
// estimating the systematics adds: per parameter, the joint estimate's
// marginal standard deviation over its conditional one (systematics held),
// both from the same information, so that the result's own inflation (the
// planarity check's) is kept. Then the limits are tested again: a quantity
// whose inflated standard deviation exceeds its limit is undetermined.
void ApplyMarginalCovariance(const SystematicsRefinement& refined,
                             const CalibrationOptions& options,
                             CalibrationResult* result) {
  if (!result->covariance || refined.extrinsic_covariance.size() == 0 ||
      refined.extrinsic_conditional_covariance.size() == 0) {
    return;
  }
  Eigen::MatrixXd& covariance = *result->covariance;
  const Eigen::MatrixXd& marginal = refined.extrinsic_covariance;
  const Eigen::MatrixXd& conditional = refined.extrinsic_conditional_covariance;
  const int n = static_cast<int>(marginal.rows());
  if (covariance.rows() < n || conditional.rows() != n) return;
  const auto ratio = [&](int k) {
    return conditional(k, k) > 0.0
               ? std::max(1.0, std::sqrt(marginal(k, k) / conditional(k, k)))
               : 1.0;
  };
  double max_rotation_ratio = 1.0;
  for (int k = 0; k < 3; ++k) {
    result->stddev_rotation_axes_deg(k) *= ratio(k);
    max_rotation_ratio = std::max(max_rotation_ratio, ratio(k));
  }
  result->stddev_roll_pitch_yaw_deg *= max_rotation_ratio;
  for (int k = 0; k < 2; ++k)
    result->stddev_translation_xy_m(k) *= ratio(3 + k);
  for (size_t k = 0; k < refined.information_segments.size(); ++k) {
    const size_t segment = refined.information_segments[k];
    if (segment < result->stddev_metric_scales_rel.size()) {
      result->stddev_metric_scales_rel[segment] *= ratio(5 + k);
    }
  }
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(covariance.rows());
  for (int k = 0; k < n; ++k) scale(k) = ratio(k);
  covariance = scale.asDiagonal() * covariance * scale.asDiagonal();

  if (!result->IsSuccess()) return;
  std::vector<std::string> above;
  if (result->stddev_rotation_axes_deg.maxCoeff() >
      options.max_rotation_stddev_deg) {
    result->observability.rotation = Determination::kUndetermined;
    above.push_back("rotation");
  }
  if (result->stddev_translation_xy_m.x() > options.max_translation_stddev_m) {
    result->observability.translation_x = Determination::kUndetermined;
    above.push_back("translation_x");
  }
  if (result->stddev_translation_xy_m.y() > options.max_translation_stddev_m) {
    result->observability.translation_y = Determination::kUndetermined;
    above.push_back("translation_y");
  }
  if (above.empty()) return;
  std::string names;
  for (const std::string& name : above) {
    names += (names.empty() ? "" : ", ") + name;
  }
  result->status = CalibrationStatus::kUnobservable;
  result->message =
      "the motion does not determine: " + names +
      " (standard deviation above the limit once the uncertainty of the "
      "clock offset and odometry intrinsics is included; drive turns of "
      "different sizes in both directions and straight stretches)";
}

// How well a refinement's final calibration fits, to choose between two
// starts of the clock offset: more pairs used, then the smaller rotation
// residual (a wrong offset shows first in the rotation while turning).
struct FitOfRun {
  bool usable = false;
  int num_inliers = 0;
  double rms_rotation_deg = 0.0;
};

FitOfRun FitOf(const CalibrationResult* result, bool offset_estimated) {
  FitOfRun fit;
  if (result == nullptr || !result->has_estimate || !offset_estimated) {
    return fit;
  }
  fit.usable = true;
  fit.num_inliers =
      static_cast<int>(std::count(result->diagnostics.inlier_mask.begin(),
                                  result->diagnostics.inlier_mask.end(),
                                  1));
  fit.rms_rotation_deg = result->diagnostics.rms_rotation_residual_deg;
  return fit;
}

bool Better(const FitOfRun& a, const FitOfRun& b) {
  if (a.usable != b.usable) return a.usable;
  if (a.num_inliers != b.num_inliers) return a.num_inliers > b.num_inliers;
  return a.rms_rotation_deg <= b.rms_rotation_deg;
}

}  // namespace

SystematicsEstimate EstimateSystematics(
    const std::vector<Trajectory>& cameras,
    const Trajectory& odometry,
    const AssociationOptions& association_options,
    const CalibrationOptions& calibration_options,
    const SystematicsEstimationOptions& options,
    const CalibrateAssociation& calibrate,
    AssociationResult* association) {
  SystematicsEstimate estimate;
  estimate.camera_time_offset_ns = association_options.camera_time_offset_ns;
  estimate.corrected_odometry = odometry;
  const bool planar = odometry.planar && odometry.poses.size() >= 2;
  // 3-D odometry (TUM): the clock offset through the endpoint twists; the
  // intrinsics re-integrate planar samples and are held.
  const bool three_d = !odometry.planar && odometry.poses.size() >= 2;
  const bool estimate_intrinsics =
      options.estimate_odometry_intrinsics && planar;

  const auto run = [&](int64_t offset_ns,
                       const OdometryIntrinsics& intrinsics) {
    AssociationOptions shifted = association_options;
    shifted.camera_time_offset_ns = offset_ns;
    estimate.corrected_odometry = IsIdentity(intrinsics)
                                      ? odometry
                                      : CorrectOdometry(odometry, intrinsics);
    *association = AssociateCameraWithOdometry(
        cameras, estimate.corrected_odometry, shifted);
    if (planar) AttachOdometrySamples(odometry, &association->pairs);
    if (three_d) AttachOdometryTwists(odometry, &association->pairs);
    estimate.camera_time_offset_ns = offset_ns;
    estimate.intrinsics = intrinsics;
    return calibrate(*association);
  };

  const bool any =
      options.estimate_time_offset || options.estimate_odometry_intrinsics;
  if (!options.estimate_time_offset) {
    estimate.time_offset_reason = "--estimate_time_offset off";
  }
  if (!options.estimate_odometry_intrinsics) {
    estimate.intrinsics_reasons.push_back("--estimate_odometry_intrinsics off");
  }
  const auto coarse_search = [&] {
    TimeOffsetSearchOptions search_options;
    search_options.center_ns = association_options.camera_time_offset_ns;
    search_options.range_s = options.time_offset_search_s;
    search_options.max_odometry_gap_s =
        OdometryGapLimitS(association_options.max_odometry_gap_s, odometry);
    estimate.coarse = SearchTimeOffset(cameras, odometry, search_options);
    estimate.coarse_search_ran = true;
    estimate.search_range_s = options.time_offset_search_s;
  };
  if (three_d && options.estimate_odometry_intrinsics) {
    estimate.intrinsics_reasons.push_back(
        "3-D odometry (a TUM log, not x, y, yaw): only a planar log's "
        "odometry intrinsics are estimated");
  }
  if (!any || !(planar || (three_d && options.estimate_time_offset))) {
    if (any && odometry.poses.size() < 2) {
      // Nothing to estimate from.
      const std::string why = "fewer than 2 odometry samples: not estimated";
      if (options.estimate_time_offset) estimate.time_offset_reason = why;
      if (options.estimate_odometry_intrinsics) {
        estimate.intrinsics_reasons = {why};
      }
    }
    run(estimate.camera_time_offset_ns, OdometryIntrinsics());
    estimate.num_rounds = 1;
    return estimate;
  }

  // One joint refinement in rounds from `start_ns`, the offset refined only
  // with `refine_offset`; `estimate`, `*association` and the returned result
  // are those of its final round.
  struct Outcome {
    std::optional<SystematicsRefinement> last;
    CalibrationResult* result = nullptr;
    std::string offset_reason;  // why the offset was not estimated
  };
  const auto refine = [&](int64_t start_ns, bool refine_offset) {
    Outcome outcome;
    SystematicsOptions limits = options.limits;
    limits.estimate_time_offset = refine_offset;
    limits.estimate_intrinsics = estimate_intrinsics;
    OdometryIntrinsics intrinsics;
    intrinsics.wheel_track_m = options.wheel_track_m;
    int64_t offset_ns = start_ns;
    std::optional<SystematicsRefinement>& last = outcome.last;
    CalibrationResult*& result = outcome.result;
    for (int round = 1; round <= options.max_rounds; ++round) {
      estimate.num_rounds = round;
      const auto [pairs, calibrated] = run(offset_ns, intrinsics);
      result = calibrated;
      last.reset();
      if (!result->has_estimate ||
          !result->observability.ExtrinsicDetermined()) {
        break;
      }
      std::vector<int> indices;
      const std::vector<char>& mask = result->diagnostics.inlier_mask;
      for (size_t k = 0; k < pairs->size(); ++k) {
        if (k < mask.size() && mask[k]) indices.push_back(static_cast<int>(k));
      }
      // Under the noise the calibration estimated from the data, when it did:
      // the options' model and the pairs' own covariances scaled alike, as
      // the hand-eye refinement weighs them.
      CalibrationOptions refine_options = calibration_options;
      const MotionPairs* refine_pairs = pairs;
      MotionPairs weighted_pairs;
      if (result->noise_estimate) {
        refine_options.noise = result->noise_estimate->noise;
        weighted_pairs = ScaleCovariances(*pairs, *result->noise_estimate);
        refine_pairs = &weighted_pairs;
      }
      const SystematicsRefinement refined =
          RefineSystematics(*refine_pairs,
                            indices,
                            result->odom_from_cam,
                            result->metric_scales,
                            intrinsics,
                            refine_options,
                            limits);
      if (!refined.usable) break;
      last = refined;
      OdometryIntrinsics next = refined.intrinsics;
      if (!refined.estimated[1]) next.yaw_scale = 1.0;
      if (!refined.estimated[2]) next.yaw_per_metre_rad = 0.0;
      if (!refined.estimated[3]) next.yaw_rate_bias_rad_s = 0.0;
      const double change_s = refined.time_offset_change_s;
      const bool converged =
          std::abs(change_s) < options.tolerance_s &&
          std::abs(next.yaw_scale - intrinsics.yaw_scale) < 1e-6 &&
          std::abs(next.yaw_per_metre_rad - intrinsics.yaw_per_metre_rad) <
              1e-6 &&
          std::abs(next.yaw_rate_bias_rad_s - intrinsics.yaw_rate_bias_rad_s) <
              1e-7;
      if (converged) break;
      // Re-association, RANSAC and the noise estimate change the pair set from
      // round to round, which can leave a limit cycle of changes about as
      // large as the parameters' standard deviations (seen: 0.17 ms against
      // 0.13 ms, wheels 1.015 / 0.99, seed 23). Holding everything at identity
      // then costs far more (0.23 deg of rotation) than the cycle: the last
      // round's refined values are the estimate, calibrated once more at them.
      const double changes[kNumSystematics] = {
          change_s,
          next.yaw_scale - intrinsics.yaw_scale,
          next.yaw_per_metre_rad - intrinsics.yaw_per_metre_rad,
          next.yaw_rate_bias_rad_s - intrinsics.yaw_rate_bias_rad_s};
      bool within_noise = true;
      for (int k = 0; k < kNumSystematics; ++k) {
        const double limit =
            refined.estimated[k] ? 3.0 * refined.stddev[k] : 0.0;
        if (!(std::abs(changes[k]) <= limit)) within_noise = false;
      }
      if (round == options.max_rounds && within_noise) {
        offset_ns += static_cast<int64_t>(std::llround(change_s * 1e9));
        result = run(offset_ns, next).second;
        if (!result->has_estimate ||
            !result->observability.ExtrinsicDetermined()) {
          last.reset();
        }
        break;
      }
      if (round == options.max_rounds) {
        outcome.offset_reason =
            "the estimate did not settle within " + std::to_string(round) +
            " rounds (last change " + FormatRounded(change_s) + " s)";
        last.reset();
        break;
      }
      offset_ns += static_cast<int64_t>(std::llround(change_s * 1e9));
      intrinsics = next;
    }
    if (last && refine_offset && !last->estimated[0]) {
      outcome.offset_reason = last->held_reason[0];
    }
    return outcome;
  };
  const auto offset_estimated = [](const Outcome& outcome) {
    return outcome.last && outcome.last->estimated[0];
  };

  // The clock offset is refined with the extrinsic whenever it is to be
  // estimated, from the coarse peak; where the peak is flat (smooth motion)
  // it still lies near the optimum, and the given value is refined too: the
  // better fit is kept. Whether the offset counts as estimated follows from
  // the refined standard deviation alone, never from the coarse peak's
  // shape; one that is not keeps the given value.
  const int64_t given_ns = association_options.camera_time_offset_ns;
  Outcome outcome;
  std::string coarse_note;  // appended to a reason for holding the offset
  if (!options.estimate_time_offset) {
    outcome = refine(given_ns, false);
  } else {
    coarse_search();
    if (!estimate.coarse.resolved) {
      coarse_note = " (coarse search: " + estimate.coarse.reason + ")";
    }
    if (estimate.coarse.num_intervals == 0) {
      outcome = refine(given_ns, false);
      outcome.offset_reason =
          "not resolved by the coarse search: " + estimate.coarse.reason;
      coarse_note.clear();
    } else {
      outcome = refine(estimate.coarse.peak_ns, true);
      const int64_t step_ns =
          static_cast<int64_t>(std::llround(estimate.coarse.step_s * 1e9));
      if (!estimate.coarse.resolved &&
          std::abs(estimate.coarse.peak_ns - given_ns) > step_ns) {
        const FitOfRun from_peak =
            FitOf(outcome.result, offset_estimated(outcome));
        Outcome from_given = refine(given_ns, true);
        const FitOfRun given_fit =
            FitOf(from_given.result, offset_estimated(from_given));
        if (Better(from_peak, given_fit)) {
          outcome = refine(estimate.coarse.peak_ns, true);
        } else {
          outcome = std::move(from_given);
        }
      }
      if (!offset_estimated(outcome)) {
        // Held: the calibration at the given value, not at a start. A
        // refinement that ended without an estimate (reset) may still have
        // said why (it did not settle).
        const std::string why =
            !outcome.offset_reason.empty()
                ? outcome.offset_reason
                : "the refinement with it free did not determine the "
                  "extrinsic";
        outcome = refine(given_ns, false);
        outcome.offset_reason = why;
      }
    }
  }
  std::optional<SystematicsRefinement>& last = outcome.last;
  CalibrationResult* result = outcome.result;
  if (!outcome.offset_reason.empty()) {
    estimate.time_offset_reason = outcome.offset_reason + coarse_note;
  }

  if (!last) {
    const std::string why =
        result != nullptr && result->has_estimate &&
                result->observability.ExtrinsicDetermined()
            ? "the joint refinement did not succeed"
            : "the calibration did not determine the extrinsic";
    if (estimate.time_offset_reason.empty() && options.estimate_time_offset) {
      estimate.time_offset_reason = why;
    }
    if (estimate_intrinsics) estimate.intrinsics_reasons.push_back(why);
    // Nothing estimated: what the caller gets must be the calibration at
    // the given values, which the outputs name, not at a coarse peak or at
    // the values of an unfinished round.
    if (estimate.camera_time_offset_ns !=
            association_options.camera_time_offset_ns ||
        !IsIdentity(estimate.intrinsics)) {
      run(association_options.camera_time_offset_ns, OdometryIntrinsics());
    }
    return estimate;
  }
  estimate.time_offset_estimated = last->estimated[0];
  estimate.camera_time_offset_stddev_s = last->stddev[0];
  for (int k = 0; k < 3; ++k) {
    estimate.intrinsics_estimated[k] = last->estimated[1 + k];
    estimate.intrinsics_stddev[k] = last->stddev[1 + k];
    if (estimate_intrinsics && !last->estimated[1 + k]) {
      estimate.intrinsics_reasons.push_back(last->held_reason[1 + k]);
    }
  }
  // The ratio rests on yaw_per_metre_rad: none when it is held.
  if (options.wheel_track_m > 0.0 && estimate.intrinsics_estimated[1]) {
    const double ys = estimate.intrinsics.yaw_scale;
    const double x = options.wheel_track_m *
                     estimate.intrinsics.yaw_per_metre_rad / (2.0 * ys);
    estimate.right_over_left = (1.0 + x) / (1.0 - x);
    // First order, correlations between the two parameters neglected.
    const double sx = std::hypot(
        options.wheel_track_m / (2.0 * ys) * estimate.intrinsics_stddev[1],
        x / ys * estimate.intrinsics_stddev[0]);
    estimate.right_over_left_stddev = 2.0 / ((1.0 - x) * (1.0 - x)) * sx;
  }
  ApplyMarginalCovariance(*last, calibration_options, result);
  return estimate;
}

}  // namespace odomcal
