// Clock offset and odometry intrinsics estimated with the extrinsic: the
// outer loop shared by `odomcal calibrate` and `odomcal colmap` / `run`.
//
//   1. coarse offset search (time_offset_search.h) around the given offset:
//      the start of step 3's offset. A flat peak (smooth motion) is a start
//      too, and the given offset another: the better fit is kept. Whether
//      the offset is estimated follows from its refined standard deviation,
//      never from the peak's shape; one that is not keeps the given value;
//   2. correct the odometry with the current intrinsics, associate at the
//      current offset, attach each pair's logged odometry
//      (odometry_increments.h) and calibrate with the caller's pipeline;
//   3. refine extrinsic, scales, offset change and intrinsics jointly over the
//      pairs the calibration used (solver/systematics_refine.h);
//   4. repeat 2-3 at the refined values until the offset changes by less than
//      tolerance_s and the yaw scale by less than 1e-6 (at most max_rounds);
//      the last calibration, at the final values, is the caller's result.
// Its covariance is then replaced by the joint one marginalised over the
// estimated systematics, so the stated uncertainty includes theirs.
// 3-D odometry (a TUM log): the clock offset alone, each pair's motion moved
// to the refined offset through its endpoint twists (AttachOdometryTwists)
// instead of re-integrated; the intrinsics, which re-integrate planar
// samples, keep identity and the reasons say so.
#pragma once

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/time_offset_search.h"
#include "odomcal/adapters/trajectory.h"
#include "odomcal/adapters/wheel_travel.h"
#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/odometry_intrinsics.h"
#include "odomcal/solver/systematics_refine.h"

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct SystematicsEstimationOptions {
  bool estimate_time_offset = true;
  double time_offset_search_s = 1.0;
  bool estimate_odometry_intrinsics = true;
  // Nominal wheel track, > 0 when given: report right_over_left and correct
  // the forward distance of turns (odometry_intrinsics.h).
  double wheel_track_m = 0.0;
  int max_rounds = 8;
  double tolerance_s = 1e-4;
  SystematicsOptions limits;
  // Encoder ticks per metre of a wheel-tick odometry log (wheel_travel.h),
  // > 0 when given.
  double wheel_ticks_per_m = 0.0;
};

// What reading a wheel-travel log needs from these options.
inline WheelTravelOptions WheelTravelOptionsOf(
    const SystematicsEstimationOptions& options) {
  return {options.wheel_track_m, options.wheel_ticks_per_m};
}

struct SystematicsEstimate {
  // Camera time offset the final association used (odometry_time =
  // camera_time + offset) and whether it was estimated.
  int64_t camera_time_offset_ns = 0;
  bool time_offset_estimated = false;
  double camera_time_offset_stddev_s = 0.0;
  std::string time_offset_reason;  // why held at the given value
  bool coarse_search_ran = false;
  double search_range_s = 0.0;
  TimeOffsetSearch coarse;

  OdometryIntrinsics intrinsics;  // identity unless estimated
  // [yaw_scale, yaw_per_metre_rad, yaw_rate_bias_rad_s]
  std::array<bool, 3> intrinsics_estimated{};
  std::array<double, 3> intrinsics_stddev{};
  std::vector<std::string> intrinsics_reasons;  // why each held one is held
  // k_right / k_left from yaw_scale and yaw_per_metre_rad with the track
  // given (yaw_per_metre = (k_r - k_l) / (k_track b), yaw_scale =
  // (k_l + k_r) / (2 k_track)): (1 + x) / (1 - x), x = b ypm / (2 yaw_scale).
  std::optional<double> right_over_left;
  double right_over_left_stddev = 0.0;

  int num_rounds = 0;
  // The odometry corrected with `intrinsics` (the input when not estimated).
  Trajectory corrected_odometry;
};

// Calibrates one association with the caller's pipeline and returns the
// pairs its result refers to (e.g. relabelled by the stretch check) and the
// result; both must stay valid until the next call.
using CalibrateAssociation =
    std::function<std::pair<const MotionPairs*, CalibrationResult*>(
        const AssociationResult&)>;

// `association` holds the given offset on entry and is the final association
// on return (the caller's calibration then is the last one `calibrate` made).
// Throws like AssociateCameraWithOdometry and SearchTimeOffset.
SystematicsEstimate EstimateSystematics(
    const std::vector<Trajectory>& cameras,
    const Trajectory& odometry,
    const AssociationOptions& association_options,
    const CalibrationOptions& calibration_options,
    const SystematicsEstimationOptions& options,
    const CalibrateAssociation& calibrate,
    AssociationResult* association);

}  // namespace odomcal
