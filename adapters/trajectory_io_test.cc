#include "odomcal/adapters/trajectory_io.h"

#include "odomcal/adapters/test_support.h"
#include "odomcal/solver/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>

namespace odomcal {
namespace {

// Written values go through %.17g and are normalized again on reading.
constexpr double kRoundTripTolerance = 1e-15;

std::string WriteTextFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "odomcal_adapters_" + name;
  std::ofstream stream(path);
  stream << text;
  EXPECT_TRUE(stream.good()) << path;
  return path;
}

// Reads `text` as TUM (seconds) and checks the error names path:line and
// contains `part`.
void ExpectTumError(const std::string& name,
                    const std::string& text,
                    int line,
                    const std::string& part) {
  SCOPED_TRACE(name);
  const std::string path = WriteTextFile(name, text);
  const std::string error =
      FormatErrorOf([&] { ReadTumTrajectory(path, TimeUnit::kSeconds); });
  EXPECT_TRUE(Contains(error, path + ":" + std::to_string(line) + ": "))
      << error;
  EXPECT_TRUE(Contains(error, part)) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

void ExpectCsvError(const std::string& name,
                    const std::string& text,
                    int line,
                    const std::string& part) {
  SCOPED_TRACE(name);
  const std::string path = WriteTextFile(name, text);
  const std::string error =
      FormatErrorOf([&] { ReadOdometryCsv(path, TimeUnit::kSeconds); });
  EXPECT_TRUE(Contains(error, path + ":" + std::to_string(line) + ": "))
      << error;
  EXPECT_TRUE(Contains(error, part)) << error;
}

// qx=0.1, qy=0.2, qz=0.3, qw=sqrt(1 - 0.14): every component different, so
// reading the file as w x y z would give a visibly different rotation.
constexpr double kQw = 0.92736184954957035;

TEST(ReadTumTrajectory, ReadsQuaternionInXyzwOrder) {
  const std::string path = WriteTextFile(
      "asymmetric.tum",
      "# timestamp tx ty tz qx qy qz qw\n"
      "1403636579.763555584 1 2 3 0.1 0.2 0.3 0.92736184954957035\n");
  const Trajectory trajectory = ReadTumTrajectory(path, TimeUnit::kSeconds);
  ASSERT_EQ(trajectory.poses.size(), 1u);
  EXPECT_FALSE(trajectory.planar);
  EXPECT_EQ(trajectory.source, path);
  const StampedPose& pose = trajectory.poses[0];
  EXPECT_EQ(pose.stamp_ns, 1403636579763555584);
  const Eigen::Quaterniond& q = pose.world_from_sensor.rotation;
  EXPECT_NEAR(q.x(), 0.1, kRoundTripTolerance);
  EXPECT_NEAR(q.y(), 0.2, kRoundTripTolerance);
  EXPECT_NEAR(q.z(), 0.3, kRoundTripTolerance);
  EXPECT_NEAR(q.w(), kQw, kRoundTripTolerance);
  EXPECT_TRUE(
      pose.world_from_sensor.translation.isApprox(Eigen::Vector3d(1, 2, 3)));
  // world_from_sensor maps the sensor x axis onto the first column of R:
  // [1 - 2(y^2 + z^2), 2(xy + wz), 2(xz - wy)].
  const Eigen::Vector3d x_in_world =
      pose.world_from_sensor * Eigen::Vector3d(1, 0, 0) -
      pose.world_from_sensor.translation;
  EXPECT_NEAR(x_in_world.x(), 1 - 2 * (0.04 + 0.09), 1e-12);
  EXPECT_NEAR(x_in_world.y(), 2 * (0.02 + kQw * 0.3), 1e-12);
  EXPECT_NEAR(x_in_world.z(), 2 * (0.03 - kQw * 0.2), 1e-12);
}

TEST(ReadTumTrajectory, AcceptsCommasCommentsBlankLinesAndCrlf) {
  const std::string path = WriteTextFile("mixed.tum",
                                         "# comment\n"
                                         "\n"
                                         "   \n"
                                         "1.0, 0, 0, 0, 0, 0, 0, 1\r\n"
                                         "  # indented comment\n"
                                         "2.0\t1 2 3   0 0 0 1\n");
  const Trajectory trajectory = ReadTumTrajectory(path, TimeUnit::kSeconds);
  ASSERT_EQ(trajectory.poses.size(), 2u);
  EXPECT_EQ(trajectory.poses[0].stamp_ns, 1000000000);
  EXPECT_EQ(trajectory.poses[1].stamp_ns, 2000000000);
  EXPECT_EQ(trajectory.poses[1].world_from_sensor.translation,
            Eigen::Vector3d(1, 2, 3));
}

TEST(ReadTumTrajectory, NormalizesSlightlyOffQuaternion) {
  const std::string path =
      WriteTextFile("near_unit.tum", "5 0 0 0 0 0 0 1.005\n");
  const Trajectory trajectory = ReadTumTrajectory(path, TimeUnit::kNanoseconds);
  ASSERT_EQ(trajectory.poses.size(), 1u);
  EXPECT_EQ(trajectory.poses[0].stamp_ns, 5);
  EXPECT_NEAR(
      trajectory.poses[0].world_from_sensor.rotation.norm(), 1.0, 1e-15);
}

TEST(ReadTumTrajectory, RejectsMissingFile) {
  const std::string path = ::testing::TempDir() + "odomcal_no_such_file.tum";
  const std::string error =
      FormatErrorOf([&] { ReadTumTrajectory(path, TimeUnit::kSeconds); });
  EXPECT_TRUE(Contains(error, path + ": cannot open for reading")) << error;
}

TEST(ReadTumTrajectory, RejectsDirectory) {
  const std::string path = ::testing::TempDir();
  const std::string error =
      FormatErrorOf([&] { ReadTumTrajectory(path, TimeUnit::kSeconds); });
  EXPECT_TRUE(Contains(error, "cannot open for reading")) << error;
}

TEST(ReadTumTrajectory, RejectsFileWithoutDataLines) {
  for (const char* text : {"", "# only\n\n# comments\n"}) {
    const std::string path = WriteTextFile("empty.tum", text);
    const std::string error =
        FormatErrorOf([&] { ReadTumTrajectory(path, TimeUnit::kSeconds); });
    EXPECT_TRUE(Contains(error, path + ": no data lines")) << error;
  }
}

TEST(ReadTumTrajectory, RejectsWrongFieldCount) {
  ExpectTumError("seven.tum",
                 "# header\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n",
                 3,
                 "expected 8 fields (timestamp tx ty tz qx qy qz qw), got 7");
  ExpectTumError("nine.tum", "1 0 0 0 0 0 0 1 9\n", 1, "expected 8 fields");
  ExpectTumError(
      "empty_field.tum", "1,0,,0,0,0,0,1\n", 1, "column 'ty' is empty");
}

TEST(ReadTumTrajectory, RejectsNonNumericField) {
  ExpectTumError("text.tum",
                 "1 0 0 0 0 0 0 1\n2 0 zero 0 0 0 0 1\n",
                 2,
                 "column 'ty' is not a number: 'zero'");
  ExpectTumError("trailing.tum", "1 0 0 0 0 0 0 1x\n", 1, "column 'qw'");
  ExpectTumError("bad_stamp.tum",
                 "1.2.3 0 0 0 0 0 0 1\n",
                 1,
                 "column 'timestamp': '1.2.3' is not a decimal number");
}

TEST(ReadTumTrajectory, RejectsNanField) {
  ExpectTumError("nan.tum",
                 "1 0 0 0 0 0 0 1\n2 0 0 nan 0 0 0 1\n",
                 2,
                 "column 'tz' is not finite");
  ExpectTumError(
      "inf.tum", "1 -inf 0 0 0 0 0 1\n", 1, "column 'tx' is not finite");
  ExpectTumError(
      "nan_stamp.tum", "nan 0 0 0 0 0 0 1\n", 1, "column 'timestamp'");
}

TEST(ReadTumTrajectory, RejectsNonUnitQuaternion) {
  ExpectTumError("zero_q.tum", "1 0 0 0 0 0 0 0\n", 1, "quaternion");
  ExpectTumError("big_q.tum", "1 0 0 0 0 0 0 1.02\n", 1, "norm 1.02");
}

TEST(ReadTumTrajectory, RejectsDuplicateTimestamp) {
  ExpectTumError("duplicate.tum",
                 "1.5 0 0 0 0 0 0 1\n# c\n1.500000000 0 0 0 0 0 0 1\n",
                 3,
                 "duplicate timestamp 1.500000000 after 1.5 on line 1");
}

TEST(ReadTumTrajectory, RejectsDecreasingTimestamp) {
  ExpectTumError("decreasing.tum",
                 "1 0 0 0 0 0 0 1\n3 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n",
                 3,
                 "timestamp not increasing: 2 after 3 on line 2");
}

TEST(ReadTumTrajectory, RejectsNanosecondsReadAsSeconds) {
  ExpectTumError("ns.tum",
                 "1403636579763555584 0 0 0 0 0 0 1\n",
                 1,
                 "looks like nanoseconds or microseconds");
  const std::string path =
      WriteTextFile("ns_ok.tum", "1403636579763555584 0 0 0 0 0 0 1\n");
  EXPECT_EQ(ReadTumTrajectory(path, TimeUnit::kNanoseconds).poses[0].stamp_ns,
            1403636579763555584);
}

TEST(WriteTumTrajectory, RoundTripsExactStampsAndPoses) {
  Trajectory trajectory;
  for (int i = 0; i < 5; ++i) {
    StampedPose pose;
    pose.stamp_ns = 1403636579763555584 + 33333333 * i + (i % 2);
    pose.world_from_sensor.rotation =
        Eigen::Quaterniond(kQw, 0.1, 0.2, 0.3) *
        Eigen::Quaterniond(Eigen::AngleAxisd(
            0.37 * i, Eigen::Vector3d(1, -2, 0.5).normalized()));
    pose.world_from_sensor.translation =
        Eigen::Vector3d(1.0 / 3.0 + i, -2.0e-7 * i, 12345.678901234567);
    trajectory.poses.push_back(pose);
  }
  const std::string path = ::testing::TempDir() + "odomcal_round_trip.tum";
  WriteTumTrajectory(trajectory, path);
  const Trajectory read = ReadTumTrajectory(path, TimeUnit::kSeconds);
  ASSERT_EQ(read.poses.size(), trajectory.poses.size());
  for (size_t i = 0; i < read.poses.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(read.poses[i].stamp_ns, trajectory.poses[i].stamp_ns);
    EXPECT_EQ(read.poses[i].world_from_sensor.translation,
              trajectory.poses[i].world_from_sensor.translation);
    EXPECT_LT((read.poses[i].world_from_sensor.rotation.coeffs() -
               trajectory.poses[i].world_from_sensor.rotation.coeffs())
                  .norm(),
              kRoundTripTolerance);
  }
}

TEST(WriteTumTrajectory, ThrowsFormatErrorWhenFileCannotBeWritten) {
  const std::string path = ::testing::TempDir() + "odomcal_no_such_dir/out.tum";
  const std::string error =
      FormatErrorOf([&] { WriteTumTrajectory(Trajectory(), path); });
  EXPECT_TRUE(Contains(error, path + ": cannot open for writing")) << error;
}

TEST(ReadOdometryCsv, ReadsWithHeader) {
  const std::string path =
      WriteTextFile("with_header.csv",
                    "# exported by the vehicle\n"
                    "timestamp,x,y,yaw\n"
                    "1403636579.763555584,1.5,-2.0,2.9\n"
                    "1403636579.863555584, 2.5 , -2.0 , -3.0\n");
  const Trajectory trajectory = ReadOdometryCsv(path, TimeUnit::kSeconds);
  EXPECT_TRUE(trajectory.planar);
  ASSERT_EQ(trajectory.poses.size(), 2u);
  EXPECT_EQ(trajectory.poses[0].stamp_ns, 1403636579763555584);
  EXPECT_EQ(trajectory.poses[1].stamp_ns, 1403636579863555584);
  const Rigid3d& pose = trajectory.poses[0].world_from_sensor;
  EXPECT_EQ(pose.translation, Eigen::Vector3d(1.5, -2.0, 0.0));
  EXPECT_TRUE(pose.rotation.isApprox(
      Eigen::Quaterniond(Eigen::AngleAxisd(2.9, Eigen::Vector3d::UnitZ())),
      1e-15));
  // Yaw is counter-clockwise (and may wrap by 2 pi between samples) about +z:
  // the body x axis points to +y at pi/2.
  EXPECT_TRUE(trajectory.poses[1].world_from_sensor.rotation.isApprox(
      Eigen::Quaterniond(Eigen::AngleAxisd(-3.0, Eigen::Vector3d::UnitZ())),
      1e-15));
}

TEST(ReadOdometryCsv, ReadsWithoutHeader) {
  const std::string path =
      WriteTextFile("no_header.csv", "100,0,0,0\n200,1,0,1.5707963267948966\n");
  const Trajectory trajectory = ReadOdometryCsv(path, TimeUnit::kMilliseconds);
  ASSERT_EQ(trajectory.poses.size(), 2u);
  EXPECT_EQ(trajectory.poses[0].stamp_ns, 100000000);
  EXPECT_EQ(trajectory.poses[1].stamp_ns, 200000000);
  const Eigen::Vector3d forward =
      trajectory.poses[1].world_from_sensor.rotation * Eigen::Vector3d::UnitX();
  EXPECT_TRUE(forward.isApprox(Eigen::Vector3d::UnitY(), 1e-15)) << forward;
}

TEST(ReadOdometryCsv, RejectsMalformedLines) {
  ExpectCsvError(
      "bad_header.csv", "t,x,y\n1,0,0,0\n", 1, "header has 3 fields");
  ExpectCsvError("five.csv",
                 "t,x,y,yaw\n1,0,0,0\n2,0,0,0,0\n",
                 3,
                 "expected 4 fields (t,x,y,yaw), got 5");
  ExpectCsvError("second_header.csv",
                 "1,0,0,0\nt,x,y,yaw\n",
                 2,
                 "column 'timestamp': 't' is not a decimal number");
  ExpectCsvError("yaw.csv", "1,0,0,north\n", 1, "column 'yaw' is not a number");
  ExpectCsvError("nan.csv", "1,0,NaN,0\n", 1, "column 'y' is not finite");
  ExpectCsvError("duplicate.csv",
                 "t,x,y,yaw\n1,0,0,0\n1,0,0,0\n",
                 3,
                 "duplicate timestamp 1 after 1 on line 2");
  ExpectCsvError("ns_as_s.csv",
                 "1403636579763555584,0,0,0\n",
                 1,
                 "pass the time unit flag");
}

TEST(ReadOdometryCsv, RejectsHeaderWithoutData) {
  const std::string path = WriteTextFile("header_only.csv", "t,x,y,yaw\n");
  const std::string error =
      FormatErrorOf([&] { ReadOdometryCsv(path, TimeUnit::kSeconds); });
  EXPECT_TRUE(Contains(error, path + ": no data lines")) << error;
}

TEST(WriteOdometryCsv, RoundTripsExactStampsAndPoses) {
  Trajectory trajectory;
  trajectory.planar = true;
  const double yaws[] = {0.0, 0.3, -2.5, 3.0, -3.14159};
  for (int i = 0; i < 5; ++i) {
    StampedPose pose;
    pose.stamp_ns = -5 + 100000001 * i;
    pose.world_from_sensor.rotation = YawRotation(yaws[i]);
    pose.world_from_sensor.translation =
        Eigen::Vector3d(0.1 * i - 1.0 / 7.0, 1e6 + i / 3.0, 0.0);
    trajectory.poses.push_back(pose);
  }
  const std::string path = ::testing::TempDir() + "odomcal_round_trip.csv";
  WriteOdometryCsv(trajectory, path);
  const Trajectory read = ReadOdometryCsv(path, TimeUnit::kSeconds);
  EXPECT_TRUE(read.planar);
  ASSERT_EQ(read.poses.size(), trajectory.poses.size());
  for (size_t i = 0; i < read.poses.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(read.poses[i].stamp_ns, trajectory.poses[i].stamp_ns);
    EXPECT_EQ(read.poses[i].world_from_sensor.translation,
              trajectory.poses[i].world_from_sensor.translation);
    EXPECT_LT(read.poses[i].world_from_sensor.rotation.angularDistance(
                  trajectory.poses[i].world_from_sensor.rotation),
              kRoundTripTolerance);
  }
}

TEST(WriteOdometryCsv, RejectsNonPlanarPose) {
  Trajectory trajectory;
  trajectory.poses.resize(2);
  trajectory.poses[1].world_from_sensor.translation.z() = 0.5;
  const std::string path = ::testing::TempDir() + "odomcal_not_planar.csv";
  EXPECT_THROW(WriteOdometryCsv(trajectory, path), std::invalid_argument);
  trajectory.poses[1].world_from_sensor.translation.z() = 0.0;
  trajectory.poses[1].stamp_ns = 1;
  trajectory.poses[1].world_from_sensor.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));
  EXPECT_THROW(WriteOdometryCsv(trajectory, path), std::invalid_argument);
}

TEST(ParseOdometryFormat, AcceptsTheThreeNames) {
  EXPECT_EQ(ParseOdometryFormat("auto"), OdometryFormat::kAuto);
  EXPECT_EQ(ParseOdometryFormat("tum"), OdometryFormat::kTum);
  EXPECT_EQ(ParseOdometryFormat("csv"), OdometryFormat::kCsv);
  EXPECT_THROW(ParseOdometryFormat("TUM "), std::invalid_argument);
}

TEST(ReadOdometry, ChoosesFormatByExtension) {
  const std::string csv = WriteTextFile("by_extension.CSV", "1,2,3,0\n");
  EXPECT_TRUE(
      ReadOdometry(csv, OdometryFormat::kAuto, TimeUnit::kSeconds).planar);
  const std::string txt =
      WriteTextFile("by_extension.txt", "1 2 3 4 0 0 0 1\n");
  EXPECT_FALSE(
      ReadOdometry(txt, OdometryFormat::kAuto, TimeUnit::kSeconds).planar);
  // An explicit format overrides the extension.
  const std::string tum_named_csv =
      WriteTextFile("really_tum.csv", "1 2 3 4 0 0 0 1\n");
  EXPECT_EQ(
      ReadOdometry(tum_named_csv, OdometryFormat::kTum, TimeUnit::kSeconds)
          .poses[0]
          .world_from_sensor.translation,
      Eigen::Vector3d(2, 3, 4));
  // The content decides over the extension.
  EXPECT_FALSE(
      ReadOdometry(tum_named_csv, OdometryFormat::kAuto, TimeUnit::kSeconds)
          .planar);
  // A field count that is neither: the extension chooses, and the error
  // says so and names the flag.
  const std::string three = WriteTextFile("three.csv", "1,2,3\n");
  EXPECT_EQ(FormatErrorOf([&] {
              ReadOdometry(three, OdometryFormat::kAuto, TimeUnit::kSeconds);
            }),
            three +
                ":1: expected 4 fields (timestamp,x,y,yaw), got 3 (read as csv "
                "because of its extension .csv; --odometry_format csv or tum "
                "chooses)");
}

TEST(ReadOdometry, ContentDecidesOverTheExtension) {
  // A CSV named .txt (issue 12: it failed with "expected 8 fields").
  const std::string csv_txt =
      WriteTextFile("csv_named.txt", "timestamp,x,y,yaw\n1,2,3,0.5\n");
  const Trajectory from_txt =
      ReadOdometry(csv_txt, OdometryFormat::kAuto, TimeUnit::kSeconds);
  EXPECT_TRUE(from_txt.planar);
  EXPECT_EQ(from_txt.poses[0].world_from_sensor.translation,
            Eigen::Vector3d(2, 3, 0));
  // An explicit format still wins, and the error names the flag.
  EXPECT_EQ(FormatErrorOf([&] {
              ReadOdometry(csv_txt, OdometryFormat::kTum, TimeUnit::kSeconds);
            }),
            csv_txt +
                ":1: expected 8 fields (timestamp tx ty tz qx qy qz qw), got 4 "
                "(read as tum because of --odometry_format tum; "
                "--odometry_format csv or tum chooses)");
  // A later broken line is a broken line, not a format question.
  const std::string broken = WriteTextFile("broken.txt", "1,2,3,0.5\n2,2,3\n");
  EXPECT_EQ(FormatErrorOf([&] {
              ReadOdometry(broken, OdometryFormat::kAuto, TimeUnit::kSeconds);
            }),
            broken + ":2: expected 4 fields (timestamp,x,y,yaw), got 3");
}

TEST(ReadOdometry, ByteOrderMarkIsIgnored) {
  const std::string bom = "\xEF\xBB\xBF";
  // Before a TUM comment line (it failed) ...
  const std::string tum = WriteTextFile(
      "bom.tum", bom + "# timestamp tx ty tz qx qy qz qw\n1 2 3 4 0 0 0 1\n");
  EXPECT_EQ(
      ReadOdometry(tum, OdometryFormat::kAuto, TimeUnit::kSeconds).poses.size(),
      1u);
  // ... and before the first sample of a CSV without a header (it was
  // taken for a header and the sample silently dropped).
  const std::string csv = WriteTextFile("bom.csv", bom + "1,2,3,0\n2,3,3,0\n");
  const Trajectory from_csv =
      ReadOdometry(csv, OdometryFormat::kAuto, TimeUnit::kSeconds);
  ASSERT_EQ(from_csv.poses.size(), 2u);
  EXPECT_EQ(from_csv.poses[0].stamp_ns, 1000000000);
  const std::string header =
      WriteTextFile("bom_header.csv", bom + "time_ms,x,y,yaw\n1,2,3,0\n");
  EXPECT_EQ(ReadOdometryCsv(header, TimeUnit::kSeconds).poses[0].stamp_ns,
            1000000);
}

TEST(ReadOdometryCsv, HeaderNamesOrderAndUnits) {
  // Reordered columns (issue 12: read as x,y,yaw before).
  const std::string reordered =
      WriteTextFile("reordered.csv", "timestamp,yaw,x,y\n1,0.5,2,3\n");
  const Trajectory a = ReadOdometryCsv(reordered, TimeUnit::kSeconds);
  EXPECT_EQ(a.poses[0].world_from_sensor.translation, Eigen::Vector3d(2, 3, 0));
  EXPECT_TRUE(
      a.poses[0].world_from_sensor.rotation.isApprox(YawRotation(0.5), 1e-15));
  // Millimetres, degrees and a time unit, exactly.
  const std::string units = WriteTextFile(
      "units.csv",
      "Time_NS,X_MM,y_cm,Yaw_Deg\n1700000000123456789,1500,-25,90\n"
      "1700000000223456789,1600,-25,100\n");
  const Trajectory b = ReadOdometryCsv(units, TimeUnit::kSeconds);
  ASSERT_EQ(b.poses.size(), 2u);
  EXPECT_EQ(b.poses[0].stamp_ns, 1700000000123456789);
  EXPECT_TRUE(b.poses[0].world_from_sensor.translation.isApprox(
      Eigen::Vector3d(1.5, -0.25, 0), 1e-15));
  EXPECT_TRUE(b.poses[0].world_from_sensor.rotation.isApprox(
      YawRotation(kPi / 2), 1e-15));
  // theta, t and milliseconds with a fraction.
  const std::string theta =
      WriteTextFile("theta.csv", "theta,y,x,t_ms\n0,1,2,1.5\n");
  EXPECT_EQ(ReadOdometryCsv(theta, TimeUnit::kSeconds).poses[0].stamp_ns,
            1500000);
}

TEST(ReadOdometryCsv, HeaderErrors) {
  const std::string accepted =
      std::string("; accepted: ") +
      "t|time|timestamp[_s|_ms|_us|_ns], x[_m|_cm|_mm], "
      "y[_m|_cm|_mm], yaw|theta[_rad|_deg] (any order, "
      "any case)";
  ExpectCsvError(
      "unknown.csv",
      "time,x,y,heading\n1,0,0,0\n",
      1,
      "header column 'heading' is not an odometry column" + accepted);
  ExpectCsvError(
      "twice.csv",
      "time,t,x,y\n1,0,0,0\n",
      1,
      "header names the time column twice ('time' and 't')" + accepted);
  ExpectCsvError("values.csv",
                 "time,x_cm,y,yaw\n1,abc,0,0\n",
                 2,
                 "column 'x_cm' is not a number: 'abc'");
  // A suffix that contradicts the unit the user gave names both.
  const std::string ms =
      WriteTextFile("conflict.csv", "time_ms,x,y,yaw\n1,0,0,0\n");
  EXPECT_EQ(
      FormatErrorOf([&] { ReadOdometryCsv(ms, TimeUnit::kNanoseconds, true); }),
      ms + ":1: header column 'time_ms' says the time is in ms but "
           "--odometry_time_unit is ns; drop the flag or rename the column");
  // The same unit, or the default, is fine.
  EXPECT_EQ(
      ReadOdometryCsv(ms, TimeUnit::kMilliseconds, true).poses[0].stamp_ns,
      1000000);
  EXPECT_EQ(
      ReadOdometryCsv(ms, TimeUnit::kNanoseconds, false).poses[0].stamp_ns,
      1000000);
  // Through ReadOdometry a header error also names --odometry_format.
  const std::string bad =
      WriteTextFile("bad_header.txt", "time,x,y,z\n1,0,0,0\n");
  EXPECT_TRUE(Contains(FormatErrorOf([&] {
                         ReadOdometry(
                             bad, OdometryFormat::kAuto, TimeUnit::kSeconds);
                       }),
                       "(read as csv because of its first data line; "
                       "--odometry_format csv or tum chooses)"));
}

// The paper's simulation protocol logged as one odometry sample per image:
// turns uniform in +-90 deg between samples, the yaw kept in -pi..pi (as
// atan2 gives it, in a few digits) and in 0..2 pi. Every such radian log
// reads; the same turns in degrees are refused.
TEST(ReadOdometryCsv, SparseRadianLogsTurningUpTo90DegreesRead) {
  int refused_as_degrees = 0;
  for (uint64_t seed = 1; seed <= 30; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> turn(-kPi / 2.0, kPi / 2.0);
    std::normal_distribution<double> step(0.0, 0.2);
    std::string minus_pi_pi = "t,x,y,yaw\n", zero_two_pi = minus_pi_pi,
                degrees = "t,x,y,yaw\n";
    double x = 0.0, y = 0.0, yaw = 0.0;
    for (int k = 0; k <= 20; ++k) {
      char line[128];
      const double wrapped = WrapAngle(yaw);
      std::snprintf(
          line, sizeof(line), "%d,%.6f,%.6f,%.5f\n", k, x, y, wrapped);
      minus_pi_pi += line;
      std::snprintf(line,
                    sizeof(line),
                    "%d,%.6f,%.6f,%.5f\n",
                    k,
                    x,
                    y,
                    wrapped < 0.0 ? wrapped + 2.0 * kPi : wrapped);
      zero_two_pi += line;
      std::snprintf(line,
                    sizeof(line),
                    "%d,%.6f,%.6f,%.3f\n",
                    k,
                    x,
                    y,
                    wrapped * kRadToDeg);
      degrees += line;
      x += step(rng);
      y += step(rng);
      yaw += turn(rng);
    }
    const std::string name = "paper_" + std::to_string(seed);
    EXPECT_EQ(ReadOdometryCsv(WriteTextFile(name + "_pi.csv", minus_pi_pi),
                              TimeUnit::kSeconds)
                  .poses.size(),
              21u)
        << seed;
    EXPECT_EQ(ReadOdometryCsv(WriteTextFile(name + "_2pi.csv", zero_two_pi),
                              TimeUnit::kSeconds)
                  .poses.size(),
              21u)
        << seed;
    try {
      ReadOdometryCsv(WriteTextFile(name + "_deg.csv", degrees),
                      TimeUnit::kSeconds);
    } catch (const FormatError& error) {
      EXPECT_NE(std::string(error.what()).find("the yaw looks like degrees"),
                std::string::npos)
          << error.what();
      ++refused_as_degrees;
    }
  }
  // Degrees are refused by the step check wherever the turns cross +-180
  // or step by more than pi units (most logs; the rest by the camera's
  // rotation angles, CheckRotationAngleUnits).
  EXPECT_GE(refused_as_degrees, 25);
}

TEST(ReadOdometryCsv, DegreesAsRadiansAreNamed) {
  ExpectCsvError(
      "degrees.csv",
      "0,0,0,179.5\n0.1,0,0,179.9\n0.2,0,0,-179.8\n",
      3,
      "yaw jumps from 179.9 to -179.8 rad, more than pi and not a wrap of a "
      "yaw kept in -pi..pi or 0..2 pi: the yaw looks like degrees; name the "
      "column yaw_deg in the header or convert it to radians");
  // Named as degrees, the same file reads.
  const std::string named = WriteTextFile(
      "degrees_named.csv",
      "t,x,y,yaw_deg\n0,0,0,179.5\n0.1,0,0,179.9\n0.2,0,0,-179.8\n");
  EXPECT_EQ(ReadOdometryCsv(named, TimeUnit::kSeconds).poses.size(), 3u);
}

TEST(ReadOdometry, SniffsFormatWithoutKnownExtension) {
  const std::string csv =
      WriteTextFile("sniff_csv.log", "# c\ntime,x,y,yaw\n1,2,3,0.5\n");
  const Trajectory from_csv =
      ReadOdometry(csv, OdometryFormat::kAuto, TimeUnit::kSeconds);
  EXPECT_TRUE(from_csv.planar);
  EXPECT_EQ(from_csv.poses[0].world_from_sensor.translation,
            Eigen::Vector3d(2, 3, 0));
  const std::string tum = WriteTextFile("sniff_tum", "1 2 3 4 0 0 0 1\n");
  EXPECT_FALSE(
      ReadOdometry(tum, OdometryFormat::kAuto, TimeUnit::kSeconds).planar);
  const std::string unknown = WriteTextFile("sniff_bad.log", "\n1,2,3\n");
  const std::string error = FormatErrorOf([&] {
    ReadOdometry(unknown, OdometryFormat::kAuto, TimeUnit::kSeconds);
  });
  EXPECT_TRUE(Contains(error, unknown + ":2: cannot tell the odometry format"))
      << error;
}

}  // namespace
}  // namespace odomcal
