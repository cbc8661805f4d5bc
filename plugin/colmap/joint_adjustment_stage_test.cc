// The joint adjustment through the project calibration: a simulated drive
// whose model drifts by 10 % in scale (points and poses), with points seen
// by the images. The adjusted model must lie on the truth in metres with
// only the calibrated transform applied, the extrinsic within its stated
// 3 sigma, and the drift reported.

#include "odomcal/plugin/colmap/joint_adjustment_stage.h"

#include "odomcal/adapters/association.h"
#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/plugin/colmap/joint_input.h"
#include "odomcal/plugin/report/colmap_report.h"
#include "odomcal/plugin/report/report_testing.h"
#include "odomcal/solver/angles.h"
#include "odomcal/tests/test_seed.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

class JointAdjustmentStageTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        fs::path(::testing::TempDir()) / (std::string("joint_") + info->name() +
                                          "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

SimulatedColmapProjectOptions DriftingProject(uint64_t seed) {
  SimulatedColmapProjectOptions options;
  options.seed = seed;
  options.duration_s = 20.0;
  options.scale_drift = 0.10;
  options.points_per_image = 12;
  return options;
}

TEST_F(JointAdjustmentStageTest, TakesTheDriftOutOfTheMetricModel) {
  SimulatedDrive drive;
  ColmapCalibrationInputs inputs = WriteSimulatedColmapProject(
      (dir_ / "project").string(), DriftingProject(TestSeed(7)), &drive);
  inputs.joint_adjustment.use = JointAdjustmentUse::kOn;
  std::vector<std::string> progress;
  const ColmapCalibrationRun run = CalibrateColmapProject(
      inputs,
      [&progress](const std::string& line) { progress.push_back(line); });
  const CalibrationResult& result = run.check.result;
  ASSERT_TRUE(result.has_estimate) << result.message;
  ASSERT_TRUE(run.joint.ran) << run.joint.skipped;
  // Every solver iteration is heard, the adjustment's and the jackknife's.
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(
      progress.front().rfind("joint adjustment: pass 1, iteration 0, ", 0), 0u)
      << progress.front();
  EXPECT_NE(progress.back().find("jackknife re-solve 8 of 8"),
            std::string::npos)
      << progress.back() << "; " << run.joint.jackknife.reason;
  const JointAdjustmentResult& joint = run.joint.result;
  ASSERT_TRUE(joint.IsSuccess()) << joint.message;
  // A planar log: whole robot poses on the ground, which the images find
  // level (the simulated drive's floor is).
  EXPECT_EQ(joint.motion_model, RobotMotionModel::kOnGround);
  EXPECT_LT(joint.max_robot_tilt_deg, 0.2);
  EXPECT_LT(joint.ground_tilt_rate_deg_per_m, 0.1);
  // The two-step cut the drifting model into parts; the adjustment joins
  // them into one.
  ASSERT_EQ(run.metric_models.size(), 1u);
  EXPECT_FALSE(run.metric_models[0].origin_from_sfm.has_value());
  EXPECT_GT(run.joint.max_scale_change, 0.02);

  // The result is the adjustment's, within its stated 3 sigma.
  const Eigen::Vector3d rotation_error = LogRotation(
      result.odom_from_cam.rotation * drive.odom_from_cam.rotation.conjugate());
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(std::abs(rotation_error[k]),
              3.0 * result.stddev_rotation_axes_deg[k] * kDegToRad)
        << "axis " << k;
  }
  for (int k = 0; k < 2; ++k) {
    EXPECT_LT(std::abs(result.odom_from_cam.translation[k] -
                       drive.odom_from_cam.translation[k]),
              3.0 * result.stddev_translation_xy_m[k])
        << "translation " << k;
  }

  // Camera centres against the truth, nothing but the calibration applied:
  // within 0.2 % of the path length or 5 mm.
  std::map<std::string, int64_t> stamps;
  for (size_t i = 0; i < run.segments[0].image_names.size(); ++i) {
    stamps.emplace(run.segments[0].image_names[i],
                   run.segments[0].trajectory.poses[i].stamp_ns);
  }
  double path_length = 0.0;
  for (size_t i = 1; i < drive.true_odometry.poses.size(); ++i) {
    path_length +=
        (drive.true_odometry.poses[i].world_from_sensor.translation -
         drive.true_odometry.poses[i - 1].world_from_sensor.translation)
            .norm();
  }
  const double tolerance = std::max(0.005, 0.002 * path_length);
  double worst = 0.0;
  for (const auto& [id, image] : run.metric_models[0].model.images) {
    const auto origin_from_odom = InterpolateOdometry(
        drive.true_odometry, stamps.at(image.name), 1.0, nullptr);
    ASSERT_TRUE(origin_from_odom.has_value());
    const Eigen::Vector3d truth =
        (*origin_from_odom * drive.odom_from_cam).translation;
    worst = std::max(
        worst, (Inverse(image.cam_from_world).translation - truth).norm());
  }
  EXPECT_LT(worst, tolerance) << "path " << path_length << " m";

  // The JSON carries the adjustment and the two-step estimate it replaced.
  const nlohmann::json json = ColmapCalibrationToJson(
      run, ProjectReportContext(inputs, run, "odomcal colmap"));
  EXPECT_EQ(json["joint_adjustment"]["status"], "success");
  EXPECT_TRUE(json["diagnostics"]["two_step"].is_object());
  EXPECT_FALSE(json["joint_adjustment"]["stretches"].empty());
}

TEST_F(JointAdjustmentStageTest, OffLeavesTheTwoStepResult) {
  ColmapCalibrationInputs inputs = WriteSimulatedColmapProject(
      (dir_ / "project").string(), DriftingProject(TestSeed(8)));
  inputs.joint_adjustment.use = JointAdjustmentUse::kOff;
  const ColmapCalibrationRun run = CalibrateColmapProject(inputs);
  EXPECT_FALSE(run.joint.requested);
  const nlohmann::json json = ColmapCalibrationToJson(
      run, ProjectReportContext(inputs, run, "odomcal colmap"));
  EXPECT_TRUE(json["joint_adjustment"].is_null());
  EXPECT_TRUE(json["diagnostics"]["two_step"].is_null());
  EXPECT_GT(run.metric_models.size(), 1u);  // the drift's parts
}

std::map<std::string, int64_t> StampOfImage(const ColmapCalibrationRun& run) {
  std::map<std::string, int64_t> stamps;
  for (const ColmapSegment& segment : run.segments) {
    for (size_t i = 0; i < segment.image_names.size(); ++i) {
      stamps.emplace(segment.image_names[i],
                     segment.trajectory.poses[i].stamp_ns);
    }
  }
  return stamps;
}

TEST_F(JointAdjustmentStageTest, TheDefaultCheckKeepsATwoStepItAgreesWith) {
  SimulatedColmapProjectOptions options = DriftingProject(TestSeed(10));
  options.scale_drift = 0.0;
  const ColmapCalibrationInputs inputs =
      WriteSimulatedColmapProject((dir_ / "project").string(), options);
  ASSERT_EQ(inputs.joint_adjustment.use, JointAdjustmentUse::kCheck);
  ColmapCalibrationInputs off = inputs;
  off.joint_adjustment.use = JointAdjustmentUse::kOff;
  const ColmapCalibrationRun two_step = CalibrateColmapProject(off);
  const ColmapCalibrationRun run = CalibrateColmapProject(inputs);
  ASSERT_TRUE(run.check.result.has_estimate) << run.check.result.message;
  ASSERT_TRUE(run.joint.ran && run.joint.result.IsSuccess())
      << run.joint.skipped << run.joint.result.message;
  EXPECT_FALSE(run.joint.adopted);
  EXPECT_LE(run.joint.max_disagreement_sigmas, kJointContradictionSigmas);
  EXPECT_FALSE(run.joint.jackknife.ran);  // needed only for its estimate
  // The reported extrinsic is the two-step's, bit for bit.
  EXPECT_TRUE(run.check.result.odom_from_cam.rotation.coeffs().isApprox(
      two_step.check.result.odom_from_cam.rotation.coeffs(), 0.0));
  EXPECT_EQ(run.check.result.odom_from_cam.translation,
            two_step.check.result.odom_from_cam.translation);
  EXPECT_EQ(run.metric_models.size(), two_step.metric_models.size());
  const nlohmann::json json = ColmapCalibrationToJson(
      run, ProjectReportContext(inputs, run, "odomcal colmap"));
  EXPECT_EQ(json["joint_adjustment"]["use"], "check");
  EXPECT_EQ(json["joint_adjustment"]["adopted"], false);
  EXPECT_TRUE(json["diagnostics"]["two_step"].is_null());
}

TEST_F(JointAdjustmentStageTest,
       TheCheckReportsTheAdjustmentWhereItContradicts) {
  const ColmapCalibrationInputs inputs = WriteSimulatedColmapProject(
      (dir_ / "project").string(), DriftingProject(TestSeed(11)));
  ColmapCalibrationInputs off = inputs;
  off.joint_adjustment.use = JointAdjustmentUse::kOff;
  ColmapCalibrationRun run = CalibrateColmapProject(off);
  CalibrationResult& result = run.check.result;
  ASSERT_TRUE(result.has_estimate && result.covariance) << result.message;
  // A two-step estimate biased far beyond its sigma, as a model whose
  // scale drifts inside a segment gives it: 1.5 deg about the odometry's x.
  const Rigid3d truth_like = result.odom_from_cam;
  result.odom_from_cam.rotation =
      Eigen::Quaterniond(
          Eigen::AngleAxisd(1.5 * kDegToRad, Eigen::Vector3d::UnitX())) *
      result.odom_from_cam.rotation;
  // Its halves disagreeing, as such a model's may.
  result.warnings.push_back(
      "the calibration does not repeat: the halves of the drive disagree");
  ApplyJointAdjustment(inputs, StampOfImage(run), nullptr, &run);
  ASSERT_TRUE(run.joint.result.IsSuccess()) << run.joint.result.message;
  EXPECT_GT(run.joint.max_disagreement_sigmas, kJointContradictionSigmas);
  EXPECT_TRUE(run.joint.adopted);
  EXPECT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
  const auto repeat = std::find_if(
      result.warnings.begin(), result.warnings.end(), [](const auto& w) {
        return w.rfind("the calibration does not repeat:", 0) == 0;
      });
  ASSERT_NE(repeat, result.warnings.end());
  EXPECT_NE(
      repeat->find("the disagreement may be that model's, not the mount's"),
      std::string::npos)
      << *repeat;
  EXPECT_TRUE(run.joint.jackknife.ran) << run.joint.jackknife.reason;
  // The adjustment came back from the bias, and says so.
  EXPECT_LT(RotationAngle(result.odom_from_cam.rotation *
                          truth_like.rotation.conjugate()),
            0.2 * kDegToRad);
  bool named = false;
  for (const std::string& warning : result.warnings) {
    named |=
        warning.find("contradict the two-step estimate") != std::string::npos;
  }
  EXPECT_TRUE(named);
  ASSERT_EQ(run.metric_models.size(), 1u);  // the adjusted model
}

TEST_F(JointAdjustmentStageTest, AModelWithoutPointsIsNamedNotAdjusted) {
  SimulatedColmapProjectOptions options = DriftingProject(TestSeed(9));
  options.points_per_image = 0;
  ColmapCalibrationInputs inputs =
      WriteSimulatedColmapProject((dir_ / "project").string(), options);
  inputs.joint_adjustment.use = JointAdjustmentUse::kOn;
  const ColmapCalibrationRun run = CalibrateColmapProject(inputs);
  ASSERT_TRUE(run.check.result.has_estimate);
  EXPECT_FALSE(run.joint.result.IsSuccess());
  bool named = false;
  for (const std::string& warning : run.check.result.warnings) {
    named |= warning.rfind("joint adjustment", 0) == 0;
  }
  EXPECT_TRUE(named);
  EXPECT_TRUE(run.check.result.has_estimate);
}

// --joint_intrinsics auto: a camera is refined where the model's intrinsics
// differ from the database's (COLMAP's bundle adjustment changed them),
// held where they are the database's or there is no database.
TEST_F(JointAdjustmentStageTest, AutoRefinesOnlyIntrinsicsColmapChanged) {
  ColmapCalibrationInputs inputs = WriteSimulatedColmapProject(
      (dir_ / "project").string(), DriftingProject(TestSeed(11)));
  inputs.joint_adjustment.use = JointAdjustmentUse::kOff;
  ColmapCalibrationRun run = CalibrateColmapProject(inputs);
  ASSERT_TRUE(run.check.result.has_estimate) << run.check.result.message;
  ASSERT_FALSE(run.metric_models.empty());
  const auto held = [&](JointIntrinsics intrinsics) {
    JointInput input;
    input.problem.odom_from_cam = run.check.result.odom_from_cam;
    EXPECT_EQ(AddMetricModels(run, StampOfImage(run), intrinsics, &input), "");
    EXPECT_FALSE(input.problem.cameras.empty());
    bool all_held = true;
    for (const JointCamera& camera : input.problem.cameras) {
      all_held = all_held && camera.held;
    }
    return all_held;
  };
  EXPECT_TRUE(run.database_cameras.empty());  // no database given
  EXPECT_TRUE(held(JointIntrinsics::kAuto));
  for (const auto& [id, camera] : run.metric_models[0].model.cameras) {
    run.database_cameras[id] = camera;  // as given: not changed
  }
  EXPECT_TRUE(held(JointIntrinsics::kAuto));
  for (auto& [id, camera] : run.database_cameras) camera.params[0] *= 1.01;
  EXPECT_FALSE(held(JointIntrinsics::kAuto));
  EXPECT_FALSE(held(JointIntrinsics::kRefined));
}

}  // namespace
}  // namespace odomcal
