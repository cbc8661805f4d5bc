#include "odomcal/solver/planarity_check.h"

#include "odomcal/adapters/association.h"
#include "odomcal/datasets/simulation/climbing_road.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace odomcal {
namespace {

constexpr double kDeg = kDegToRad;

const Rigid3d kOdomFromCam = DriveSimulatorOptions().odom_from_cam;
constexpr double kScale = 0.37;

// A pair whose camera motion, mapped into the odometry frame, is the planar
// odometry motion (yaw, forward) tilted by `tilt` (a horizontal rotation
// vector, radians) and lifted by `lift_m`.
MotionPair TiltedPair(double yaw_deg,
                      double forward_m,
                      const Eigen::Vector3d& tilt,
                      double lift_m) {
  MotionPair pair;
  pair.odom_i_from_odom_j =
      Rigid3d(YawRotation(yaw_deg * kDeg), Eigen::Vector3d(forward_m, 0, 0));
  const Rigid3d odom_motion(
      ExpRotation(tilt) * pair.odom_i_from_odom_j.rotation,
      pair.odom_i_from_odom_j.translation + Eigen::Vector3d(0, 0, lift_m));
  Rigid3d cam_motion = Inverse(kOdomFromCam) * odom_motion * kOdomFromCam;
  cam_motion.translation /= kScale;
  pair.cam_i_from_cam_j = cam_motion;
  return pair;
}

TEST(PlanarityCheck, PerPairNumbersAreExactOnNoiseFreeData) {
  MotionPairs pairs;
  pairs.push_back(TiltedPair(20, 0.3, Eigen::Vector3d::Zero(), 0.0));
  pairs.push_back(TiltedPair(-15, 0.2, Eigen::Vector3d(0.3, 0.4, 0) * kDeg, 0));
  pairs.push_back(TiltedPair(5, 0.4, Eigen::Vector3d(0, -1.0, 0) * kDeg, 0.02));
  pairs.push_back(TiltedPair(-30, 0.1, Eigen::Vector3d::Zero(), -0.01));
  for (size_t i = 0; i < pairs.size(); ++i) {
    pairs[i].stamp_i_ns = 1000000000LL * i;
    pairs[i].stamp_j_ns = 1000000000LL * (i + 1);
  }
  const PlanarityCheck check =
      CheckPlanarity(pairs, {0, 1, 2, 3}, kOdomFromCam, {kScale}, NoiseModel());
  ASSERT_TRUE(check.checked);
  const double expected_tilt_deg[4] = {0.0, 0.5, 1.0, 0.0};
  for (size_t i = 0; i < pairs.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_NEAR(check.tilt_deg[i], expected_tilt_deg[i], 1e-9);
    // For planar odometry: the camera's displacement along odometry z.
    const Eigen::Vector3d camera_step =
        kScale *
        (kOdomFromCam.rotation * pairs[i].cam_i_from_cam_j.translation);
    EXPECT_NEAR(check.out_of_plane_m[i], camera_step.z(), 1e-12);
  }
  // A pure lift is the displacement itself; a pure tilt moves the camera
  // out of the plane through the lever arm.
  EXPECT_NEAR(check.out_of_plane_m[0], 0.0, 1e-12);
  EXPECT_NEAR(check.out_of_plane_m[3], -0.01, 1e-12);
  EXPECT_NEAR(check.tilt_max_deg, 1.0, 1e-9);
  EXPECT_NEAR(check.tilt_rms_deg, std::sqrt((0.25 + 1.0) / 4.0), 1e-9);
  EXPECT_EQ(check.degrees_of_freedom, 3 * 4 - 2);
  EXPECT_FALSE(check.consistent);  // 1 deg against 0.05 deg of camera noise
  EXPECT_GT(check.covariance_inflation, 1.0);
  EXPECT_NE(PlanarityWarning(check, 0).find("the motion is not planar: per "
                                            "motion pair the camera tilts "),
            std::string::npos);
}

// Two segments, listed late one first: the tilted pairs at the end of one and
// the start of the other are adjacent in the list, not in time. The worst
// stretch lies within one segment (3 pairs, 3 s), not across both.
TEST(PlanarityCheck, TheWorstStretchLiesWithinOneSegment) {
  MotionPairs pairs;
  std::vector<int> used;
  const int64_t kSecond = 1000000000;
  for (int i = 0; i < 20; ++i) {
    const bool tilted = i >= 8 && i <= 11;
    pairs.push_back(TiltedPair(i % 2 ? 12.0 : -7.0,
                               0.1 + 0.03 * i,
                               Eigen::Vector3d(tilted ? 1.0 : 0.0, 0, 0) * kDeg,
                               0));
    pairs.back().segment = i < 10 ? 0 : 1;
    const int64_t start = i < 10 ? (100 + i) * kSecond : (i - 10) * kSecond;
    pairs.back().stamp_i_ns = start;
    pairs.back().stamp_j_ns = start + kSecond;
    used.push_back(i);
  }
  const PlanarityCheck check =
      CheckPlanarity(pairs, used, kOdomFromCam, {kScale, kScale}, {});
  ASSERT_TRUE(check.checked);
  EXPECT_FALSE(check.consistent);
  EXPECT_EQ(check.worst_last_stamp_ns - check.worst_first_stamp_ns,
            3 * kSecond);
  EXPECT_NEAR(check.worst_tilt_rms_deg, std::sqrt(2.0 / 3.0), 1e-9);
}

TEST(PlanarityCheck, PlanarNoiseFreeMotionIsConsistent) {
  MotionPairs pairs;
  for (int i = 0; i < 10; ++i) {
    pairs.push_back(TiltedPair(
        i % 2 ? 12.0 : -7.0, 0.1 + 0.03 * i, Eigen::Vector3d::Zero(), 0));
  }
  const PlanarityCheck check = CheckPlanarity(
      pairs, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, kOdomFromCam, {kScale}, {});
  ASSERT_TRUE(check.checked);
  EXPECT_LT(check.tilt_max_deg, 1e-9);
  EXPECT_LT(check.out_of_plane_max_m, 1e-12);
  EXPECT_LT(check.chi_square, 1e-12);
  EXPECT_TRUE(check.consistent);
  EXPECT_EQ(check.covariance_inflation, 1.0);
}

TEST(PlanarityCheck, OdometryWithRollPitchOrHeightIsNotChecked) {
  MotionPairs pairs = {TiltedPair(20, 0.3, Eigen::Vector3d::Zero(), 0),
                       TiltedPair(-20, 0.3, Eigen::Vector3d::Zero(), 0)};
  EXPECT_TRUE(IsPlanarOdometry(pairs));
  pairs[1].odom_i_from_odom_j.translation.z() = 0.01;  // SE(3) odometry
  EXPECT_FALSE(IsPlanarOdometry(pairs));
  EXPECT_FALSE(
      CheckPlanarity(pairs, {0, 1}, kOdomFromCam, {kScale}, {}).checked);
  pairs[1].odom_i_from_odom_j.translation.z() = 0.0;
  pairs[0].odom_i_from_odom_j.rotation =
      ExpRotation(Eigen::Vector3d(0.01, 0, 0)) *
      pairs[0].odom_i_from_odom_j.rotation;
  EXPECT_FALSE(IsPlanarOdometry(pairs));
}

// The drive of `odomcal demo --simulated` (60 s here) on ground tilted by
// up to `tilt_deg`, calibrated like the demo (z held at its true value).
struct TiltedRun {
  SimulatedDrive drive;
  CalibrationResult result;
};

TiltedRun CalibrateTiltedDrive(uint64_t seed, double tilt_deg) {
  DriveSimulatorOptions options;
  options.seed = seed;
  options.ground_tilt_deg = tilt_deg;
  options.wheel_scale_error_left = 0.003;
  options.wheel_scale_error_right = -0.002;
  options.yaw_rate_bias_radps = 0.002;
  options.camera_rotation_noise_deg = 0.02;
  options.camera_position_noise = 0.002;
  TiltedRun run;
  run.drive = SimulateDrive(options);
  const AssociationResult association = AssociateCameraWithOdometry(
      {run.drive.camera}, run.drive.odometry, AssociationOptions());
  CalibrationOptions calibration;
  calibration.fixed_translation_z_m = options.odom_from_cam.translation.z();
  run.result = CalibrateOdomCam(association.pairs, calibration);
  return run;
}

bool NamesNonPlanarMotion(const CalibrationResult& result) {
  for (const std::string& warning : result.warnings) {
    if (warning.rfind("the motion is not planar", 0) == 0) return true;
  }
  return false;
}

TEST(TiltedGround, FlatDrivesPassWithTheirCovarianceUnchanged) {
  for (const uint64_t seed : {1, 2, 3, 4}) {
    SCOPED_TRACE(seed);
    const TiltedRun run = CalibrateTiltedDrive(seed, 0.0);
    ASSERT_EQ(run.result.status, CalibrationStatus::kSuccess);
    const PlanarityCheck& check = run.result.diagnostics.planarity;
    ASSERT_TRUE(check.checked);
    EXPECT_TRUE(check.consistent)
        << check.chi_square << " > " << check.chi_square_threshold;
    EXPECT_EQ(check.covariance_inflation, 1.0);
    EXPECT_FALSE(NamesNonPlanarMotion(run.result));
  }
}

// Flat ground: whatever excess the camera's noise leaves over the noise
// model (reduced chi-square up to about 1.2 on these drives, some above the
// 99.9 % point) is spread evenly along the drive and named no slope; the
// same drives over +-3 deg ground are named.
TEST(TiltedGround, NoSlopeNamedOnFlatGround) {
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    SCOPED_TRACE(seed);
    const TiltedRun flat = CalibrateTiltedDrive(seed, 0.0);
    ASSERT_EQ(flat.result.status, CalibrationStatus::kSuccess);
    const PlanarityCheck& check = flat.result.diagnostics.planarity;
    EXPECT_LT(check.correlation_length, kMinSlopeCorrelation);
    EXPECT_FALSE(check.named);
    EXPECT_FALSE(NamesNonPlanarMotion(flat.result));
  }
  for (const uint64_t seed : {1, 2}) {
    const TiltedRun tilted = CalibrateTiltedDrive(seed, 3.0);
    EXPECT_TRUE(tilted.result.diagnostics.planarity.named) << seed;
    EXPECT_TRUE(NamesNonPlanarMotion(tilted.result)) << seed;
  }
}

// At +-3 deg the planar covariance alone does not cover the error in at
// least one seed; the check names the motion and its inflated 3 sigma does.
TEST(TiltedGround, ThreeDegreesIsNamedAndCoveredWithinThreeSigma) {
  int covered_without_inflation = 0;
  for (const uint64_t seed : {1, 2, 3, 4}) {
    SCOPED_TRACE(seed);
    const TiltedRun run = CalibrateTiltedDrive(seed, 3.0);
    ASSERT_EQ(run.result.status, CalibrationStatus::kSuccess);
    EXPECT_TRUE(NamesNonPlanarMotion(run.result));
    const PlanarityCheck& check = run.result.diagnostics.planarity;
    EXPECT_FALSE(check.consistent);
    ASSERT_TRUE(run.result.covariance.has_value());
    const Eigen::MatrixXd& covariance = *run.result.covariance;
    const Eigen::Vector3d rotation_error =
        LogRotation(run.result.odom_from_cam.rotation *
                    run.drive.odom_from_cam.rotation.conjugate());
    const Eigen::Vector2d translation_error =
        (run.result.odom_from_cam.translation -
         run.drive.odom_from_cam.translation)
            .head<2>();
    bool covered_planar = true;
    for (int k = 0; k < 5; ++k) {
      const double error = k < 3 ? rotation_error(k) : translation_error(k - 3);
      const double sigma = std::sqrt(covariance(k, k));
      EXPECT_LE(std::abs(error), 3.0 * sigma) << "parameter " << k;
      covered_planar &= std::abs(error) <=
                        3.0 * sigma / std::sqrt(check.covariance_inflation);
    }
    covered_without_inflation += covered_planar;
  }
  EXPECT_LT(covered_without_inflation, 4);
}

// The limits on the standard deviations apply to the inflated ones: a
// rotation limit between the planar and the inflated sigma leaves the
// rotation undetermined.
TEST(TiltedGround, LimitsApplyToTheInflatedStandardDeviations) {
  DriveSimulatorOptions options;
  options.seed = 1;
  options.ground_tilt_deg = 3.0;
  options.camera_rotation_noise_deg = 0.02;
  options.camera_position_noise = 0.002;
  const SimulatedDrive drive = SimulateDrive(options);
  const AssociationResult association = AssociateCameraWithOdometry(
      {drive.camera}, drive.odometry, AssociationOptions());
  CalibrationOptions calibration;
  calibration.fixed_translation_z_m = options.odom_from_cam.translation.z();
  const CalibrationResult inflated =
      CalibrateOdomCam(association.pairs, calibration);
  ASSERT_EQ(inflated.status, CalibrationStatus::kSuccess);
  const double inflation = inflated.diagnostics.planarity.covariance_inflation;
  ASSERT_GT(inflation, 4.0);
  const double sigma = inflated.stddev_rotation_axes_deg.maxCoeff();
  calibration.max_rotation_stddev_deg = 0.5 * sigma;  // > the planar sigma
  ASSERT_GT(calibration.max_rotation_stddev_deg, sigma / std::sqrt(inflation));
  const CalibrationResult limited =
      CalibrateOdomCam(association.pairs, calibration);
  EXPECT_EQ(limited.status, CalibrationStatus::kUnobservable);
  EXPECT_EQ(limited.observability.rotation, Determination::kUndetermined);
}

// The same +-3 deg drives with SE(3) odometry (e.g. from an INS: the true
// 3-D poses): no planarity warning, translation z is estimated (started at
// 0), and rotation, x, y and z lie within their 3 sigma.
TEST(TiltedGround, Se3OdometryOfTheSameDriveEstimatesZWithinThreeSigma) {
  for (const uint64_t seed : {1, 2, 3, 4}) {
    SCOPED_TRACE(seed);
    DriveSimulatorOptions options;
    options.seed = seed;
    options.ground_tilt_deg = 3.0;
    options.camera_rotation_noise_deg = 0.02;
    options.camera_position_noise = 0.002;
    const SimulatedDrive drive = SimulateDrive(options);
    const AssociationResult association = AssociateCameraWithOdometry(
        {drive.camera}, drive.true_odometry, AssociationOptions());
    CalibrationOptions calibration;
    calibration.fixed_translation_z_m = 0.0;
    calibration.noise.odom_tilt_sigma_deg = 0.02;
    // z's standard deviation on these 60 s drives is 9-10 cm (the relative
    // tilts between keyframes are small): above the default limit of 5 cm,
    // where z is held and named; the limit is raised to see the estimate.
    calibration.max_translation_stddev_m = 0.2;
    const CalibrationResult result =
        CalibrateOdomCam(association.pairs, calibration);
    ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
    EXPECT_FALSE(result.diagnostics.planarity.checked);
    EXPECT_FALSE(NamesNonPlanarMotion(result));
    ASSERT_EQ(result.observability.translation_z, Determination::kEstimated);
    ASSERT_TRUE(result.covariance.has_value());
    const Eigen::MatrixXd& covariance = *result.covariance;
    const Eigen::Vector3d rotation_error =
        LogRotation(result.odom_from_cam.rotation *
                    drive.odom_from_cam.rotation.conjugate());
    const Eigen::Vector3d translation_error =
        result.odom_from_cam.translation - drive.odom_from_cam.translation;
    for (int k = 0; k < 5; ++k) {
      const double error = k < 3 ? rotation_error(k) : translation_error(k - 3);
      EXPECT_LE(std::abs(error), 3.0 * std::sqrt(covariance(k, k)))
          << "parameter " << k;
    }
    EXPECT_LE(std::abs(translation_error.z()),
              3.0 * result.stddev_translation_z_m)
        << "z " << result.odom_from_cam.translation.z() << " true "
        << drive.odom_from_cam.translation.z();
  }
}

TEST(TiltedGround, OdometryStaysPlanarWhileTheTruthTilts) {
  DriveSimulatorOptions options;
  options.seed = 5;
  const SimulatedDrive flat = SimulateDrive(options);
  options.ground_tilt_deg = 3.0;
  const SimulatedDrive tilted = SimulateDrive(options);
  EXPECT_TRUE(tilted.odometry.planar);
  EXPECT_FALSE(tilted.true_odometry.planar);
  double max_tilt_deg = 0.0, min_z = 0.0, max_z = 0.0;
  for (size_t k = 0; k < tilted.odometry.poses.size(); ++k) {
    // The wheel odometry is the flat drive's: it cannot see the ground.
    EXPECT_EQ(tilted.odometry.poses[k].world_from_sensor.translation,
              flat.odometry.poses[k].world_from_sensor.translation);
    const Rigid3d& truth = tilted.true_odometry.poses[k].world_from_sensor;
    const Eigen::Vector3d up = truth.rotation * Eigen::Vector3d::UnitZ();
    max_tilt_deg = std::max(max_tilt_deg, std::acos(up.z()) / kDeg);
    min_z = std::min(min_z, truth.translation.z());
    max_z = std::max(max_z, truth.translation.z());
  }
  // Slopes of +-3 deg along each of two axes: at most atan(sqrt(2) tan 3).
  EXPECT_GT(max_tilt_deg, 2.0);
  EXPECT_LT(max_tilt_deg, 4.25);
  EXPECT_GT(max_z - min_z, 0.05);  // the ground rises and falls
  EXPECT_NE(tilted.camera.poses[10].world_from_sensor.rotation.coeffs(),
            flat.camera.poses[10].world_from_sensor.rotation.coeffs());
}

bool NamesGroundTilt(const CalibrationResult& result) {
  for (const std::string& warning : result.warnings) {
    if (warning.rfind("the ground is not level", 0) == 0) return true;
  }
  return false;
}

// Planar odometry (x, y, yaw of each pose) of a car on a road whose banking
// varies within 0-3 deg and grade within 0-2.5 deg, camera 1.65 m up. The
// mean roll, 1.5 deg, is a different extrinsic to planar odometry: roll
// absorbs it (1.0-1.9 deg off, against a planar 3 sigma of about 0.25 deg)
// and y the height times it. The noise estimation takes the tilt for
// camera rotation noise (about 7x the model) and the chi-square under it
// passes; the tilt proportional to the turns is the ground's, named, and
// its covariance covers the error.
TEST(BankingRoad, PlanarOdometryNamesTheGroundAndCoversRollPitchXY) {
  ClimbingRoadOptions road;
  road.planar_odometry = true;
  road.max_bank_deg = 3.0;
  const CalibrationOptions options;
  for (const uint64_t seed : {1, 2, 3, 4}) {
    SCOPED_TRACE(seed);
    const CalibrationResult result = CalibrateOdomCam(
        ClimbingRoadPairs(road, &options.noise, seed), options);
    ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
    const PlanarityCheck& check = result.diagnostics.planarity;
    EXPECT_TRUE(check.ground_tilt_seen)
        << check.ground_f_statistic << " <= " << check.ground_f_threshold;
    EXPECT_TRUE(check.ground_named);
    EXPECT_TRUE(NamesGroundTilt(result));
    // The roll the ground's banking varies by (RMS 1.06 deg along the drive).
    EXPECT_GT(check.ground_roll_rms_deg, 0.5);
    EXPECT_LT(check.ground_roll_rms_deg, 2.0);
    const Eigen::Vector3d rotation_error_deg =
        kRadToDeg * LogRotation(road.odom_from_cam.rotation *
                                result.odom_from_cam.rotation.conjugate());
    const Eigen::Vector3d translation_error =
        result.odom_from_cam.translation - road.odom_from_cam.translation;
    // The bias the test is about: the mean banking in roll.
    EXPECT_GT(std::abs(rotation_error_deg(0)), 0.5);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(std::abs(rotation_error_deg(k)),
                3.0 * result.stddev_rotation_axes_deg(k))
          << "axis " << k;
    }
    for (int k = 0; k < 2; ++k) {
      EXPECT_LE(std::abs(translation_error(k)),
                3.0 * result.stddev_translation_xy_m(k))
          << "translation " << k;
    }
  }
}

// Flat ground, and ground rough by 0.3 deg of roll per keyframe without a
// mean or a trend: no ground tilt seen, nothing named or added.
TEST(BankingRoad, FlatOrRoughGroundIsNotNamed) {
  ClimbingRoadOptions road;
  road.planar_odometry = true;
  road.max_grade_deg = 0.0;
  const CalibrationOptions options;
  for (const double roll_sigma_deg : {0.0, 0.3}) {
    road.roll_sigma_deg = roll_sigma_deg;
    for (uint64_t seed = 1; seed <= 6; ++seed) {
      SCOPED_TRACE(seed);
      const CalibrationResult result = CalibrateOdomCam(
          ClimbingRoadPairs(road, &options.noise, seed), options);
      ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
      const PlanarityCheck& check = result.diagnostics.planarity;
      EXPECT_TRUE(check.ground_tested);
      EXPECT_FALSE(check.ground_tilt_seen)
          << check.ground_f_statistic << " > " << check.ground_f_threshold;
      EXPECT_FALSE(NamesGroundTilt(result));
    }
  }
}

}  // namespace
}  // namespace odomcal
