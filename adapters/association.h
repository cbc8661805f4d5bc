// Associating camera poses with wheel odometry, and cutting the result into
// keyframe-to-keyframe MotionPairs for hand-eye calibration.
//
// Time: odometry_time = camera_time + camera_time_offset_ns. Every camera pose
// is looked up in the odometry log at its odometry time; the pose there,
// origin_from_odom, is interpolated between the two neighbouring samples.
// Frames: camera trajectories hold world_from_cam (the reconstruction's world,
// translation in reconstruction units), the odometry holds origin_from_odom
// (metres). For consecutive keyframes i, j of one camera segment:
//   odom_i_from_odom_j = Inverse(origin_from_odom_i) * origin_from_odom_j
//   cam_i_from_cam_j   = Inverse(world_from_cam_i) * world_from_cam_j
// which satisfy the hand-eye equation of motion_pair.h.
#pragma once

#include "odomcal/adapters/camera_pose_drift.h"
#include "odomcal/adapters/trajectory.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace odomcal {

// max_odometry_gap_s's "automatic" value: the limit then follows the log's
// own sampling (AutomaticOdometryGapS).
constexpr double kAutomaticOdometryGap = 0.0;

// The keyframe thresholds' "automatic" value: the spacing then follows the
// camera poses' errors (camera_pose_drift.h): drifting poses (visual
// odometry) pair every frame the robot moved to with the next, other poses
// (a bundle-adjusted model) keep the longer steps, whose scale short steps
// of per-pose errors would bias (docs/benchmarks.md, "Which frames make the
// motion pairs"). Both thresholds automatic or either set: an automatic one
// takes the chosen spacing's value. Automatic keyframes are also at least
// one odometry sample interval apart: shorter pairs split one interpolated
// odometry interval and share its error, which the per-pair noise model
// does not know (measured at 4 Hz odometry, 7 Hz camera and 3x the noise:
// the scale within 3 sigma in 80 % of the drives without it, 100 % with it;
// docs/statistics.md).
constexpr double kAutomaticKeyframeSpacing = -1.0;
struct KeyframeSpacing {
  double min_rotation_deg = 0.0;
  double min_translation_m = 0.0;
};
constexpr KeyframeSpacing kConsistentPosesKeyframeSpacing{5.0, 0.10};
constexpr KeyframeSpacing kDriftingPosesKeyframeSpacing{1.0, 0.02};
// The shortest automatic keyframe span in median odometry sample intervals:
// one, less a tenth for the jitter of the camera's and the odometry's stamps
// (a 5 Hz camera on 5 Hz odometry still pairs consecutive frames).
constexpr double kKeyframeMinSpanOdometryIntervals = 0.9;

struct AssociationOptions {
  // A camera time between two odometry samples further apart than this is
  // refused (the vehicle may have done anything in between). Seconds, > 0,
  // or kAutomaticOdometryGap (the default): AutomaticOdometryGapS(odometry).
  double max_odometry_gap_s = kAutomaticOdometryGap;
  // A new keyframe once the odometry has moved by either threshold since the
  // previous keyframe (rotation angle in degrees, translation norm in metres).
  // Each >= 0 (zero makes every usable camera pose a keyframe) or
  // kAutomaticKeyframeSpacing (the default; see there).
  double keyframe_min_rotation_deg = kAutomaticKeyframeSpacing;
  double keyframe_min_translation_m = kAutomaticKeyframeSpacing;
  // Added to camera times before the odometry lookup:
  // odometry_time = camera_time + camera_time_offset_ns.
  int64_t camera_time_offset_ns = 0;

  // Throws std::invalid_argument when a value is out of range or not finite;
  // the message starts with the field's name, which is also the CLI flag's
  // ("max_odometry_gap_s must be finite and > 0, got -1").
  void Check() const;
};

// Median interval between consecutive samples, seconds (0 for fewer than two
// samples). The median ignores dropouts and jitter.
double MedianSampleIntervalS(const Trajectory& odometry);

// The automatic gap limit: 2.5 median sample intervals (one missing sample
// is tolerated, two are not, and jitter of +-25 % never trips it), kept
// within [kMinAutomaticOdometryGapS, kMaxAutomaticOdometryGapS]. The floor is
// the old fixed default, so logs of 10 Hz and more behave as they always did;
// above the ceiling constant-velocity interpolation is a guess (a robot
// turning at 0.8 rad/s turns 46 degrees in a second) and the acceleration
// seen by the neighbouring samples no longer bounds its error (see
// odometry_interpolation_error.h).
constexpr double kMinAutomaticOdometryGapS = 0.25;
constexpr double kMaxAutomaticOdometryGapS = 1.0;
double AutomaticOdometryGapS(const Trajectory& odometry);

// max_odometry_gap_s if > 0, else AutomaticOdometryGapS(odometry).
double OdometryGapLimitS(double max_odometry_gap_s, const Trajectory& odometry);

// How far InterpolateOdometry continues the log beyond its first or last
// sample, as a fraction of that end interval. An image taken with the last
// odometry sample gets odometry time last + offset, and an estimated offset
// a hair above zero (noise: microseconds, well within its stated
// uncertainty) put it outside the log, so the last image was dropped
// whenever the estimate came out positive. Within a tenth of the interval
// the constant-velocity continuation is off by at most dv * interval / 10
// (dv: the change of velocity after the last sample), less than the
// dv * interval / 4 an interpolation mid-interval may be off; further out it
// would be a guess, and the stamp is refused.
constexpr double kEndToleranceFraction = 0.1;

// Why InterpolateOdometry returned no pose.
enum class InterpolationFailure {
  kNone,  // it did return a pose
  // Before the first or after the last sample by more than the end tolerance
  // (or fewer than two samples).
  kOutsideSpan,
  kInGap,  // between two samples more than max_gap_s apart
};

// origin_from_odom at stamp_ns (odometry time base).
//
// A stamp equal to a sample's returns that sample unchanged. Otherwise, with
// a, b the samples around the stamp and tau = (t - t_a) / (t_b - t_a):
//   - planar trajectories follow the SE(2) geodesic
//       T(tau) = T_a * Exp(tau * Log(Inverse(T_a) * T_b)),
//     on (x, y, yaw), with z interpolated linearly. This is exact for a
//     unicycle moving at constant linear and angular velocity between the
//     samples, as long as it turns by less than pi between them. Planar poses
//     are assumed to be rotations about +z only (roll and pitch are dropped).
//   - other trajectories use slerp for the rotation (shortest arc) and linear
//     interpolation for the translation. This is not the SE(3) geodesic; the
//     two agree for pure rotation or pure translation and differ by
//     O(rotation * translation) along arcs.
// A stamp before the first or after the last sample by at most
// kEndToleranceFraction of that end interval (itself no gap) continues the
// end interval's motion the same way (tau slightly below 0 or above 1).
// Returns std::nullopt and sets *why (when why is not null) if the stamp is
// further outside the log or inside a gap. Precondition: strictly increasing
// stamps. Throws std::invalid_argument when max_gap_s is not positive and
// finite.
std::optional<Rigid3d> InterpolateOdometry(const Trajectory& odometry,
                                           int64_t stamp_ns,
                                           double max_gap_s,
                                           InterpolationFailure* why);

struct AssociationResult {
  // Consecutive keyframe pairs, in input order; pair.segment is the index of
  // the camera trajectory, stamps are odometry times (camera + offset).
  MotionPairs pairs;
  // All camera poses given, over all segments.
  int num_camera_poses = 0;
  // Camera poses that got an odometry pose (= num_camera_poses minus the two
  // refusal counts below).
  int num_usable_camera_poses = 0;
  // Camera poses refused because their odometry time is outside the log.
  int num_outside_odometry_span = 0;
  // Camera poses refused because their odometry time falls in a gap longer
  // than max_odometry_gap_s.
  int num_in_odometry_gaps = 0;
  // Keyframes, including one at the start of every unbroken run of usable
  // poses (that one may end up in no pair if the run is too short).
  int num_keyframes = 0;
  // Odometry time and segment index of every keyframe, in order.
  std::vector<int64_t> keyframe_stamps_ns;
  std::vector<int> keyframe_segments;
  // Number of pairs per camera segment (size = number of segments).
  std::vector<int> num_pairs_per_segment;
  // The odometry's sampling rate (1 / median sample interval; 0 for fewer
  // than two samples), the gap limit used, and whether it was automatic.
  double odometry_rate_hz = 0.0;
  double max_odometry_gap_s = 0.0;
  bool max_odometry_gap_automatic = false;
  // The keyframe thresholds used, whether either was automatic, and then the
  // test of the camera poses that chose them.
  double keyframe_min_rotation_deg = 0.0;
  double keyframe_min_translation_m = 0.0;
  bool keyframe_spacing_automatic = false;
  // Automatic spacing only: the shortest time between keyframes
  // (kKeyframeMinSpanOdometryIntervals median odometry sample intervals),
  // else 0.
  double keyframe_min_span_s = 0.0;
  CameraPoseDriftTest camera_pose_drift;
  // The clock offset the stamps include (options.camera_time_offset_ns):
  // the estimated one when the systematics loop associated.
  int64_t camera_time_offset_ns = 0;
};

// Builds MotionPairs from camera trajectories (one per SfM segment, each with
// its own world frame and scale; MotionPair::segment = index in
// camera_segments) and one odometry log.
//
// Per segment, camera poses are visited in time order. A refused pose (see
// InterpolateOdometry) is counted and breaks the chain: no pair spans it, and
// the next usable pose starts a new chain. The first usable pose of a chain is
// a keyframe; each later usable pose becomes the next keyframe when the
// odometry motion since the previous keyframe has a rotation angle >=
// keyframe_min_rotation_deg OR a translation norm >=
// keyframe_min_translation_m (automatic thresholds: TestCameraPoseDrift over
// all camera segments chooses them, and the keyframe must also be
// keyframe_min_span_s after the previous one), and each consecutive keyframe
// pair of a chain gives one MotionPair (see the top of this file). Covariances
// are left empty.
//
// Throws std::invalid_argument from options.Check(), and when a trajectory's
// stamps are not strictly increasing (naming the trajectory and index).
AssociationResult AssociateCameraWithOdometry(
    const std::vector<Trajectory>& camera_segments,
    const Trajectory& odometry,
    const AssociationOptions& options);

}  // namespace odomcal
