#include "odomcal/plugin/report/calibration_report.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/plugin/options/cli_flags.h"
#include "odomcal/plugin/report/report_testing.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace odomcal {
namespace {

using nlohmann::json;

Eigen::Matrix4d MatrixOf(const json& rows) {
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = rows.at(r).at(c).get<double>();
  }
  return m;
}

TEST(CalibrationToJson, ASuccessGivesTheEstimateConsistentlyInEveryForm) {
  const CalibrationRun run =
      SimulatedCalibrationRun(3, /*straight_only=*/false);
  ASSERT_TRUE(run.result.IsSuccess()) << run.result.message;
  const json out = CalibrationToJson(run.result, run.context);
  EXPECT_EQ(out["schema"], "odomcal.calibration");
  EXPECT_EQ(out["schema_version"], kResultSchemaVersion);
  EXPECT_EQ(out["status"], "success");

  const json& transform = out["odom_from_cam"];
  const json& q = transform["quaternion_wxyz"];
  const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
  EXPECT_NEAR(rotation.norm(), 1.0, 1e-12);
  EXPECT_GE(q[0].get<double>(), 0.0);  // the sign is fixed: w >= 0
  const Eigen::Matrix4d m = MatrixOf(transform["matrix"]);
  const Eigen::Matrix3d rotation_block = m.topLeftCorner(3, 3);
  EXPECT_TRUE(rotation_block.isApprox(rotation.toRotationMatrix(), 1e-12));
  for (int k = 0; k < 3; ++k) {
    EXPECT_DOUBLE_EQ(m(k, 3), transform["translation_m"][k].get<double>());
  }
  EXPECT_EQ(m.row(3), Eigen::RowVector4d(0.0, 0.0, 0.0, 1.0));
  EXPECT_DOUBLE_EQ(transform["translation_m"][2].get<double>(),
                   0.4);  // fixed z
  // roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll), degrees.
  const json& rpy = transform["roll_pitch_yaw_deg"];
  const Eigen::Matrix3d from_rpy =
      (Eigen::AngleAxisd(rpy[2].get<double>() * kDegToRad,
                         Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(rpy[1].get<double>() * kDegToRad,
                         Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(rpy[0].get<double>() * kDegToRad,
                         Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  EXPECT_TRUE(from_rpy.isApprox(rotation.toRotationMatrix(), 1e-9));
  EXPECT_TRUE((MatrixOf(out["cam_from_odom"]["matrix"]) * m)
                  .isApprox(Eigen::Matrix4d::Identity(), 1e-12));

  ASSERT_EQ(out["metric_scales"].size(), 1u);
  EXPECT_EQ(out["metric_scale"], out["metric_scales"][0]);
  EXPECT_GT(out["stddev"]["translation_x_m"].get<double>(), 0.0);
  const json& covariance = out["covariance"];
  EXPECT_EQ(covariance["order"], json({"rx", "ry", "rz", "tx", "ty", "s_0"}));
  ASSERT_EQ(covariance["matrix"].size(), 6u);
  for (const json& row : covariance["matrix"]) EXPECT_EQ(row.size(), 6u);
  const json& d = out["diagnostics"];
  EXPECT_EQ(d["inlier_mask"].size(), d["num_pairs_in"].get<size_t>());
  EXPECT_EQ(d["num_pairs_in"].get<size_t>(),
            run.context.association.pairs.size());
  EXPECT_EQ(out["inputs"]["command"], "odomcal calibrate");
}

// A quantity named in `unobservable` is null wherever it appears, and the
// inverse transform, which depends on all of them, is null too.
TEST(CalibrationToJson, UnobservableQuantitiesAreNullNeverNumbers) {
  CalibrationRun run = SimulatedCalibrationRun(3, /*straight_only=*/false);
  ASSERT_TRUE(run.result.has_estimate);
  const Observability estimated = run.result.observability;
  run.result.observability.translation_y = Determination::kUndetermined;
  run.result.observability.metric_scales[0] = Determination::kUndetermined;
  const json out = CalibrationToJson(run.result, run.context);
  const json& t = out["odom_from_cam"]["translation_m"];
  EXPECT_TRUE(t[0].is_number());
  EXPECT_TRUE(t[1].is_null());
  EXPECT_TRUE(t[2].is_number());  // fixed, not estimated
  EXPECT_EQ(out["unobservable"],
            json::array({"translation_z", "translation_y", "metric_scale"}));
  EXPECT_TRUE(out["odom_from_cam"]["quaternion_wxyz"].is_array());
  EXPECT_TRUE(out["cam_from_odom"].is_null());
  EXPECT_TRUE(out["metric_scales"][0].is_null());
  EXPECT_TRUE(out["metric_scale"].is_null());
  EXPECT_TRUE(out["stddev"]["translation_y_m"].is_null());
  EXPECT_TRUE(out["stddev"]["metric_scales_rel"][0].is_null());
  EXPECT_TRUE(
      out["diagnostics"]["closed_form"]["odom_from_cam"]["translation_m"][1]
          .is_null());

  run.result.observability = estimated;
  run.result.observability.rotation = Determination::kUndetermined;
  const json no_rotation = CalibrationToJson(run.result, run.context);
  for (const char* key : {"matrix", "quaternion_wxyz", "roll_pitch_yaw_deg"}) {
    EXPECT_TRUE(no_rotation["odom_from_cam"][key].is_null()) << key;
  }
  EXPECT_TRUE(no_rotation["stddev"]["yaw_deg"].is_null());
}

TEST(CalibrationToJson, AStraightDriveHasNoEstimateAndSaysWhatIsUndetermined) {
  const CalibrationRun run = SimulatedCalibrationRun(3, /*straight_only=*/true);
  ASSERT_FALSE(run.result.IsSuccess());
  const json out = CalibrationToJson(run.result, run.context);
  EXPECT_EQ(out["status"], ToString(run.result.status));
  EXPECT_FALSE(out["message"].get<std::string>().empty());
  if (!run.result.has_estimate) {
    EXPECT_TRUE(out["odom_from_cam"].is_null());
    EXPECT_TRUE(out["cam_from_odom"].is_null());
  }
  EXPECT_FALSE(out["unobservable"].empty());
  for (const json& scale : out["metric_scales"]) {
    EXPECT_TRUE(scale.is_null() || run.result.has_estimate);
  }
}

// The scale rows of the covariance are named by their segment: the middle
// one of three segments has no pairs, hence no row, and the order says so.
TEST(CalibrationToJson, CovarianceOrderNamesTheSegmentOfEachScaleRow) {
  MotionSimulatorOptions options;
  options.num_pairs = 60;
  options.num_segments = 3;
  std::mt19937_64 rng(5);
  SimulatedMotions motions = SimulateMotions(options, &rng);
  MotionPairs pairs;
  for (const MotionPair& pair : motions.pairs) {
    if (pair.segment != 1) pairs.push_back(pair);
  }
  ASSERT_EQ(NumSegments(pairs), 3);
  CalibrationOptions calibration;
  calibration.use_ransac = false;
  const CalibrationResult result = CalibrateOdomCam(pairs, calibration);
  ASSERT_TRUE(result.covariance.has_value()) << result.message;
  EXPECT_EQ(result.covariance_segments, (std::vector<int>{0, 2}));
  const json out = CalibrationToJson(result, ReportContext());
  EXPECT_EQ(out["covariance"]["order"],
            json({"rx", "ry", "rz", "tx", "ty", "s_0", "s_2"}));
  EXPECT_EQ(out["covariance"]["matrix"].size(), 7u);
  // Segment 2's scale: its row, not the (missing) second row's.
  const double stddev_2 =
      std::sqrt(out["covariance"]["matrix"][6][6].get<double>()) /
      result.metric_scales[2];
  EXPECT_NEAR(out["stddev"]["metric_scales_rel"][2].get<double>(),
              stddev_2,
              1e-12 * stddev_2);
}

// A library caller (no command line) gets the echo of the options it
// calibrated with, made from the same tables as the CLI's flags.
TEST(CalibrationToJson, TheOptionsEchoDefaultsToTheContextsOptions) {
  const CalibrationRun run =
      SimulatedCalibrationRun(3, /*straight_only=*/false);
  ReportContext context = run.context;
  context.flag_echo = nullptr;  // as a default-constructed context's
  context.calibration_options.robust_loss = RobustLoss::kHuber;
  context.calibration_options.noise.odom_yaw_sigma_deg = 0.7;
  context.association_options.keyframe_min_rotation_deg = 7.5;
  const json out = CalibrationToJson(run.result, context);
  EXPECT_EQ(out["options"]["robust_loss"], "huber");
  EXPECT_EQ(out["options"]["noise"]["odom_yaw_sigma_deg"], 0.7);
  // Automatic keyframe thresholds are echoed as the association chose them.
  ASSERT_TRUE(context.association.keyframe_spacing_automatic);
  EXPECT_EQ(out["inputs"]["keyframe_min_rotation_deg"],
            context.association.keyframe_min_rotation_deg);
  EXPECT_EQ(out["inputs"]["keyframe_spacing_automatic"], true);
  EXPECT_TRUE(out["diagnostics"]["association"].contains("camera_pose_drift"));
  // A threshold given is echoed as given.
  context.association.keyframe_spacing_automatic = false;
  EXPECT_EQ(CalibrationToJson(run.result,
                              context)["inputs"]["keyframe_min_rotation_deg"],
            7.5);
  // The gap limit is the one the association used, not the option's "auto".
  EXPECT_EQ(out["inputs"]["max_odometry_gap_s"],
            context.association.max_odometry_gap_s);
  for (const OptionRow<CalibrationOptions>& row : CalibrationOptionFlags()) {
    const json& object = row.echo_object.empty()
                             ? out["options"]
                             : out["options"][row.echo_object];
    EXPECT_TRUE(object.contains(row.echo_key)) << row.name;
  }
  for (const OptionRow<AssociationOptions>& row : AssociationFlags()) {
    EXPECT_TRUE(out["inputs"].contains(row.echo_key)) << row.name;
  }
  EXPECT_EQ(ReportContext().flag_echo, nullptr);
  // An echo given is written as given.
  context.flag_echo = json::object();
  EXPECT_EQ(CalibrationToJson(run.result, context)["options"], json::object());
}

// The clock offset is echoed as the decimal given (ns / 1e9), not as
// 1e-9 * ns, whose shortest text would be 0.7544807910000001.
TEST(CalibrationFlagsEcho, EchoesTheTimeOffsetAsGiven) {
  AssociationOptions association;
  association.camera_time_offset_ns = 754480791;
  const json echo = CalibrationFlagsEcho(association, CalibrationOptions());
  EXPECT_EQ(echo["inputs"]["camera_time_offset_s"].dump(), "0.754480791");
}

// The summary's input line counts the poses outside the odometry's span and
// in its gaps apart, and says the odometry's rate and the gap limit used.
TEST(AssociationSummary, CountsOutsideAndInGapsApart) {
  AssociationResult a;
  a.num_camera_poses = 282;
  a.num_usable_camera_poses = 4;
  a.num_outside_odometry_span = 1;
  a.num_in_odometry_gaps = 277;
  a.num_keyframes = 4;
  a.pairs.resize(3);
  a.odometry_rate_hz = 3.8;
  a.max_odometry_gap_s = 0.25;
  EXPECT_EQ(AssociationSummary(a),
            "282 camera poses: 4 used, 1 outside the odometry's span, 277 in "
            "its gaps (> 0.25 s); odometry at 3.8 Hz; 4 keyframes, 3 motion "
            "pairs");
  a.max_odometry_gap_s = 2.5 / 3.8;
  a.max_odometry_gap_automatic = true;
  EXPECT_NE(AssociationSummary(a).find("(> 0.658 s, automatic)"),
            std::string::npos)
      << AssociationSummary(a);
}

// The keyframes line says the spacing used and what the drift test saw.
TEST(KeyframeSpacingSummary, SaysWhatTheDriftTestSaw) {
  AssociationResult a;
  EXPECT_EQ(KeyframeSpacingSummary(a), "");  // thresholds given
  a.keyframe_spacing_automatic = true;
  a.keyframe_min_rotation_deg = 1.0;
  a.keyframe_min_translation_m = 0.02;
  a.keyframe_min_span_s = 0.237;
  a.camera_pose_drift.decided = true;
  a.camera_pose_drift.drifting = true;
  a.camera_pose_drift.span = 8;
  a.camera_pose_drift.rotation_ratio = 7.91;
  a.camera_pose_drift.translation_ratio = 8.52;
  a.camera_pose_drift.threshold = 4.5;
  EXPECT_EQ(KeyframeSpacingSummary(a),
            "every 1 deg / 0.02 m of odometry motion, 0.237 s apart at least "
            "(automatic): the camera poses drift (their error across the "
            "plane of motion over 8 frames is 7.91x in rotation and 8.52x in "
            "translation that over one; drift from 4.5x)");
  a.camera_pose_drift.decided = false;
  a.camera_pose_drift.drifting = false;
  EXPECT_NE(KeyframeSpacingSummary(a).find("not tested for drift"),
            std::string::npos);
}

}  // namespace
}  // namespace odomcal
