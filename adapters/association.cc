// Camera-odometry association. InterpolateOdometry binary-searches the two
// odometry samples around a stamp and interpolates between them: on the SE(2)
// geodesic for planar logs (Log of the relative motion a->b, scaled by tau,
// Exp'd and composed onto a), with slerp + linear translation otherwise.
// AssociateCameraWithOdometry walks each camera segment in time order, looks
// up origin_from_odom for every camera pose at camera time + offset, keeps a
// running keyframe per unbroken chain of usable poses, and emits a MotionPair
// whenever the odometry has moved past either threshold since that keyframe.
#include "odomcal/adapters/association.h"

#include "odomcal/adapters/odometry_interpolation_error.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace odomcal {
namespace {

// Below this |theta| the SE(2) coefficients use their Taylor series; the
// first omitted terms are O(theta^4) ~ 1e-24, far below double precision.
constexpr double kSmallAngle = 1e-6;

// The SE(2) left Jacobian V(theta) = [[a, -b], [b, a]] with
//   a = sin(theta) / theta,  b = (1 - cos(theta)) / theta,
// so that Exp(v, theta) has translation V(theta) * v. b is evaluated as
// 2 sin^2(theta / 2) / theta, which has no cancellation for small theta.
void Se2JacobianCoefficients(double theta, double* a, double* b) {
  if (std::abs(theta) < kSmallAngle) {
    const double theta2 = theta * theta;
    *a = 1.0 - theta2 / 6.0;
    *b = 0.5 * theta * (1.0 - theta2 / 12.0);
    return;
  }
  const double sin_half = std::sin(0.5 * theta);
  *a = std::sin(theta) / theta;
  *b = 2.0 * sin_half * sin_half / theta;
}

// Translation part of Exp of the twist (v, theta).
Eigen::Vector2d Se2ExpTranslation(const Eigen::Vector2d& v, double theta) {
  double a = 0.0, b = 0.0;
  Se2JacobianCoefficients(theta, &a, &b);
  return Eigen::Vector2d(a * v.x() - b * v.y(), b * v.x() + a * v.y());
}

// Linear velocity part v of Log(translation p, rotation theta): V^-1 * p.
// a^2 + b^2 = (sin(theta/2) / (theta/2))^2 > 0 for |theta| <= pi.
Eigen::Vector2d Se2LogTranslation(const Eigen::Vector2d& p, double theta) {
  double a = 0.0, b = 0.0;
  Se2JacobianCoefficients(theta, &a, &b);
  const double inverse_det = 1.0 / (a * a + b * b);
  return inverse_det *
         Eigen::Vector2d(a * p.x() + b * p.y(), -b * p.x() + a * p.y());
}

// Yaw in [-pi, pi] of a rotation about +z.
Rigid3d InterpolatePlanar(const Rigid3d& a, const Rigid3d& b, double tau) {
  const Rigid3d a_from_b = Inverse(a) * b;
  const double theta = YawAboutZ(a_from_b.rotation);
  const Eigen::Vector2d v =
      Se2LogTranslation(a_from_b.translation.head<2>(), theta);
  const double tau_theta = tau * theta;
  const Eigen::Vector2d p = Se2ExpTranslation(tau * v, tau_theta);
  const Rigid3d a_from_tau(YawRotation(tau_theta),
                           Eigen::Vector3d(p.x(), p.y(), 0.0));
  Rigid3d result = a * a_from_tau;
  result.translation.z() =
      (1.0 - tau) * a.translation.z() + tau * b.translation.z();
  return result;
}

Rigid3d InterpolateSlerpLinear(const Rigid3d& a, const Rigid3d& b, double tau) {
  return Rigid3d(a.rotation.slerp(tau, b.rotation).normalized(),
                 (1.0 - tau) * a.translation + tau * b.translation);
}

void CheckIncreasing(const Trajectory& trajectory, const std::string& name) {
  for (size_t i = 1; i < trajectory.poses.size(); ++i) {
    if (trajectory.poses[i].stamp_ns <= trajectory.poses[i - 1].stamp_ns) {
      throw std::invalid_argument(
          name + ".poses[" + std::to_string(i) +
          "].stamp_ns: not strictly increasing (" +
          std::to_string(trajectory.poses[i].stamp_ns) + " after " +
          std::to_string(trajectory.poses[i - 1].stamp_ns) + ")");
    }
  }
}

void CheckNonNegative(double value, const char* field) {
  if (!std::isfinite(value) || value < 0.0) {
    throw std::invalid_argument(std::string(field) +
                                " must be finite and >= 0, got " +
                                FormatNumber(value));
  }
}

void CheckMaxGap(double max_gap_s, const char* field, bool zero_allowed) {
  if (zero_allowed && max_gap_s == 0.0) return;
  if (!std::isfinite(max_gap_s) || max_gap_s <= 0.0) {
    throw std::invalid_argument(std::string(field) +
                                " must be finite and > 0, got " +
                                FormatNumber(max_gap_s));
  }
}

void SetFailure(InterpolationFailure* why, InterpolationFailure failure) {
  if (why != nullptr) *why = failure;
}

// Whether a stamp before the first or after the last sample lies within
// kEndToleranceFraction of the end interval, and that interval is no gap.
bool WithinEndTolerance(const std::vector<StampedPose>& poses,
                        int64_t stamp_ns,
                        double max_gap_s) {
  if (poses.size() < 2) return false;
  const bool before = stamp_ns < poses.front().stamp_ns;
  const int64_t end_ns =
      before ? poses.front().stamp_ns : poses.back().stamp_ns;
  const int64_t interval_ns =
      before ? poses[1].stamp_ns - poses[0].stamp_ns
             : poses.back().stamp_ns - poses[poses.size() - 2].stamp_ns;
  if (ElapsedSeconds(0, interval_ns) > max_gap_s) return false;
  const int64_t tolerance_ns = static_cast<int64_t>(
      std::floor(kEndToleranceFraction * static_cast<double>(interval_ns)));
  int64_t beyond_ns = 0;
  if (__builtin_sub_overflow(
          before ? end_ns : stamp_ns, before ? stamp_ns : end_ns, &beyond_ns)) {
    return false;  // certainly far outside
  }
  return beyond_ns <= tolerance_ns;
}

}  // namespace

void AssociationOptions::Check() const {
  CheckMaxGap(max_odometry_gap_s, "max_odometry_gap_s", true);
  if (keyframe_min_rotation_deg != kAutomaticKeyframeSpacing) {
    CheckNonNegative(keyframe_min_rotation_deg, "keyframe_min_rotation_deg");
  }
  if (keyframe_min_translation_m != kAutomaticKeyframeSpacing) {
    CheckNonNegative(keyframe_min_translation_m, "keyframe_min_translation_m");
  }
}

double MedianSampleIntervalS(const Trajectory& odometry) {
  const std::vector<StampedPose>& poses = odometry.poses;
  if (poses.size() < 2) return 0.0;
  std::vector<double> intervals_s;
  intervals_s.reserve(poses.size() - 1);
  for (size_t i = 1; i < poses.size(); ++i) {
    intervals_s.push_back(
        ElapsedSeconds(poses[i - 1].stamp_ns, poses[i].stamp_ns));
  }
  const auto middle = intervals_s.begin() + intervals_s.size() / 2;
  std::nth_element(intervals_s.begin(), middle, intervals_s.end());
  return *middle;
}

double AutomaticOdometryGapS(const Trajectory& odometry) {
  return std::clamp(2.5 * MedianSampleIntervalS(odometry),
                    kMinAutomaticOdometryGapS,
                    kMaxAutomaticOdometryGapS);
}

double OdometryGapLimitS(double max_odometry_gap_s,
                         const Trajectory& odometry) {
  return max_odometry_gap_s > 0.0 ? max_odometry_gap_s
                                  : AutomaticOdometryGapS(odometry);
}

std::optional<Rigid3d> InterpolateOdometry(const Trajectory& odometry,
                                           int64_t stamp_ns,
                                           double max_gap_s,
                                           InterpolationFailure* why) {
  CheckMaxGap(max_gap_s, "max_gap_s", false);
  const std::vector<StampedPose>& poses = odometry.poses;
  // First sample strictly after the stamp.
  const auto after =
      std::upper_bound(poses.begin(),
                       poses.end(),
                       stamp_ns,
                       [](int64_t stamp, const StampedPose& pose) {
                         return stamp < pose.stamp_ns;
                       });
  if (after != poses.begin() && (after - 1)->stamp_ns == stamp_ns) {
    SetFailure(why, InterpolationFailure::kNone);
    return (after - 1)->world_from_sensor;
  }
  const bool beyond_end = after == poses.begin() || after == poses.end();
  if (beyond_end && !WithinEndTolerance(poses, stamp_ns, max_gap_s)) {
    SetFailure(why, InterpolationFailure::kOutsideSpan);
    return std::nullopt;
  }
  // Within the tolerance beyond an end, the end interval is continued.
  const auto b_it = after == poses.begin()
                        ? poses.begin() + 1
                        : (after == poses.end() ? poses.end() - 1 : after);
  const StampedPose& a = *(b_it - 1);
  const StampedPose& b = *b_it;
  if (ElapsedSeconds(a.stamp_ns, b.stamp_ns) > max_gap_s) {
    SetFailure(why, InterpolationFailure::kInGap);
    return std::nullopt;
  }
  const double tau = static_cast<double>(stamp_ns - a.stamp_ns) /
                     static_cast<double>(b.stamp_ns - a.stamp_ns);
  SetFailure(why, InterpolationFailure::kNone);
  return odometry.planar
             ? InterpolatePlanar(a.world_from_sensor, b.world_from_sensor, tau)
             : InterpolateSlerpLinear(
                   a.world_from_sensor, b.world_from_sensor, tau);
}

AssociationResult AssociateCameraWithOdometry(
    const std::vector<Trajectory>& camera_segments,
    const Trajectory& odometry,
    const AssociationOptions& options) {
  options.Check();
  CheckIncreasing(odometry, "odometry");
  AssociationResult result;
  result.keyframe_min_rotation_deg = options.keyframe_min_rotation_deg;
  result.keyframe_min_translation_m = options.keyframe_min_translation_m;
  result.keyframe_spacing_automatic =
      options.keyframe_min_rotation_deg == kAutomaticKeyframeSpacing ||
      options.keyframe_min_translation_m == kAutomaticKeyframeSpacing;
  if (result.keyframe_spacing_automatic) {
    result.camera_pose_drift =
        TestCameraPoseDrift(camera_segments, CameraPoseDriftOptions());
    const KeyframeSpacing chosen = result.camera_pose_drift.drifting
                                       ? kDriftingPosesKeyframeSpacing
                                       : kConsistentPosesKeyframeSpacing;
    if (result.keyframe_min_rotation_deg == kAutomaticKeyframeSpacing) {
      result.keyframe_min_rotation_deg = chosen.min_rotation_deg;
    }
    if (result.keyframe_min_translation_m == kAutomaticKeyframeSpacing) {
      result.keyframe_min_translation_m = chosen.min_translation_m;
    }
  }
  const double min_rotation_rad =
      result.keyframe_min_rotation_deg * kPi / 180.0;
  const double median_interval_s = MedianSampleIntervalS(odometry);
  if (result.keyframe_spacing_automatic) {
    result.keyframe_min_span_s =
        kKeyframeMinSpanOdometryIntervals * median_interval_s;
  }
  result.camera_time_offset_ns = options.camera_time_offset_ns;
  result.num_pairs_per_segment.assign(camera_segments.size(), 0);
  result.odometry_rate_hz =
      median_interval_s > 0.0 ? 1.0 / median_interval_s : 0.0;
  result.max_odometry_gap_automatic =
      options.max_odometry_gap_s == kAutomaticOdometryGap;
  result.max_odometry_gap_s =
      OdometryGapLimitS(options.max_odometry_gap_s, odometry);
  for (size_t segment = 0; segment < camera_segments.size(); ++segment) {
    const Trajectory& camera = camera_segments[segment];
    CheckIncreasing(camera, "camera_segments[" + std::to_string(segment) + "]");

    bool have_keyframe = false;
    int64_t keyframe_stamp_ns = 0;
    Rigid3d keyframe_origin_from_odom;
    Rigid3d keyframe_world_from_cam;
    Eigen::Matrix3d keyframe_interpolation_covariance;
    for (const StampedPose& camera_pose : camera.poses) {
      ++result.num_camera_poses;
      int64_t odometry_stamp_ns = 0;
      std::optional<Rigid3d> origin_from_odom;
      InterpolationFailure why = InterpolationFailure::kOutsideSpan;
      // A shifted time outside int64 is certainly outside the log.
      if (!__builtin_add_overflow(camera_pose.stamp_ns,
                                  options.camera_time_offset_ns,
                                  &odometry_stamp_ns)) {
        origin_from_odom = InterpolateOdometry(
            odometry, odometry_stamp_ns, result.max_odometry_gap_s, &why);
      }
      if (!origin_from_odom) {
        if (why == InterpolationFailure::kInGap) {
          ++result.num_in_odometry_gaps;
        } else {
          ++result.num_outside_odometry_span;
        }
        have_keyframe = false;  // no pair may span a refused pose
        continue;
      }
      ++result.num_usable_camera_poses;
      const Eigen::Matrix3d interpolation_covariance =
          OdometryInterpolationCovariance(odometry, odometry_stamp_ns);

      bool new_keyframe = !have_keyframe;
      if (have_keyframe) {
        const Rigid3d odom_i_from_odom_j =
            Inverse(keyframe_origin_from_odom) * *origin_from_odom;
        new_keyframe =
            (RotationAngle(odom_i_from_odom_j.rotation) >= min_rotation_rad ||
             odom_i_from_odom_j.translation.norm() >=
                 result.keyframe_min_translation_m) &&
            ElapsedSeconds(keyframe_stamp_ns, odometry_stamp_ns) >=
                result.keyframe_min_span_s;
        if (new_keyframe) {
          MotionPair pair;
          pair.odom_i_from_odom_j = odom_i_from_odom_j;
          pair.cam_i_from_cam_j =
              Inverse(keyframe_world_from_cam) * camera_pose.world_from_sensor;
          pair.segment = static_cast<int>(segment);
          pair.stamp_i_ns = keyframe_stamp_ns;
          pair.stamp_j_ns = odometry_stamp_ns;
          if (!keyframe_interpolation_covariance.isZero(0.0) ||
              !interpolation_covariance.isZero(0.0)) {
            pair.odom_interpolation_covariance =
                RelativeMotionInterpolationCovariance(
                    keyframe_origin_from_odom,
                    keyframe_interpolation_covariance,
                    *origin_from_odom,
                    interpolation_covariance);
          }
          result.pairs.push_back(pair);
          ++result.num_pairs_per_segment[segment];
        }
      }
      if (new_keyframe) {
        have_keyframe = true;
        keyframe_stamp_ns = odometry_stamp_ns;
        keyframe_origin_from_odom = *origin_from_odom;
        keyframe_world_from_cam = camera_pose.world_from_sensor;
        keyframe_interpolation_covariance = interpolation_covariance;
        ++result.num_keyframes;
        result.keyframe_stamps_ns.push_back(odometry_stamp_ns);
        result.keyframe_segments.push_back(static_cast<int>(segment));
      }
    }
  }
  return result;
}

}  // namespace odomcal
