#include "odomcal/adapters/excitation_precheck.h"

#include "odomcal/solver/calibrate.h"

#include <algorithm>

namespace odomcal {
namespace {

// A camera looking forward (z_cam = x_odom, x_cam = -y_odom, y_cam = -z_odom)
// 20 cm ahead of and 5 cm beside the odometry origin. Any mount with a
// lever arm gives the same verdict: translation z is fixed by the solver,
// and the turns, not the mount, decide what is determined.
Rigid3d NominalOdomFromCam() {
  return Rigid3d(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5),
                 Eigen::Vector3d(0.2, 0.05, 0.0));
}

}  // namespace

ExcitationPrecheck PrecheckExcitation(
    const std::vector<int64_t>& image_stamps_ns,
    const Trajectory& odometry,
    const AssociationOptions& association,
    const CalibrationOptions& calibration,
    const SystematicsEstimationOptions& systematics) {
  association.Check();
  calibration.Check();
  std::vector<int64_t> stamps = image_stamps_ns;
  std::sort(stamps.begin(), stamps.end());
  stamps.erase(std::unique(stamps.begin(), stamps.end()), stamps.end());

  // world_from_cam of a perfect reconstruction (world = odometry origin, in
  // metres); images without an odometry pose keep their place in time, so
  // that the association breaks its chains there as it would after SfM.
  const Rigid3d odom_from_cam = NominalOdomFromCam();
  const double max_gap_s =
      OdometryGapLimitS(association.max_odometry_gap_s, odometry);
  Trajectory camera;
  camera.source = "images";
  for (const int64_t stamp : stamps) {
    InterpolationFailure why;
    const auto origin_from_odom = InterpolateOdometry(
        odometry, stamp + association.camera_time_offset_ns, max_gap_s, &why);
    StampedPose pose;
    pose.stamp_ns = stamp;
    pose.world_from_sensor =
        origin_from_odom ? *origin_from_odom * odom_from_cam : Rigid3d();
    camera.poses.push_back(pose);
  }

  // The given noise: estimated from exact poses it would run to its floor
  // and find determined what a real reconstruction leaves undetermined.
  CalibrationOptions given_noise = calibration;
  given_noise.estimate_noise = false;
  ExcitationPrecheck precheck;
  MotionPairs pairs;
  CalibrationResult ideal;
  EstimateSystematics(
      {camera},
      odometry,
      association,
      given_noise,
      systematics,
      [&](const AssociationResult& associated) {
        pairs = associated.pairs;
        ideal = CalibrateOdomCam(pairs, given_noise);
        return std::make_pair(static_cast<const MotionPairs*>(&pairs), &ideal);
      },
      &precheck.association);
  CalibrationResult& verdict = precheck.verdict;
  verdict.status = ideal.status;
  verdict.message = ideal.message;
  verdict.observability = ideal.observability;
  verdict.warnings = ideal.warnings;
  const CalibrationDiagnostics& d = ideal.diagnostics;
  verdict.diagnostics.num_pairs_in = d.num_pairs_in;
  verdict.diagnostics.yaw_increment_min_deg = d.yaw_increment_min_deg;
  verdict.diagnostics.yaw_increment_max_deg = d.yaw_increment_max_deg;
  verdict.diagnostics.yaw_increment_stddev_deg = d.yaw_increment_stddev_deg;
  verdict.diagnostics.num_rotating_pairs = d.num_rotating_pairs;
  verdict.diagnostics.num_left_turns = d.num_left_turns;
  verdict.diagnostics.num_right_turns = d.num_right_turns;
  precheck.determinable = ideal.status != CalibrationStatus::kNotEnoughMotion &&
                          ideal.status != CalibrationStatus::kUnobservable;
  return precheck;
}

}  // namespace odomcal
