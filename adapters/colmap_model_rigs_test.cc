// Models with rigs and frames (COLMAP >= 3.12): fixtures built from the
// layouts of reconstruction_io_binary.cc / _text.cc, the poses COLMAP takes
// from the frames, the models COLMAP cannot read, and the rigs and frames
// WriteColmapModel writes.
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/colmap_model_internal.h"
#include "odomcal/adapters/colmap_model_test_support.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using namespace colmap_test;  // NOLINT(google-build-using-namespace)

constexpr double kPoseTolerance = 1e-12;

// Camera 1 is the reference sensor of rig 1, camera 2 a second sensor of it
// at sensor_from_rig = kCam2FromRig; frame 5 holds image 1 (camera 1) and
// image 2 (camera 2). images.bin stores a different, outdated pose for both
// images, which COLMAP (and the reader) must ignore.
const Rigid3d kRigFromWorld = Pose(0.9, 0.1, -0.3, 0.2, 1.5, -2.0, 0.25);
const Rigid3d kCam2FromRig = Pose(0.8, 0.0, 0.6, 0.0, 0.1, 0.0, -0.05);
const Rigid3d kOutdated = Pose(1, 0, 0, 0, 9, 9, 9);

Bytes& PutPose(Bytes& b, const Rigid3d& pose) {
  const Eigen::Quaterniond& q = pose.rotation;
  b.F64(q.w()).F64(q.x()).F64(q.y()).F64(q.z());
  return b.F64(pose.translation.x())
      .F64(pose.translation.y())
      .F64(pose.translation.z());
}

Bytes RigCamerasBin() {
  Bytes b;
  b.U64(2);
  b.U32(1).U32(1).U64(640).U64(480).F64(500).F64(501).F64(320).F64(240);
  b.U32(2).U32(0).U64(320).U64(240).F64(250).F64(160).F64(120);
  return b;
}

Bytes RigImagesBin() {
  Bytes b;
  b.U64(2);
  PutPose(b.U32(1), kOutdated).U32(1).Text("left/0001.png").U8(0).U64(0);
  PutPose(b.U32(2), kOutdated).U32(2).Text("right/0001.png").U8(0).U64(0);
  return b;
}

// rigs.bin: rig_id, num_sensors, ref (type, id), then (type, id, has_pose,
// pose) per other sensor.
Bytes RigsBin(bool second_sensor_has_pose) {
  Bytes b;
  b.U64(1).U32(1).U32(2).U32(0).U32(1).U32(0).U32(2);
  if (!second_sensor_has_pose) return b.U8(0);
  return PutPose(b.U8(1), kCam2FromRig);
}

// frames.bin: frame_id, rig_id, pose, num_data, (type, sensor_id, data_id).
Bytes FramesBin() {
  Bytes b;
  PutPose(b.U64(1).U32(5).U32(1), kRigFromWorld).U32(2);
  return b.U32(0).U32(1).U64(1).U32(0).U32(2).U64(2);
}

std::string WriteRigFixture(const std::string& name) {
  const std::string dir = FreshDir(name);
  WriteFile(dir + "/cameras.bin", RigCamerasBin().data);
  WriteFile(dir + "/images.bin", RigImagesBin().data);
  WriteFile(dir + "/points3D.bin", Bytes().U64(0).data);
  WriteFile(dir + "/rigs.bin", RigsBin(true).data);
  WriteFile(dir + "/frames.bin", FramesBin().data);
  return dir;
}

void ExpectPose(const Rigid3d& expected, const Rigid3d& actual) {
  EXPECT_LT(RotationAngle(expected.rotation.inverse() * actual.rotation),
            kPoseTolerance);
  EXPECT_LT((expected.translation - actual.translation).norm(), kPoseTolerance);
}

void ExpectRigPoses(const ColmapModel& model) {
  ASSERT_EQ(model.images.size(), 2u);
  ExpectPose(kRigFromWorld, model.images.at(1).cam_from_world);
  ExpectPose(kCam2FromRig * kRigFromWorld, model.images.at(2).cam_from_world);
}

TEST(ColmapModelRigs, BinaryPosesComeFromTheFrames) {
  ExpectRigPoses(ReadColmapModel(WriteRigFixture("rigs_bin")));
}

TEST(ColmapModelRigs, TextPosesComeFromTheFrames) {
  const std::string dir = FreshDir("rigs_txt");
  WriteFile(dir + "/cameras.txt",
            "1 PINHOLE 640 480 500 501 320 240\n"
            "2 SIMPLE_PINHOLE 320 240 250 160 120\n");
  WriteFile(dir + "/images.txt",
            "1 1 0 0 0 9 9 9 1 left/0001.png\n\n"
            "2 1 0 0 0 9 9 9 2 right/0001.png\n\n");
  WriteFile(dir + "/points3D.txt", "");
  const auto pose_text = [](const Rigid3d& pose) {
    std::string text;
    for (const double value : {pose.rotation.w(),
                               pose.rotation.x(),
                               pose.rotation.y(),
                               pose.rotation.z(),
                               pose.translation.x(),
                               pose.translation.y(),
                               pose.translation.z()}) {
      text += " " + internal::FormatDouble(value);
    }
    return text;
  };
  WriteFile(dir + "/rigs.txt",
            "# Rig calib list with one line of data per calib:\n"
            "# Number of rigs: 1\n"
            "1 2 CAMERA 1 CAMERA 2 1" +
                pose_text(kCam2FromRig) + "\n");
  WriteFile(dir + "/frames.txt",
            "# Number of frames: 1\n"
            "5 1" +
                pose_text(kRigFromWorld) + " 2 CAMERA 1 1 CAMERA 2 2\n");
  ExpectRigPoses(ReadColmapModel(dir));
  // A binary model beside it never looks at rigs.txt/frames.txt.
  WriteColmapModel(ReadColmapModel(dir), dir, ColmapFormat::kBinary);
  WriteFile(dir + "/frames.txt", "garbage\n");
  ExpectRigPoses(ReadColmapModel(dir));
}

TEST(ColmapModelRigs, ModelsColmapCannotReadAreRefused) {
  struct Case {
    const char* name;
    const char* remove;  // file to remove, or ""
    Bytes rigs;          // replaces rigs.bin when not empty
    Bytes frames;        // replaces frames.bin when not empty
    const char* where;   // file named first in the message
    const char* part;
  };
  Bytes frame_of_image_1;
  PutPose(frame_of_image_1.U64(1).U32(5).U32(1), kRigFromWorld)
      .U32(1)
      .U32(0)
      .U32(1)
      .U64(1);
  Bytes frame_of_unknown_rig;
  PutPose(frame_of_unknown_rig.U64(1).U32(5).U32(7), kRigFromWorld).U32(0);
  Bytes image_1_as_camera_2;
  PutPose(image_1_as_camera_2.U64(1).U32(5).U32(1), kRigFromWorld)
      .U32(1)
      .U32(0)
      .U32(2)
      .U64(1);
  const Case cases[] = {
      {"only_rigs",
       "frames.bin",
       {},
       {},
       "rigs.bin",
       ": no frames.bin beside it"},
      {"only_frames",
       "rigs.bin",
       {},
       {},
       "frames.bin",
       ": no rigs.bin beside it"},
      {"image_in_no_frame",
       "",
       {},
       frame_of_image_1,
       "frames.bin",
       "image_id 2 ('right/0001.png') is in no frame"},
      {"unposed_sensor",
       "",
       RigsBin(false),
       {},
       "rigs.bin",
       "camera_id 2 has no sensor_from_rig"},
      {"unknown_rig",
       "",
       {},
       frame_of_unknown_rig,
       "frames.bin",
       "frame_id 5 names rig_id 7, which is not in"},
      {"wrong_camera",
       "",
       {},
       image_1_as_camera_2,
       "frames.bin",
       "as data of camera 2, but the image's camera_id is 1"},
      {"truncated_rigs",
       "",
       Bytes().U64(1).U32(1).U32(2),
       {},
       "rigs.bin: byte ",
       "truncated"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string dir = WriteRigFixture(std::string("rigs_bad_") + c.name);
    if (*c.remove != '\0') fs::remove(dir + "/" + c.remove);
    if (!c.rigs.data.empty()) WriteFile(dir + "/rigs.bin", c.rigs.data);
    if (!c.frames.data.empty()) WriteFile(dir + "/frames.bin", c.frames.data);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(error, dir + "/" + c.where)) << error;
    EXPECT_TRUE(Contains(error, c.part)) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
}

// The trivial rigs and frames COLMAP >= 3.12 writes for a single camera.
void ExpectTrivialRigsAndFrames(const std::string& dir,
                                ColmapFormat format,
                                const ColmapModel& model) {
  const bool binary = format == ColmapFormat::kBinary;
  const internal::RigMap rigs =
      binary ? internal::ReadRigsBinary(dir + "/rigs.bin")
             : internal::ReadRigsText(dir + "/rigs.txt");
  const internal::FrameMap frames =
      binary ? internal::ReadFramesBinary(dir + "/frames.bin")
             : internal::ReadFramesText(dir + "/frames.txt");
  ASSERT_EQ(rigs.size(), model.cameras.size());
  for (const auto& [camera_id, camera] : model.cameras) {
    const internal::Rig& rig = rigs.at(camera_id);
    ASSERT_TRUE(rig.ref_sensor.has_value());
    EXPECT_EQ(rig.ref_sensor->type, internal::kSensorCamera);
    EXPECT_EQ(rig.ref_sensor->id, camera_id);
    EXPECT_TRUE(rig.other_sensors.empty());
  }
  ASSERT_EQ(frames.size(), model.images.size());
  for (const auto& [image_id, image] : model.images) {
    SCOPED_TRACE(image.name);
    const internal::Frame& frame = frames.at(image_id);
    EXPECT_EQ(frame.rig_id, image.camera_id);
    ExpectPose(image.cam_from_world, frame.rig_from_world);
    ASSERT_EQ(frame.data.size(), 1u);
    EXPECT_EQ(frame.data[0].sensor.id, image.camera_id);
    EXPECT_EQ(frame.data[0].data_id, image_id);
  }
}

TEST(ColmapModelRigs, WrittenModelsHoldTrivialRigsAndFrames) {
  const ColmapModel model = MakeModel();
  for (const ColmapFormat format :
       {ColmapFormat::kBinary, ColmapFormat::kText}) {
    const std::string dir =
        FreshDir(format == ColmapFormat::kBinary ? "rigs_written_bin"
                                                 : "rigs_written_txt");
    WriteColmapModel(model, dir, format);
    ExpectTrivialRigsAndFrames(dir, format, model);
    ExpectEqualModels(model, ReadColmapModel(dir));
  }
  const std::string dir = FreshDir("rigs_text_layout");
  ColmapModel one;
  one.cameras[1] = model.cameras.at(1);
  one.images[12] = model.images.at(12);
  one.images[12].cam_from_world = Pose(1, 0, 0, 0, 0.1, 2, -3);
  WriteColmapModel(one, dir, ColmapFormat::kText);
  EXPECT_EQ(ReadBytes(dir + "/rigs.txt"),
            "# Rig calib list with one line of data per calib:\n"
            "#   RIG_ID, NUM_SENSORS, REF_SENSOR_TYPE, REF_SENSOR_ID, "
            "SENSORS[] as (SENSOR_TYPE, SENSOR_ID, HAS_POSE, [QW, QX, QY, QZ, "
            "TX, TY, TZ])\n"
            "# Number of rigs: 1\n"
            "1 1 CAMERA 1\n");
  EXPECT_EQ(ReadBytes(dir + "/frames.txt"),
            "# Frame list with one line of data per frame:\n"
            "#   FRAME_ID, RIG_ID, RIG_FROM_WORLD[QW, QX, QY, QZ, TX, TY, TZ], "
            "NUM_DATA_IDS, DATA_IDS[] as (SENSOR_TYPE, SENSOR_ID, DATA_ID)\n"
            "# Number of frames: 1\n"
            "12 1 1 0 0 0 0.10000000000000001 2 -3 1 CAMERA 1 12\n");
}

// The metric export of a COLMAP 3.12 model with a two-camera rig: scaled
// poses written over the model itself and into a fresh folder are read back
// with the new poses, and the rigs and frames beside them agree.
TEST(ColmapModelRigs, MetricExportOfA312ModelIsReadBackConsistently) {
  const std::string dir = WriteRigFixture("rigs_metric_export");
  ColmapModel metric = ReadColmapModel(dir);
  constexpr double kScale = 0.37;
  for (auto& [id, image] : metric.images) {
    image.cam_from_world.translation *= kScale;
  }
  const std::string fresh = FreshDir("rigs_metric_export_fresh");
  for (const std::string& target : {dir, fresh}) {
    SCOPED_TRACE(target);
    WriteColmapModel(metric, target, ColmapFormat::kBinary);
    ExpectTrivialRigsAndFrames(target, ColmapFormat::kBinary, metric);
    const ColmapModel back = ReadColmapModel(target);
    ExpectPose(
        Rigid3d(kRigFromWorld.rotation, kScale * kRigFromWorld.translation),
        back.images.at(1).cam_from_world);
    const Rigid3d cam2 = kCam2FromRig * kRigFromWorld;
    ExpectPose(Rigid3d(cam2.rotation, kScale * cam2.translation),
               back.images.at(2).cam_from_world);
  }
  // A folder with stale text rigs/frames of an older text model: the text
  // writer replaces them too.
  WriteFile(fresh + "/frames.txt", "5 1 1 0 0 0 9 9 9 1 CAMERA 1 1\n");
  WriteColmapModel(metric, fresh, ColmapFormat::kText);
  ExpectTrivialRigsAndFrames(fresh, ColmapFormat::kText, metric);
}

}  // namespace
}  // namespace odomcal
