// Plausibility checks that recognise a unit mistake in the inputs and name
// it, instead of letting a calibration of numbers in the wrong unit end in
// a "success" with a wrong scale or in advice about the wrong thing.
//
// Each check has a threshold that no correct input of a wheeled robot
// reaches and that the usual mistakes (centimetres or millimetres for
// metres, degrees for radians, frame numbers for times) exceed many times:
//   - odometry speed: the 90th percentile of the speeds between consecutive
//     samples above kMaxOdometrySpeedMps (20 m/s, 72 km/h);
//   - odometry yaw: a step of more than pi between consecutive samples that
//     is not a wrap by 2 pi (degrees wrap at +-180, radians at +-pi);
//   - camera vs odometry rotation: the rotation angle of a motion is the
//     same seen from either sensor (hand-eye: the mount does not change
//     it), so odometry angles that match the camera's only after a factor
//     of 180/pi = 57.3 (or pi/180) are degrees read as radians (or the
//     reverse);
//   - image times: consecutive images less than 1 ms apart are frame
//     numbers, not times;
//   - the estimated extrinsic: a camera more than kMaxExtrinsicDistanceM
//     (5 m) from the odometry origin; this one is only a warning, since a
//     large vehicle can have it.
// The checks are pure: they throw FormatError with one line naming the file
// and the likely unit mistake, or return a warning text.
#pragma once

#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/trajectory.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

inline constexpr double kMaxOdometrySpeedMps = 20.0;
inline constexpr double kMaxExtrinsicDistanceM = 5.0;
inline constexpr int64_t kMinImageIntervalNs = 1000000;  // 1 ms

// The reason a yaw step from `previous_yaw_rad` to `yaw_rad` (consecutive
// samples, in radians as read) cannot come from a radian log, or
// std::nullopt when it can. A radian log turns by at most pi between samples
// either way (a sparse log, one sample per image, may turn that far): its
// raw step is at most pi, or it wraps, and then both samples lie in the
// interval the log keeps its yaw in (-pi..pi or 0..2 pi). Anything else
// cannot be radians; a log in degrees that never wraps is left to
// CheckRotationAngleUnits. `yaw_unit_named`: the header named the yaw unit,
// so the message does not suggest naming it.
std::optional<std::string> YawStepProblem(double previous_yaw_rad,
                                          double yaw_rad,
                                          bool yaw_unit_named);

// Throws FormatError "<odometry.source>: the odometry moves at ... m/s ..."
// when it is faster than kMaxOdometrySpeedMps (see the top of this file).
void CheckOdometrySpeed(const Trajectory& odometry);

// Throws FormatError "<odometry_source>: the odometry yaw looks like
// degrees ..." (or radians named as degrees) when the rotation angles of
// the motion pairs agree between camera and odometry only after a factor
// of 57.3. Needs at least 3 pairs that rotate by more than 1 deg; decides
// nothing otherwise.
void CheckRotationAngleUnits(const MotionPairs& pairs,
                             const std::string& odometry_source);

// Throws FormatError "<source>: the image times were <how_read> ... look
// like frame numbers ..." when consecutive image times (all images of all
// segments, in order) are typically less than kMinImageIntervalNs apart.
// `how_read` says where the times came from, e.g. "read from the image
// names as ns".
void CheckImageTimesAreNotFrameNumbers(std::vector<int64_t> stamps_ns,
                                       const std::string& source,
                                       const std::string& how_read);

// "camera times 0.000-3.900 s (read from the image names as ns), odometry
// 1700000000.000-1700000120.000 s": the spans of all camera poses (plus
// camera_time_offset_ns, noted when not zero or when estimated: "then
// shifted by the estimated offset 0.301 s") and of the odometry, for the
// message when they do not overlap.
std::string TimeSpansText(const std::vector<Trajectory>& cameras,
                          const std::string& camera_times_origin,
                          int64_t camera_time_offset_ns,
                          const Trajectory& odometry,
                          bool offset_estimated = false);

// A warning when odom_from_cam puts the camera more than
// kMaxExtrinsicDistanceM from the odometry origin, else std::nullopt.
std::optional<std::string> ExtrinsicDistanceWarning(
    const Rigid3d& odom_from_cam);

}  // namespace odomcal
