// rigs.txt and frames.txt (COLMAP >= 3.12; the same up to 4.1:
// src/colmap/scene/reconstruction_io_text.cc, WriteRigsText and
// WriteFramesText). One line per rig / frame, sensor types by name (CAMERA,
// IMU), numbers as "%.17g":
//   RIG_ID NUM_SENSORS [REF_SENSOR_TYPE REF_SENSOR_ID]
//          (SENSOR_TYPE SENSOR_ID HAS_POSE [QW QX QY QZ TX TY TZ])...
//   FRAME_ID RIG_ID QW QX QY QZ TX TY TZ NUM_DATA_IDS
//          (SENSOR_TYPE SENSOR_ID DATA_ID)...
#include "odomcal/adapters/colmap_model_internal.h"
#include "odomcal/adapters/text_reader.h"

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace odomcal::internal {
namespace {

constexpr uint64_t kMaxU32 = std::numeric_limits<uint32_t>::max();

// Reads the blank-separated fields of one line in order, failing with the
// reader's "path:line:" prefix when they run out.
class FieldCursor {
 public:
  FieldCursor(const std::string& line, const TextLineReader& reader)
      : fields_(SplitOnBlanks(line)), reader_(reader) {}

  std::string_view Next(const char* what) {
    if (index_ >= fields_.size()) {
      reader_.Fail(std::string("too few fields: ") + what + " is missing");
    }
    return fields_[index_++];
  }
  uint32_t U32(const char* what) {
    return static_cast<uint32_t>(
        ParseUnsigned(Next(what), what, kMaxU32, reader_));
  }
  int32_t SensorType(const char* what) {
    const std::string_view name = Next(what);
    if (name == "CAMERA") return kSensorCamera;
    if (name == "IMU") return kSensorImu;
    reader_.Fail(std::string(what) + ": '" + std::string(name) +
                 "' is not a sensor type (CAMERA or IMU)");
  }
  Rigid3d Pose(const char* what) {
    double pose[7];
    for (double& value : pose)
      value = ParseFiniteDouble(Next(what), what, reader_);
    const std::string problem =
        QuaternionProblem(pose[0], pose[1], pose[2], pose[3]);
    if (!problem.empty()) reader_.Fail(std::string(what) + ": " + problem);
    return MakeCamFromWorld(pose, pose + 4);
  }
  void ExpectEnd(const std::string& record) {
    if (index_ != fields_.size()) {
      reader_.Fail(record + ": " + std::to_string(fields_.size() - index_) +
                   " fields after the last expected one");
    }
  }

 private:
  std::vector<std::string_view> fields_;
  size_t index_ = 0;
  const TextLineReader& reader_;
};

const char* SensorTypeName(int32_t type) {
  return type == kSensorImu ? "IMU" : "CAMERA";
}

std::string PoseText(const Rigid3d& pose) {
  const Eigen::Quaterniond q = pose.rotation.normalized();
  std::string text;
  for (const double value : {q.w(), q.x(), q.y(), q.z()}) {
    text += FormatDouble(value) + " ";
  }
  for (int k = 0; k < 3; ++k) {
    text += FormatDouble(pose.translation[k]) + (k < 2 ? " " : "");
  }
  return text;
}

}  // namespace

RigMap ReadRigsText(const std::string& path) {
  TextLineReader reader(path);
  RigMap rigs;
  std::string line;
  while (reader.NextDataLine(&line)) {
    FieldCursor fields(line, reader);
    Rig rig;
    rig.rig_id = fields.U32("RIG_ID");
    const std::string record = "rig_id " + std::to_string(rig.rig_id);
    if (rigs.count(rig.rig_id) != 0) reader.Fail("duplicate " + record);
    const uint32_t num_sensors = fields.U32("NUM_SENSORS");
    if (num_sensors > 0) {
      SensorId ref;
      ref.type = fields.SensorType("REF_SENSOR_TYPE");
      ref.id = fields.U32("REF_SENSOR_ID");
      rig.ref_sensor = ref;
    }
    for (uint32_t k = 1; k < num_sensors; ++k) {
      RigSensor sensor;
      sensor.sensor.type = fields.SensorType("SENSOR_TYPE");
      sensor.sensor.id = fields.U32("SENSOR_ID");
      const uint32_t has_pose = fields.U32("HAS_POSE");
      if (has_pose > 1) reader.Fail(record + ": HAS_POSE must be 0 or 1");
      if (has_pose == 1)
        sensor.sensor_from_rig = fields.Pose("SENSOR_FROM_RIG");
      rig.other_sensors.push_back(std::move(sensor));
    }
    fields.ExpectEnd(record);
    const uint32_t id = rig.rig_id;
    rigs.emplace(id, std::move(rig));
  }
  return rigs;
}

FrameMap ReadFramesText(const std::string& path) {
  TextLineReader reader(path);
  FrameMap frames;
  std::string line;
  while (reader.NextDataLine(&line)) {
    FieldCursor fields(line, reader);
    Frame frame;
    frame.frame_id = fields.U32("FRAME_ID");
    const std::string record = "frame_id " + std::to_string(frame.frame_id);
    if (frames.count(frame.frame_id) != 0) reader.Fail("duplicate " + record);
    frame.rig_id = fields.U32("RIG_ID");
    frame.rig_from_world = fields.Pose("RIG_FROM_WORLD");
    const uint32_t num_data = fields.U32("NUM_DATA_IDS");
    // Each data id takes 3 fields; a larger count fails on the missing ones
    // before it could allocate more than the line holds.
    for (uint32_t k = 0; k < num_data; ++k) {
      FrameData data;
      data.sensor.type = fields.SensorType("SENSOR_TYPE");
      data.sensor.id = fields.U32("SENSOR_ID");
      data.data_id = ParseUnsigned(fields.Next("DATA_ID"),
                                   "DATA_ID",
                                   std::numeric_limits<uint64_t>::max(),
                                   reader);
      frame.data.push_back(data);
    }
    fields.ExpectEnd(record);
    const uint32_t id = frame.frame_id;
    frames.emplace(id, std::move(frame));
  }
  return frames;
}

void WriteRigsText(const RigMap& rigs, const std::string& path) {
  OutputFile file(path);
  file.PutText(
      "# Rig calib list with one line of data per calib:\n"
      "#   RIG_ID, NUM_SENSORS, REF_SENSOR_TYPE, REF_SENSOR_ID, SENSORS[] as "
      "(SENSOR_TYPE, SENSOR_ID, HAS_POSE, [QW, QX, QY, QZ, TX, TY, TZ])\n"
      "# Number of rigs: " +
      std::to_string(rigs.size()) + "\n");
  for (const auto& [id, rig] : rigs) {
    std::string line = std::to_string(id) + " ";
    if (!rig.ref_sensor) {
      file.PutText(line + "0\n");
      continue;
    }
    line += std::to_string(rig.other_sensors.size() + 1) + " " +
            SensorTypeName(rig.ref_sensor->type) + " " +
            std::to_string(rig.ref_sensor->id);
    for (const RigSensor& sensor : rig.other_sensors) {
      line += std::string(" ") + SensorTypeName(sensor.sensor.type) + " " +
              std::to_string(sensor.sensor.id);
      line += sensor.sensor_from_rig ? " 1 " + PoseText(*sensor.sensor_from_rig)
                                     : std::string(" 0");
    }
    file.PutText(line + "\n");
  }
  file.Close();
}

void WriteFramesText(const FrameMap& frames, const std::string& path) {
  OutputFile file(path);
  file.PutText(
      "# Frame list with one line of data per frame:\n"
      "#   FRAME_ID, RIG_ID, RIG_FROM_WORLD[QW, QX, QY, QZ, TX, TY, TZ], "
      "NUM_DATA_IDS, DATA_IDS[] as (SENSOR_TYPE, SENSOR_ID, DATA_ID)\n"
      "# Number of frames: " +
      std::to_string(frames.size()) + "\n");
  for (const auto& [id, frame] : frames) {
    std::string line = std::to_string(id) + " " + std::to_string(frame.rig_id) +
                       " " + PoseText(frame.rig_from_world) + " " +
                       std::to_string(frame.data.size());
    for (const FrameData& data : frame.data) {
      line += std::string(" ") + SensorTypeName(data.sensor.type) + " " +
              std::to_string(data.sensor.id) + " " +
              std::to_string(data.data_id);
    }
    file.PutText(line + "\n");
  }
  file.Close();
}

}  // namespace odomcal::internal
