// Statistics are medians and percentiles over all samples or pairs, so that a
// single glitch neither triggers nor hides a finding.
#include "odomcal/adapters/input_plausibility.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace odomcal {
namespace {

// Slack for yaw written with few digits (pi as 3.14159).
constexpr double kYawTextSlackRad = 1e-3;
// Pairs that rotate less than this on both sensors say nothing about the
// unit of the angles.
constexpr double kMinPairAngleRad = 1.0 * kPi / 180.0;
constexpr int kMinRotatingPairs = 3;
// The radian reading must be off by this much, and the other reading this
// many times closer, to call it a unit mistake.
constexpr double kMinAngleMismatchRad = 1.0 * kPi / 180.0;
constexpr double kUnitMismatchRatio = 0.2;

double Median(std::vector<double> values) {
  const size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + middle, values.end());
  return values[middle];
}

// Angle of a rotation by `angle_rad` about one axis, in [0, pi].
double FoldedAngle(double angle_rad) { return std::abs(WrapAngle(angle_rad)); }

std::string SpanText(int64_t first_ns, int64_t last_ns) {
  return FormatPrintf("%.3f", NsToSeconds(first_ns)) + "-" +
         FormatPrintf("%.3f", NsToSeconds(last_ns)) + " s";
}

}  // namespace

std::optional<std::string> YawStepProblem(double previous_yaw_rad,
                                          double yaw_rad,
                                          bool yaw_unit_named) {
  const double step = yaw_rad - previous_yaw_rad;
  if (!(std::abs(step) > kPi)) return std::nullopt;
  // A wrap: both samples in -pi..pi, or both in 0..2 pi.
  const auto within = [](double yaw, double low, double high) {
    return yaw >= low - kYawTextSlackRad && yaw <= high + kYawTextSlackRad;
  };
  if ((within(previous_yaw_rad, -kPi, kPi) && within(yaw_rad, -kPi, kPi)) ||
      (within(previous_yaw_rad, 0.0, 2.0 * kPi) &&
       within(yaw_rad, 0.0, 2.0 * kPi))) {
    return std::nullopt;
  }
  const std::string what =
      "yaw jumps from " + FormatPrintf("%.6g", previous_yaw_rad) + " to " +
      FormatPrintf("%.6g", yaw_rad) +
      " rad, more than pi and not a wrap of a yaw kept in -pi..pi or "
      "0..2 pi";
  if (yaw_unit_named) return what;
  return what +
         ": the yaw looks like degrees; name the column yaw_deg in the header "
         "or convert it to radians";
}

void CheckOdometrySpeed(const Trajectory& odometry) {
  std::vector<double> speeds;
  for (size_t i = 1; i < odometry.poses.size(); ++i) {
    const double dt = ElapsedSeconds(odometry.poses[i - 1].stamp_ns,
                                     odometry.poses[i].stamp_ns);
    const double distance =
        (odometry.poses[i].world_from_sensor.translation -
         odometry.poses[i - 1].world_from_sensor.translation)
            .norm();
    if (dt > 0.0 && std::isfinite(distance)) speeds.push_back(distance / dt);
  }
  if (speeds.empty()) return;
  const size_t k = (speeds.size() * 9) / 10;
  std::nth_element(speeds.begin(), speeds.begin() + k, speeds.end());
  const double speed = speeds[k];
  if (!(speed > kMaxOdometrySpeedMps)) return;
  throw FormatError(
      odometry.source + ": the odometry moves at " +
      FormatPrintf("%.1f", speed) +
      " m/s between samples (90th percentile), faster than " +
      FormatPrintf("%.0f", kMaxOdometrySpeedMps) +
      " m/s: the positions look like centimetres or millimetres; " +
      (odometry.planar
           ? "name the columns x_cm,y_cm or x_mm,y_mm in the header or convert "
             "them to metres"
           : "convert them to metres"));
}

void CheckRotationAngleUnits(const MotionPairs& pairs,
                             const std::string& odometry_source) {
  std::vector<double> as_radians, as_degrees, as_inverse;
  for (const MotionPair& pair : pairs) {
    const double odom = RotationAngle(pair.odom_i_from_odom_j.rotation);
    const double cam = RotationAngle(pair.cam_i_from_cam_j.rotation);
    if (!std::isfinite(odom) || !std::isfinite(cam)) continue;
    if (std::max(odom, cam) < kMinPairAngleRad) continue;
    as_radians.push_back(std::abs(odom - cam));
    as_degrees.push_back(std::abs(odom - FoldedAngle(cam * kRadToDeg)));
    as_inverse.push_back(std::abs(odom - cam / kRadToDeg));
  }
  if (static_cast<int>(as_radians.size()) < kMinRotatingPairs) return;
  const double radians = Median(as_radians);
  if (!(radians > kMinAngleMismatchRad)) return;
  const std::string over = " (median mismatch " +
                           FormatPrintf("%.2f", radians * kRadToDeg) +
                           " deg as given, ";
  const std::string pairs_text = " deg after the factor, over " +
                                 std::to_string(as_radians.size()) +
                                 " motion pairs)";
  const double degrees = Median(as_degrees);
  if (degrees < kUnitMismatchRatio * radians) {
    throw FormatError(
        odometry_source +
        ": the odometry turns 57.3 times as far as the camera in every motion "
        "pair" +
        over + FormatPrintf("%.2f", degrees * kRadToDeg) + pairs_text +
        ": the odometry yaw looks like degrees; name the column yaw_deg in the "
        "header or convert it to radians");
  }
  const double inverse = Median(as_inverse);
  if (inverse < kUnitMismatchRatio * radians) {
    throw FormatError(
        odometry_source +
        ": the odometry turns 57.3 times less than the camera in every motion "
        "pair" +
        over + FormatPrintf("%.2f", inverse * kRadToDeg) + pairs_text +
        ": the odometry yaw looks like radians read as degrees; name the "
        "column "
        "yaw or yaw_rad in the header");
  }
}

void CheckImageTimesAreNotFrameNumbers(std::vector<int64_t> stamps_ns,
                                       const std::string& source,
                                       const std::string& how_read) {
  std::sort(stamps_ns.begin(), stamps_ns.end());
  std::vector<double> intervals_ns;
  for (size_t i = 1; i < stamps_ns.size(); ++i) {
    if (stamps_ns[i] > stamps_ns[i - 1]) {
      intervals_ns.push_back(
          static_cast<double>(stamps_ns[i] - stamps_ns[i - 1]));
    }
  }
  if (intervals_ns.empty()) return;
  const double interval_ns = Median(intervals_ns);
  if (!(interval_ns < static_cast<double>(kMinImageIntervalNs))) return;
  throw FormatError(
      source + ": the image times were " + how_read + " and are " +
      FormatPrintf("%.6g", interval_ns * 1e-9) +
      " s apart (median): the names look like frame numbers, not times; "
      "pass --image_timestamps with a CSV image_name,timestamp (or "
      "--file_name_time_unit if the names are times)");
}

std::string TimeSpansText(const std::vector<Trajectory>& cameras,
                          const std::string& camera_times_origin,
                          int64_t camera_time_offset_ns,
                          const Trajectory& odometry,
                          bool offset_estimated) {
  int64_t first = 0, last = 0;
  bool any = false;
  for (const Trajectory& camera : cameras) {
    for (const StampedPose& pose : camera.poses) {
      first = any ? std::min(first, pose.stamp_ns) : pose.stamp_ns;
      last = any ? std::max(last, pose.stamp_ns) : pose.stamp_ns;
      any = true;
    }
  }
  std::string text =
      "camera times " + (any ? SpanText(first, last) : std::string("none"));
  std::string notes = camera_times_origin;
  if (camera_time_offset_ns != 0 || offset_estimated) {
    notes += std::string(notes.empty() ? "" : "; ") + "then shifted by " +
             (offset_estimated ? "the estimated offset " : "") +
             FormatPrintf("%.3f", NsToSeconds(camera_time_offset_ns)) + " s";
  }
  if (!notes.empty()) text += " (" + notes + ")";
  text += ", odometry ";
  text += odometry.poses.empty() ? std::string("none")
                                 : SpanText(odometry.poses.front().stamp_ns,
                                            odometry.poses.back().stamp_ns);
  return text;
}

std::optional<std::string> ExtrinsicDistanceWarning(
    const Rigid3d& odom_from_cam) {
  const double distance = odom_from_cam.translation.norm();
  if (!(distance > kMaxExtrinsicDistanceM)) return std::nullopt;
  return "the camera is " + FormatPrintf("%.2f", distance) +
         " m from the odometry origin, more than " +
         FormatPrintf("%.0f", kMaxExtrinsicDistanceM) +
         " m: check that the odometry positions are in metres (name the "
         "columns x_cm,y_cm "
         "or x_mm,y_mm otherwise)";
}

}  // namespace odomcal
