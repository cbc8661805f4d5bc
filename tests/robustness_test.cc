// Bad inputs to the odomcal executable, one test per row of
// docs/robustness.md: each asserts the exact error line (or the result
// status) and the exit code. Rows already checked elsewhere are listed in
// that document with their own tests.
//
// The executable is started with fork/exec (no shell) so that a test can
// change its PATH or limit the size of the files it may write.

#include "odomcal/tests/robustness_fixture.h"

namespace odomcal::robustness_test {
namespace {

TEST_F(Robustness, MissingInputFile) {
  WriteDrive();
  std::vector<std::string> arguments = Calibrate();
  arguments[2] = Path("missing.tum");
  ExpectBadInput(
      RunOdomcal(arguments),
      std::string(kCalibrateError) +
          "--camera_poses: File does not exist: " + Path("missing.tum"));
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

// As root every file is readable, so a folder given as a file and a file
// whose read() fails (/proc/self/mem at offset 0: EIO) stand in for a file
// without read permission; that case runs only when not root.
TEST_F(Robustness, UnreadableInputFile) {
  WriteDrive();
  fs::create_directories(Path("folder.csv"));
  std::vector<std::string> arguments = Calibrate();
  arguments[4] = Path("folder.csv");
  ExpectBadInput(
      RunOdomcal(arguments),
      std::string(kCalibrateError) +
          "--odometry: File is actually a directory: " + Path("folder.csv"));

  arguments[4] = "/proc/self/mem";
  ExpectBadInput(RunOdomcal(arguments),
                 std::string(kCalibrateError) + "/proc/self/mem:1: read error");

  if (::geteuid() != 0) {
    ::chmod(Path("odometry.csv").c_str(), 0);
    arguments[4] = Path("odometry.csv");
    ExpectBadInput(RunOdomcal(arguments),
                   std::string(kCalibrateError) + Path("odometry.csv") +
                       ": cannot open for reading: Permission denied");
  }
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

// ---------------------------------------------------------------------------
// COLMAP models.

TEST_F(Robustness, TruncatedColmapBinary) {
  WriteColmapProject();
  const std::string bytes = ReadFile(Model("images.bin"));
  // Cut early: the image count no longer fits in what is left.
  WriteFile(Model("images.bin"), bytes.substr(0, 100));
  ExpectBadInput(
      RunOdomcal(Colmap()),
      std::string(kColmapError) + Model("images.bin") +
          ": byte 0: number of images is 301, but the 92 remaining bytes "
          "hold at most 1 (garbled or truncated file)");
  // Cut inside the last record.
  WriteFile(Model("images.bin"), bytes.substr(0, bytes.size() - 3));
  ExpectBadInputContaining(
      RunOdomcal(Colmap()),
      std::string(kColmapError) + Model("images.bin") + ": byte ",
      {": image 301 of 301 (image_id 601, '000600.png'): truncated: "
       "number of points2D needs 8 bytes, 5 remain"});
  EXPECT_FALSE(fs::exists(Path("out/calibration.json")));
}

TEST_F(Robustness, ColmapBinaryCountLargerThanTheFile) {
  WriteColmapProject();
  std::string bytes = ReadFile(Model("images.bin"));
  const uint64_t huge = uint64_t{1} << 60;
  bytes.replace(
      0, 8, reinterpret_cast<const char*>(&huge), 8);  // little-endian host
  WriteFile(Model("images.bin"), bytes);
  ExpectBadInputContaining(
      RunOdomcal(Colmap()),
      std::string(kColmapError) + Model("images.bin") + ": byte 0: ",
      {"number of images is 1152921504606846976",
       "remaining bytes hold at most"});
}

TEST_F(Robustness, UnknownColmapCameraModelId) {
  WriteColmapProject();
  std::string bytes = ReadFile(Model("cameras.bin"));
  const uint32_t model_id = 99;
  bytes.replace(12, 4, reinterpret_cast<const char*>(&model_id), 4);
  WriteFile(Model("cameras.bin"), bytes);
  ExpectBadInput(
      RunOdomcal(Colmap()),
      std::string(kColmapError) + Model("cameras.bin") +
          ": byte 12: camera 1 of 1 (camera_id 1): unknown camera model id 99 "
          "(COLMAP 3.8 to 4.1 models are 0 to 17)");
}

TEST_F(Robustness, ColmapTextWrongColumnCount) {
  WriteColmapProject(ColmapFormat::kText);
  // images.txt: 4 comment lines, then the first image's pose line.
  std::string pose = Line(Model("images.txt"), 5);
  ReplaceLine(Model("images.txt"), 5, pose.substr(0, pose.rfind(' ')));
  ExpectBadInput(RunOdomcal(Colmap()),
                 std::string(kColmapError) + Model("images.txt") +
                     ":5: expected 10 fields (IMAGE_ID QW QX QY QZ TX TY TZ "
                     "CAMERA_ID NAME; names cannot contain blanks), got 9");
  WriteColmapProject(ColmapFormat::kText);
  ReplaceLine(Model("cameras.txt"), 4, "1 PINHOLE 320");
  ExpectBadInput(
      RunOdomcal(Colmap("out2")),
      std::string(kColmapError) + Model("cameras.txt") +
          ":4: expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[], got 3 fields");
}

// ---------------------------------------------------------------------------
// TUM and CSV trajectories. odometry.csv has a header on line 1; camera.tum
// has one comment line.

TEST_F(Robustness, NanOrInfInTrajectory) {
  WriteDrive();
  ReplaceLine(Path("odometry.csv"), 10, "1700000000.180000000,nan,0,0");
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("odometry.csv") +
                     ":10: column 'x' is not finite (NaN or Inf): 'nan'");
  WriteDrive();
  ReplaceLine(Path("camera.tum"), 3, "1700000000.100000000 0 0 0 0 0 0 inf");
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("camera.tum") +
                     ":3: column 'qw' is not finite (NaN or Inf): 'inf'");
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

TEST_F(Robustness, NonNumericField) {
  WriteDrive();
  ReplaceLine(Path("odometry.csv"), 10, "1700000000.180000000,0,0,north");
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("odometry.csv") +
                     ":10: column 'yaw' is not a number: 'north'");
  WriteDrive();
  ReplaceLine(Path("camera.tum"), 3, "yesterday 0 0 0 0 0 0 1");
  ExpectBadInput(
      RunOdomcal(Calibrate()),
      std::string(kCalibrateError) + Path("camera.tum") +
          ":3: column 'timestamp': 'yesterday' is not a decimal number");
}

TEST_F(Robustness, FewerColumns) {
  WriteDrive();
  ReplaceLine(Path("odometry.csv"), 10, "1700000000.180000000,0,0");
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("odometry.csv") +
                     ":10: expected 4 fields (timestamp,x,y,yaw), got 3");
  WriteDrive();
  ReplaceLine(Path("camera.tum"), 3, "1700000000.100000000 0 0 0 0 0 1");
  ExpectBadInput(
      RunOdomcal(Calibrate()),
      std::string(kCalibrateError) + Path("camera.tum") +
          ":3: expected 8 fields (timestamp tx ty tz qx qy qz qw), got 7");
}

TEST_F(Robustness, UnsortedTimestamps) {
  WriteDrive();
  const std::string line_10 = Line(Path("odometry.csv"), 10);
  ReplaceLine(Path("odometry.csv"), 10, Line(Path("odometry.csv"), 11));
  ReplaceLine(Path("odometry.csv"), 11, line_10);
  ExpectBadInput(
      RunOdomcal(Calibrate()),
      std::string(kCalibrateError) + Path("odometry.csv") +
          ":11: timestamp not increasing: 1700000000.160000000 after "
          "1700000000.180000000 on line 10");
}

TEST_F(Robustness, DuplicateTimestamps) {
  WriteDrive();
  const std::string line_3 = Line(Path("camera.tum"), 3);
  ReplaceLine(Path("camera.tum"), 4, line_3);
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("camera.tum") +
                     ":4: duplicate timestamp 1700000000.100000000 after "
                     "1700000000.100000000 on line 3");
}

// Nanosecond stamps in a file declared as seconds (the default).
TEST_F(Robustness, TimestampsInAnotherUnit) {
  WriteDrive();
  ReplaceLine(Path("odometry.csv"), 2, "1700000000000000000,0,0,0");
  ExpectBadInput(
      RunOdomcal(Calibrate()),
      std::string(kCalibrateError) + Path("odometry.csv") +
          ":2: column 'timestamp': timestamp 1700000000000000000 looks like "
          "nanoseconds or microseconds but the time unit is seconds; pass the "
          "time unit flag");
  // Seconds declared as nanoseconds.
  WriteDrive();
  std::vector<std::string> arguments = Calibrate();
  arguments.insert(arguments.end(), {"--camera_time_unit", "ns"});
  ExpectBadInput(
      RunOdomcal(arguments),
      std::string(kCalibrateError) + Path("camera.tum") +
          ":3: column 'timestamp': timestamp '1700000000.100000000' has a "
          "fractional part but the time unit is ns; pass the time unit flag");
}

// ---------------------------------------------------------------------------
// Time coverage.

TEST_F(Robustness, OdometryCoversOnlyPartOfTheImages) {
  const SimulatedDrive drive = WriteDrive();
  Trajectory first_half = drive.odometry;
  first_half.poses.resize(first_half.poses.size() / 2);
  WriteOdometryCsv(first_half, Path("odometry.csv"));
  const CommandResult run = RunOdomcal(Calibrate());
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "success");
  EXPECT_TRUE(
      ContainsName(result["warnings"],
                   "301 camera poses were skipped: outside the odometry span "
                   "or in gaps longer than 0.25 s"))
      << result["warnings"];
}

TEST_F(Robustness, NoTimeOverlap) {
  WriteDrive();
  std::vector<std::string> arguments = Calibrate();
  arguments.insert(arguments.end(), {"--camera_time_offset_s", "3600"});
  ExpectBadInput(
      RunOdomcal(arguments),
      std::string(kCalibrateError) +
          "no camera timestamp falls inside the odometry (601 outside "
          "its span, 0 in gaps): camera times "
          "1700000000.000-1700000060.000 s (then shifted by 3600.000 s), "
          "odometry 1700000000.000-1700000060.000 s; check the time units "
          "and --camera_time_offset_s");
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

// ---------------------------------------------------------------------------
// Motions that do not determine the calibration.

TEST_F(Robustness, SingleMotion) {
  const SimulatedDrive drive = WriteDrive();
  Trajectory two = drive.camera;
  two.poses = {drive.camera.poses[100], drive.camera.poses[140]};
  WriteTumTrajectory(two, Path("camera.tum"));
  const CommandResult run = RunOdomcal(Calibrate());
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "not_enough_motion");
  EXPECT_EQ(result["message"], "only 1 motion pairs; at least 2 are needed");
  EXPECT_TRUE(result["odom_from_cam"].is_null());
  ExpectNoNonFiniteText(ReadFile(Path("result.yaml")));
}

// Turning on the spot at 0.4 rad/s for a minute.
TEST_F(Robustness, PureRotationInPlace) {
  WritePath(
      IntegratePath([](double) { return Eigen::Vector2d(0.0, 0.4); }, 60.0));
  const CommandResult run = RunOdomcal(Calibrate());
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "unobservable");
  EXPECT_EQ(
      result["message"],
      "the odometry never translates (largest step 0 m: rotation in place "
      "only): the metric scale and the x/y translation cannot be "
      "determined; drive forward while turning");
  EXPECT_EQ(
      result["unobservable"],
      json::array(
          {"translation_x", "translation_y", "translation_z", "metric_scale"}));
  EXPECT_TRUE(result["metric_scale"].is_null());
  ExpectNoNonFiniteText(ReadFile(Path("result.yaml")));
}

// A circle at constant speed: every keyframe pair is the same motion, with
// the same yaw.
TEST_F(Robustness, AllMotionsWithTheSameYaw) {
  WritePath(
      IntegratePath([](double) { return Eigen::Vector2d(0.3, 0.3); }, 60.0));
  const CommandResult run = RunOdomcal(Calibrate());
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "unobservable");
  EXPECT_EQ(
      result["message"],
      "the motion does not determine: rotation, translation_x, translation_y, "
      "metric_scale (standard deviation above the limit or no information; "
      "drive turns of different sizes in both directions)");
  EXPECT_EQ(result["unobservable"],
            json::array({"translation_z",
                         "rotation",
                         "translation_x",
                         "translation_y",
                         "metric_scale"}));
  EXPECT_TRUE(result["metric_scale"].is_null());
  ExpectNoNonFiniteText(ReadFile(Path("result.json")));
  ExpectNoNonFiniteText(ReadFile(Path("result.yaml")));
}

// Every third motion pair's camera motion replaced by a wrong one: two
// consecutive camera poses out of every ten are moved, which spoils the
// three pairs that touch them.
TEST_F(Robustness, ThirtyPercentOutlierCameraMotions) {
  const SimulatedDrive drive = WriteDrive();
  Trajectory camera = drive.camera;
  for (size_t i = 0; i < camera.poses.size(); ++i) {
    if (i % 10 == 4 || i % 10 == 5) {
      Rigid3d& pose = camera.poses[i].world_from_sensor;
      pose.rotation =
          pose.rotation * ExpRotation(Eigen::Vector3d(0.2, -0.3, 0.1) *
                                      (i % 10 == 4 ? 1.0 : -1.0));
      pose.translation +=
          Eigen::Vector3d(0.5, 0.3, -0.2) * (i % 10 == 4 ? 1.0 : -1.0);
    }
  }
  WriteTumTrajectory(camera, Path("camera.tum"));
  std::vector<std::string> arguments = Calibrate();
  // Every camera pose a keyframe, so that the outliers are 30 % of the pairs.
  arguments.insert(arguments.end(),
                   {"--keyframe_min_rotation_deg",
                    "0",
                    "--keyframe_min_translation_m",
                    "0"});
  const CommandResult run = RunOdomcal(arguments);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "success");
  // Every spoiled pair (those touching poses 4 and 5 of ten) rejected; of
  // the 420 good ones the 99.9 % chi-square gate may reject a few by chance
  // (0.4 expected).
  const json& inliers = result["diagnostics"]["inlier_mask"];
  ASSERT_EQ(inliers.size(), 600u);
  int good_rejected = 0;
  for (size_t i = 0; i < inliers.size(); ++i) {
    const bool spoiled = i % 10 == 3 || i % 10 == 4 || i % 10 == 5;
    if (spoiled) {
      EXPECT_FALSE(inliers[i].get<bool>()) << "pair " << i;
    } else {
      good_rejected += !inliers[i].get<bool>();
    }
  }
  EXPECT_LE(good_rejected, 2);
  const int used = 420 - good_rejected;
  EXPECT_EQ(result["message"],
            "calibrated from " + std::to_string(used) + " of 600 motion pairs");
  EXPECT_TRUE(ContainsName(
      result["warnings"],
      std::to_string(600 - used) + " of 600 motion pairs rejected as outliers"))
      << result["warnings"];
  const auto& q = result["odom_from_cam"]["quaternion_wxyz"];
  const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
  // The inliers carry 0.01 deg camera noise.
  EXPECT_LT(RotationAngle(rotation.conjugate() * drive.odom_from_cam.rotation) *
                180.0 / kPi,
            0.1);
}

// Positions near the largest double: each file value is finite, but the
// differences between poses overflow. The solver's guard names it.
TEST_F(Robustness, FiniteInputsWhoseMotionsOverflow) {
  const SimulatedDrive drive = WriteDrive();
  Trajectory camera = drive.camera;
  for (size_t i = 0; i < camera.poses.size(); ++i) {
    camera.poses[i].world_from_sensor.translation.x() =
        (i % 2 == 0 ? 1.7e308 : -1.7e308);
  }
  WriteTumTrajectory(camera, Path("camera.tum"));
  const CommandResult run = RunOdomcal(Calibrate());
  ExpectBadInput(
      run,
      std::string(kCalibrateError) + "motion pair 0 has a non-finite value");
  // Finite steps whose squares overflow.
  for (size_t i = 0; i < camera.poses.size(); ++i) {
    camera.poses[i].world_from_sensor.translation.x() =
        (i % 2 == 0 ? 1e200 : -1e200);
  }
  WriteTumTrajectory(camera, Path("camera.tum"));
  ExpectBadInput(
      RunOdomcal(Calibrate()),
      std::string(kCalibrateError) +
          "motion pair 0 has a translation too large to square in double "
          "precision (check the units)");
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

// ---------------------------------------------------------------------------
// odomcal run and COLMAP.

TEST_F(Robustness, OutputExists) {
  WriteDrive();
  WriteFile(Path("result.json"), "precious");
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("result.json") +
                     ": exists (pass --overwrite to replace it)");
  EXPECT_EQ(ReadFile(Path("result.json")), "precious");

  WriteColmapProject();
  fs::create_directories(Path("out"));
  WriteFile(Path("out/keep.txt"), "precious");
  ExpectBadInput(
      RunOdomcal(Colmap()),
      std::string(kColmapError) + Path("out") +
          ": is not empty (pass --overwrite to replace odomcal's files in it)");
  EXPECT_EQ(ReadFile(Path("out/keep.txt")), "precious");
}

// Permissions do not stop root, so the unwritable places are ones no user
// can write: a path below a regular file, and /proc.
TEST_F(Robustness, OutputNotWritable) {
  WriteDrive();
  WriteFile(Path("a_file"), "");
  ExpectBadInput(RunOdomcal(Calibrate("a_file/result.json")),
                 std::string(kCalibrateError) + Path("a_file/result.json") +
                     ": " + Path("a_file") + " is not a folder");
  std::vector<std::string> arguments = Calibrate();
  arguments.back() = "/proc/odomcal_result.json";
  ExpectBadInputContaining(
      RunOdomcal(arguments),
      std::string(kCalibrateError) +
          "/proc/odomcal_result.json: cannot create a temporary file (",
      {});

  WriteColmapProject();
  ExpectBadInput(RunOdomcal(Colmap("a_file/out")),
                 std::string(kColmapError) + Path("a_file/out") +
                     ": cannot create (Not a directory)");
}

TEST_F(Robustness, OutputInsideTheInputProject) {
  WriteColmapProject();
  const std::string inside =
      (dir_ / "project" / "sparse" / "0" / "out").string();
  ExpectBadInput(RunOdomcal(Colmap("project/sparse/0/out")),
                 std::string(kColmapError) + inside +
                     " (--output_path) is inside the input folder " +
                     (dir_ / "project" / "sparse").string() +
                     " (--model_path); odomcal never writes into an input");
  EXPECT_FALSE(fs::exists(inside));
}

// A full disk, simulated by limiting the size of files odomcal may write to
// 1 KiB: the result JSON is larger, write() fails with EFBIG.
TEST_F(Robustness, DiskFullDuringWrite) {
  WriteDrive();
  RunLimits limits;
  limits.max_file_size_bytes = 1024;
  ExpectBadInput(RunOdomcal(Calibrate(), limits),
                 std::string(kCalibrateError) + Path("result.json") +
                     ": write failed (File too large)");
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find("result"),
              std::string::npos)
        << "left behind: " << entry.path();
  }

  WriteColmapProject();
  ExpectBadInputContaining(
      RunOdomcal(Colmap(), limits), kColmapError, {"File too large"});
  EXPECT_FALSE(fs::exists(Path("out/calibration.json")) &&
               fs::file_size(Path("out/calibration.json")) == 0);
}

}  // namespace
}  // namespace odomcal::robustness_test
