// Translation z from the motion (calibrate_translation_z_internal.h).
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
#include <optional>

namespace odomcal::internal {
// The data's information on z with every other parameter free: the Schur
// complement of the last row and column. 0 where the others are singular.
double MarginalInformationOfLast(const Eigen::MatrixXd& information) {
  const Eigen::Index n = information.rows();
  if (n < 2 || !information.allFinite()) return 0.0;
  const std::optional<Eigen::MatrixXd> others_covariance =
      InvertInformation(information.topLeftCorner(n - 1, n - 1));
  if (!others_covariance) return 0.0;
  const Eigen::VectorXd cross = information.col(n - 1).head(n - 1);
  return std::max(
      0.0, information(n - 1, n - 1) - cross.dot(*others_covariance * cross));
}

// True when some odometry rotation moves the z axis beyond the planar
// tolerance (the same as IsPlanarOdometry's): R_A e_z leaves e_z.
bool OdometryTilts(const MotionPairs& pairs, const std::vector<int>& used) {
  for (const int i : used) {
    const Eigen::Matrix3d r_a =
        pairs[i].odom_i_from_odom_j.rotation.toRotationMatrix();
    if (std::hypot(r_a(0, 2), r_a(1, 2)) > kPlanarTolerance) return true;
  }
  return false;
}

// The estimate with translation z free, for SE(3) odometry: the 3-D linear
// translation step at the current rotation, then the refinement with z as a
// parameter (or its information alone without refinement). Accepted only
// when the information determines z within options.max_translation_stddev_m;
// otherwise the result keeps z held (nothing changes) and this returns
// false. RANSAC chose `used` with z held: it left out pairs whose tilt shows
// a wrong z, and the ones it kept lean toward the held value, so the pairs
// are chosen again under the estimate with z (and `used` updated).
bool EstimateTranslationZ(const MotionPairs& pairs,
                          std::vector<int>* used_pairs,
                          const CalibrationOptions& options,
                          CalibrationResult* result,
                          Eigen::MatrixXd* information,
                          std::vector<int>* information_segments) {
  std::vector<int> used = *used_pairs;
  const LinearEstimate linear =
      SolveTranslationScale3d(pairs, used, result->odom_from_cam.rotation);
  if (!linear.success) return false;
  std::vector<double> scales = linear.metric_scales;
  scales.resize(result->metric_scales.size(), std::nan(""));
  for (const int i : used) {
    if (!(scales[pairs[i].segment] > 0.0)) return false;
  }
  Rigid3d odom_from_cam = linear.odom_from_cam;
  Eigen::MatrixXd z_information;
  std::vector<int> z_segments;
  if (options.refine) {
    const RefinementResult refined = RefineOdomFromCam(
        pairs, used, odom_from_cam, scales, options, TranslationZ::kEstimate);
    if (!refined.usable || !IsFinite(refined.odom_from_cam)) return false;
    odom_from_cam = refined.odom_from_cam;
    scales = refined.metric_scales;
    z_information = refined.information;
    z_segments = refined.information_segments;
    std::vector<int> inliers;
    for (int i = 0; options.use_ransac && i < static_cast<int>(pairs.size());
         ++i) {
      const double scale = scales[pairs[i].segment];
      if (std::isfinite(scale) &&
          IsInlier(pairs[i], odom_from_cam, scale, options)) {
        inliers.push_back(i);
      }
    }
    if (static_cast<int>(inliers.size()) >= options.min_num_pairs &&
        inliers != used) {
      const RefinementResult again = RefineOdomFromCam(pairs,
                                                       inliers,
                                                       odom_from_cam,
                                                       scales,
                                                       options,
                                                       TranslationZ::kEstimate);
      if (!again.usable || !IsFinite(again.odom_from_cam)) return false;
      odom_from_cam = again.odom_from_cam;
      scales = again.metric_scales;
      z_information = again.information;
      z_segments = again.information_segments;
      used = inliers;
    }
  } else {
    z_information = HandEyeInformation(pairs,
                                       used,
                                       odom_from_cam,
                                       scales,
                                       options,
                                       &z_segments,
                                       TranslationZ::kEstimate);
  }
  const std::optional<Eigen::MatrixXd> covariance =
      InvertInformation(z_information);
  if (!covariance) return false;
  const Eigen::Index z = covariance->rows() - 1;
  if (!(std::sqrt((*covariance)(z, z)) <= options.max_translation_stddev_m)) {
    return false;
  }
  result->odom_from_cam = odom_from_cam;
  result->metric_scales = scales;
  result->observability.translation_z = Determination::kEstimated;
  result->observability.translation_z_source = TranslationZSource::kMotion;
  *used_pairs = used;
  *information = z_information;
  *information_segments = z_segments;
  return true;
}

// SE(3) odometry that does not determine z: z estimated under its prior
// N(fixed_translation_z_m, translation_z_prior_sigma_m^2) from the result
// with z held, the pairs chosen again under that estimate as in
// EstimateTranslationZ. Kept when the data's information on z (the others
// free) is more than TranslationZPrior::kMovedInformationRatio of the
// prior's; then `information` is the data's with z last (the prior's is
// added after the widening for the estimated noise, which concerns the data
// alone). Otherwise nothing changes: the data's standard deviation of z is
// then above ten prior sigmas, and a held z wrong by one prior sigma moves x
// and y by under a tenth of their standard deviations with z free. Records
// the data's standard deviation of z.
void EstimateTranslationZUnderPrior(const MotionPairs& pairs,
                                    std::vector<int>* used_pairs,
                                    const CalibrationOptions& options,
                                    CalibrationResult* result,
                                    Eigen::MatrixXd* information,
                                    std::vector<int>* information_segments) {
  if (!options.refine || !(options.translation_z_prior_sigma_m > 0.0)) return;
  std::vector<int> used = *used_pairs;
  Rigid3d start = result->odom_from_cam;
  start.translation.z() = options.fixed_translation_z_m;
  RefinementResult refined = RefineOdomFromCam(
      pairs, used, start, result->metric_scales, options, TranslationZ::kPrior);
  if (!refined.usable || !IsFinite(refined.odom_from_cam)) return;
  std::vector<int> inliers;
  for (int i = 0; options.use_ransac && i < static_cast<int>(pairs.size());
       ++i) {
    const double scale = refined.metric_scales[pairs[i].segment];
    if (std::isfinite(scale) &&
        IsInlier(pairs[i], refined.odom_from_cam, scale, options)) {
      inliers.push_back(i);
    }
  }
  if (static_cast<int>(inliers.size()) >= options.min_num_pairs &&
      inliers != used) {
    refined = RefineOdomFromCam(pairs,
                                inliers,
                                refined.odom_from_cam,
                                refined.metric_scales,
                                options,
                                TranslationZ::kPrior);
    if (!refined.usable || !IsFinite(refined.odom_from_cam)) return;
    used = inliers;
  }
  for (const int i : used) {
    if (!(refined.metric_scales[pairs[i].segment] > 0.0)) return;
  }
  const double data_information =
      MarginalInformationOfLast(refined.information);
  TranslationZPrior& prior = result->translation_z_prior;
  prior.data_stddev_m = data_information > 0.0
                            ? 1.0 / std::sqrt(data_information)
                            : std::numeric_limits<double>::infinity();
  const double prior_information = 1.0 / (options.translation_z_prior_sigma_m *
                                          options.translation_z_prior_sigma_m);
  if (!(data_information >
        TranslationZPrior::kMovedInformationRatio * prior_information)) {
    return;
  }
  prior.moved_by_data = true;
  result->odom_from_cam = refined.odom_from_cam;
  result->metric_scales = refined.metric_scales;
  *used_pairs = used;
  *information = refined.information;
  *information_segments = refined.information_segments;
}

}  // namespace odomcal::internal
