#include "odomcal/adapters/excitation_precheck.h"

#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/datasets/simulation/model_noise.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace odomcal {
namespace {

// The JSON `unobservable` list of a result.
std::vector<std::string> Unobservable(const CalibrationResult& result) {
  return UnobservableNames(result.observability);
}
constexpr int64_t kBaseNs = 1700000000000000000;
constexpr int64_t kOdometryStepNs = 20000000;  // 50 Hz
constexpr int64_t kImageStepNs = 500000000;    // 2 Hz

// A planar odometry log integrated from speed (m/s) and yaw rate (rad/s)
// at time t, and image times every image_step_ns (0.5 s) over it.
struct Drive {
  Trajectory odometry;
  std::vector<int64_t> image_stamps_ns;
};

Drive Integrate(
    const std::function<Eigen::Vector2d(double)>& speed_and_yaw_rate,
    double duration_s,
    int64_t image_step_ns = kImageStepNs) {
  Drive drive;
  drive.odometry.planar = true;
  double x = 0.0, y = 0.0, yaw = 0.0;
  const double step_s = kOdometryStepNs / 1e9;
  const int num_steps = static_cast<int>(std::lround(duration_s / step_s));
  for (int k = 0; k <= num_steps; ++k) {
    const int64_t stamp = kBaseNs + k * kOdometryStepNs;
    drive.odometry.poses.push_back(
        {stamp, Rigid3d(YawRotation(yaw), Eigen::Vector3d(x, y, 0.0))});
    if ((stamp - kBaseNs) % image_step_ns == 0)
      drive.image_stamps_ns.push_back(stamp);
    const Eigen::Vector2d v_w = speed_and_yaw_rate(k * step_s);
    const double mid_yaw = yaw + 0.5 * v_w(1) * step_s;
    x += v_w(0) * step_s * std::cos(mid_yaw);
    y += v_w(0) * step_s * std::sin(mid_yaw);
    yaw += v_w(1) * step_s;
  }
  return drive;
}

// The drive as it is recorded and reconstructed: the odometry log and a
// reconstruction by a camera on another mount (0.37 m per unit), both as
// noisy as the default noise model says (model_noise.h).
struct Recording {
  Drive drive;
  Trajectory camera;
};

Recording Record(const Drive& truth, uint64_t seed) {
  const Rigid3d odom_from_cam(
      Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5).normalized() *
          Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX())),
      Eigen::Vector3d(0.25, -0.1, 0.4));
  Recording recording;
  recording.drive = truth;
  recording.drive.odometry = WithModelOdometryNoise(
      truth.odometry, truth.image_stamps_ns, NoiseModel(), 1.0, seed);
  recording.camera = ModelNoisyReconstruction(truth.odometry,
                                              truth.image_stamps_ns,
                                              truth.image_stamps_ns,
                                              odom_from_cam,
                                              0.37,
                                              NoiseModel(),
                                              1.0,
                                              seed + 1000);
  return recording;
}

// What the calibration says (as `odomcal calibrate` runs it:
// EstimateSystematics around CalibrateOdomCam, defaults): the pre-check must
// say the same from the odometry alone.
CalibrationResult Calibrate(const Recording& recording) {
  MotionPairs pairs;
  CalibrationResult result;
  AssociationResult association;
  EstimateSystematics(
      {recording.camera},
      recording.drive.odometry,
      AssociationOptions(),
      CalibrationOptions(),
      SystematicsEstimationOptions(),
      [&](const AssociationResult& associated) {
        pairs = associated.pairs;
        result = CalibrateOdomCam(pairs, CalibrationOptions());
        return std::make_pair(static_cast<const MotionPairs*>(&pairs), &result);
      },
      &association);
  return result;
}

CalibrationResult SolverOnReconstruction(const Drive& truth,
                                         uint64_t seed = 1) {
  return Calibrate(Record(truth, seed));
}

ExcitationPrecheck Precheck(const Drive& drive) {
  return PrecheckExcitation(drive.image_stamps_ns,
                            drive.odometry,
                            AssociationOptions(),
                            CalibrationOptions(),
                            SystematicsEstimationOptions());
}

TEST(PrecheckExcitation, StraightDriveDeterminesNeitherRotationNorLeverArm) {
  const Drive drive =
      Integrate([](double) { return Eigen::Vector2d(0.3, 0.0); }, 60.0);
  const ExcitationPrecheck precheck = Precheck(drive);
  EXPECT_FALSE(precheck.determinable);
  EXPECT_EQ(precheck.verdict.status, CalibrationStatus::kUnobservable);
  // The solver's rule: no turn leaves the rotation and the x/y lever arm
  // free (the scale is the ratio of the step lengths, but no calibration
  // comes of it).
  EXPECT_EQ(
      Unobservable(precheck.verdict),
      (std::vector<std::string>{
          "rotation", "translation_x", "translation_y", "translation_z"}));
  EXPECT_EQ(precheck.verdict.message,
            "no motion pair rotates by more than 2 deg (straight driving or no "
            "motion): the "
            "rotation and the x/y translation of the extrinsic cannot be "
            "determined; drive "
            "turns in both directions");
  EXPECT_FALSE(precheck.verdict.has_estimate);
  EXPECT_EQ(precheck.verdict.diagnostics.num_rotating_pairs, 0);
  EXPECT_GT(precheck.association.pairs.size(), 100u);
  const CalibrationResult solver = SolverOnReconstruction(drive);
  EXPECT_EQ(solver.status, precheck.verdict.status);
  EXPECT_EQ(Unobservable(solver), Unobservable(precheck.verdict));
}

TEST(PrecheckExcitation, OneTurnIsTooFewRotatingPairs) {
  // Straight, but for a 6 deg turn within one image interval.
  const Drive drive = Integrate(
      [](double t) {
        return Eigen::Vector2d(
            0.3, t >= 20.0 && t < 20.5 ? 6.0 * kPi / 180.0 / 0.5 : 0.0);
      },
      40.0);
  const ExcitationPrecheck precheck = Precheck(drive);
  EXPECT_FALSE(precheck.determinable);
  EXPECT_EQ(precheck.verdict.status, CalibrationStatus::kNotEnoughMotion);
  EXPECT_EQ(precheck.verdict.message,
            "only 1 motion pairs rotate by more than 2 deg; 2 are needed");
  EXPECT_EQ(SolverOnReconstruction(drive).status,
            CalibrationStatus::kNotEnoughMotion);
}

// Circles of one radius, all to the left: every motion pair is the same, so
// the rotation and the lever arm are not determined. The pre-check refuses
// as the solver refuses after SfM; the names can differ by a quantity whose
// standard deviation is near its limit (here the scale, which the noise of
// the one reconstruction takes over it).
TEST(PrecheckExcitation, TurnsOfOneSizeInOneDirectionAsTheSolverSays) {
  const Drive drive =
      Integrate([](double) { return Eigen::Vector2d(0.3, 0.3); }, 60.0);
  const Recording recording = Record(drive, 1);
  const ExcitationPrecheck precheck = Precheck(recording.drive);
  const CalibrationResult solver = Calibrate(recording);
  EXPECT_EQ(precheck.verdict.status, solver.status) << solver.message;
  EXPECT_FALSE(precheck.determinable) << precheck.verdict.message;
  EXPECT_EQ(precheck.verdict.status, CalibrationStatus::kUnobservable);
  const std::vector<std::string> solver_names =
      UndeterminedNames(solver.observability);
  const std::vector<std::string> names =
      UndeterminedNames(precheck.verdict.observability);
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(names.front(), "rotation") << precheck.verdict.message;
  for (const std::string& name : names) {
    EXPECT_NE(std::find(solver_names.begin(), solver_names.end(), name),
              solver_names.end())
        << name << " is not named by the solver: " << solver.message;
  }
  EXPECT_FALSE(precheck.verdict.has_estimate)
      << "the nominal mount is no estimate";
}

// Left turns of changing size determine everything the solver estimates.
TEST(PrecheckExcitation, TurnsOfDifferentSizesInOneDirectionAsTheSolverSays) {
  const Drive drive = Integrate(
      [](double t) {
        return Eigen::Vector2d(0.3, 0.2 + 0.2 * std::sin(0.3 * t));
      },
      60.0);
  const Recording recording = Record(drive, 1);
  const ExcitationPrecheck precheck = Precheck(recording.drive);
  const CalibrationResult solver = Calibrate(recording);
  EXPECT_EQ(precheck.verdict.status, solver.status) << solver.message;
  EXPECT_EQ(Unobservable(precheck.verdict), Unobservable(solver));
  EXPECT_EQ(precheck.determinable,
            solver.status == CalibrationStatus::kSuccess);
}

// A car's drive: 52 m at 10 m/s with one 98 deg right turn (0.6 rad/s,
// 0.5 s ramps), 10 Hz images. Every turn goes one way at nearly one rate, so
// the lateral lever arm and the scale barely separate: under the noise of
// a real reconstruction the calibration refuses translation y, and the
// pre-check must refuse it with the same reason (exact poses alone would let
// the noise estimation find the noise at its floor and pass the drive).
Drive RoadDriveWithOneRightTurn() {
  return Integrate(
      [](double t) {
        const double peak = 0.6, ramp = 0.5, begin = 0.925;
        const double end = begin + 98.0 * kDegToRad / peak + ramp;
        double rate = peak;
        if (t < begin || t >= end) {
          rate = 0.0;
        } else if (t < begin + ramp) {
          rate = peak * (t - begin) / ramp;
        } else if (t >= end - ramp) {
          rate = peak * (end - t) / ramp;
        }
        return Eigen::Vector2d(10.0, -rate);
      },
      5.2,
      100000000);
}

TEST(PrecheckExcitation, OneRightTurnIsRefusedWithTheCalibrationsReason) {
  for (const uint64_t seed : {1, 2, 3}) {
    const Recording recording = Record(RoadDriveWithOneRightTurn(), seed);
    const ExcitationPrecheck precheck = Precheck(recording.drive);
    EXPECT_EQ(precheck.verdict.diagnostics.num_left_turns, 0);
    EXPECT_GT(precheck.verdict.diagnostics.num_right_turns, 20);
    EXPECT_FALSE(precheck.determinable) << precheck.verdict.message;
    EXPECT_EQ(precheck.verdict.status, CalibrationStatus::kUnobservable);
    EXPECT_NE(precheck.verdict.message.find("translation_y"), std::string::npos)
        << precheck.verdict.message;
    const CalibrationResult solver = Calibrate(recording);
    EXPECT_EQ(solver.status, precheck.verdict.status) << solver.message;
    EXPECT_EQ(solver.message, precheck.verdict.message);
    EXPECT_EQ(Unobservable(solver), Unobservable(precheck.verdict));
  }
}

TEST(PrecheckExcitation, DriveWithTurnsBothWaysPasses) {
  const Drive drive = Integrate(
      [](double t) { return Eigen::Vector2d(0.3, 0.5 * std::sin(0.4 * t)); },
      60.0);
  const Recording recording = Record(drive, 1);
  const ExcitationPrecheck precheck = Precheck(recording.drive);
  EXPECT_TRUE(precheck.determinable) << precheck.verdict.message;
  EXPECT_EQ(precheck.verdict.status, CalibrationStatus::kSuccess);
  EXPECT_GT(precheck.verdict.diagnostics.num_left_turns, 0);
  EXPECT_GT(precheck.verdict.diagnostics.num_right_turns, 0);
  EXPECT_EQ(Calibrate(recording).status, CalibrationStatus::kSuccess);
}

// Images outside the odometry take part in no pair; none at all: too few.
TEST(PrecheckExcitation, ImagesOutsideTheOdometryGiveNoPairs) {
  Drive drive = Integrate(
      [](double t) { return Eigen::Vector2d(0.3, 0.5 * std::sin(0.4 * t)); },
      60.0);
  for (int64_t& stamp : drive.image_stamps_ns) stamp += 3600LL * 1000000000LL;
  const ExcitationPrecheck precheck = Precheck(drive);
  EXPECT_FALSE(precheck.determinable);
  EXPECT_EQ(precheck.verdict.status, CalibrationStatus::kNotEnoughMotion);
  EXPECT_EQ(precheck.association.num_usable_camera_poses, 0);
}

}  // namespace
}  // namespace odomcal
