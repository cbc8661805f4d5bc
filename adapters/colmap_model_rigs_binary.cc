// rigs.bin and frames.bin (COLMAP >= 3.12; the layout is the same up to
// 4.1: src/colmap/scene/reconstruction_io_binary.cc, WriteRigsBinary and
// WriteFramesBinary). Little endian:
//   rigs.bin    uint64 count, then per rig: uint32 rig_id, uint32 num_sensors
//               (the reference sensor included); if num_sensors > 0: int32
//               ref_sensor_type, uint32 ref_sensor_id; then per other sensor:
//               int32 type, uint32 id, uint8 has_pose, [float64 qw qx qy qz
//               tx ty tz = sensor_from_rig]
//   frames.bin  uint64 count, then per frame: uint32 frame_id, uint32 rig_id,
//               float64 qw qx qy qz tx ty tz = rig_from_world, uint32
//               num_data_ids, per data id: int32 sensor_type, uint32
//               sensor_id, uint64 data_id
#include "odomcal/adapters/colmap_model_binary_reader.h"
#include "odomcal/adapters/colmap_model_internal.h"

#include <cstdint>
#include <string>
#include <utility>

namespace odomcal::internal {
namespace {

constexpr uint64_t kMinRigBytes = 4 + 4;
constexpr uint64_t kRefSensorBytes = 4 + 4;
constexpr uint64_t kMinOtherSensorBytes = 4 + 4 + 1;
constexpr uint64_t kMinFrameBytes = 4 + 4 + 7 * 8 + 4;
constexpr uint64_t kFrameDataBytes = 4 + 4 + 8;

// A uint32 count of items of at least `min_item_bytes` each, checked against
// the rest of the file like BinaryReader::ReadCount.
uint64_t ReadCount32(BinaryReader& reader,
                     const char* what,
                     uint64_t min_item_bytes) {
  const uint64_t start = reader.offset();
  const uint64_t count = reader.ReadU32(what);
  if (count > reader.remaining() / min_item_bytes) {
    reader.FailAt(start,
                  std::string(what) + " is " + std::to_string(count) +
                      ", but the " + std::to_string(reader.remaining()) +
                      " remaining bytes hold at most " +
                      std::to_string(reader.remaining() / min_item_bytes) +
                      " (garbled or truncated file)");
  }
  return count;
}

Rigid3d ReadPose(BinaryReader& reader, const char* what) {
  const uint64_t start = reader.offset();
  double q[4];
  double t[3];
  for (double& value : q) value = reader.ReadFiniteDouble(what);
  for (double& value : t) value = reader.ReadFiniteDouble(what);
  const std::string problem = QuaternionProblem(q[0], q[1], q[2], q[3]);
  if (!problem.empty())
    reader.FailAt(start, std::string(what) + ": " + problem);
  return MakeCamFromWorld(q, t);
}

void PutPose(OutputFile& file, const Rigid3d& pose) {
  const Eigen::Quaterniond q = pose.rotation.normalized();
  for (const double value : {q.w(), q.x(), q.y(), q.z()}) file.PutDouble(value);
  for (int k = 0; k < 3; ++k) file.PutDouble(pose.translation[k]);
}

}  // namespace

RigMap ReadRigsBinary(const std::string& path) {
  BinaryReader reader(path);
  RigMap rigs;
  const uint64_t count = reader.ReadCount("number of rigs", kMinRigBytes);
  for (uint64_t i = 0; i < count; ++i) {
    const std::string record = BinaryRecordName("rig", i, count);
    reader.set_record(record);
    Rig rig;
    rig.rig_id = reader.ReadU32("rig_id");
    reader.set_record(record + " (rig_id " + std::to_string(rig.rig_id) + ")");
    if (rigs.count(rig.rig_id) != 0) {
      reader.FailAt(reader.offset() - 4,
                    "duplicate rig_id " + std::to_string(rig.rig_id));
    }
    // The reference sensor takes 8 bytes, every other one at least 9.
    const uint64_t count_offset = reader.offset();
    const uint64_t num_sensors = reader.ReadU32("number of sensors");
    if (num_sensors > 0 &&
        (reader.remaining() < kRefSensorBytes ||
         num_sensors - 1 >
             (reader.remaining() - kRefSensorBytes) / kMinOtherSensorBytes)) {
      reader.FailAt(count_offset,
                    "number of sensors is " + std::to_string(num_sensors) +
                        ", more than the " +
                        std::to_string(reader.remaining()) +
                        " remaining bytes hold (garbled or truncated file)");
    }
    if (num_sensors > 0) {
      SensorId ref;
      ref.type = reader.ReadI32("ref_sensor_type");
      ref.id = reader.ReadU32("ref_sensor_id");
      rig.ref_sensor = ref;
    }
    for (uint64_t k = 1; k < num_sensors; ++k) {
      RigSensor sensor;
      sensor.sensor.type = reader.ReadI32("sensor_type");
      sensor.sensor.id = reader.ReadU32("sensor_id");
      const uint64_t has_pose_offset = reader.offset();
      const uint8_t has_pose = reader.ReadU8("has_pose");
      if (has_pose > 1) {
        reader.FailAt(
            has_pose_offset,
            "has_pose is " + std::to_string(has_pose) + ", expected 0 or 1");
      }
      if (has_pose == 1) {
        sensor.sensor_from_rig = ReadPose(reader, "sensor_from_rig");
      }
      rig.other_sensors.push_back(std::move(sensor));
    }
    const uint32_t id = rig.rig_id;
    rigs.emplace(id, std::move(rig));
  }
  reader.ExpectEnd();
  return rigs;
}

FrameMap ReadFramesBinary(const std::string& path) {
  BinaryReader reader(path);
  FrameMap frames;
  const uint64_t count = reader.ReadCount("number of frames", kMinFrameBytes);
  for (uint64_t i = 0; i < count; ++i) {
    const std::string record = BinaryRecordName("frame", i, count);
    reader.set_record(record);
    Frame frame;
    frame.frame_id = reader.ReadU32("frame_id");
    reader.set_record(record + " (frame_id " + std::to_string(frame.frame_id) +
                      ")");
    if (frames.count(frame.frame_id) != 0) {
      reader.FailAt(reader.offset() - 4,
                    "duplicate frame_id " + std::to_string(frame.frame_id));
    }
    frame.rig_id = reader.ReadU32("rig_id");
    frame.rig_from_world = ReadPose(reader, "rig_from_world");
    const uint64_t num_data =
        ReadCount32(reader, "number of data ids", kFrameDataBytes);
    frame.data.resize(num_data);
    for (FrameData& data : frame.data) {
      data.sensor.type = reader.ReadI32("sensor_type");
      data.sensor.id = reader.ReadU32("sensor_id");
      data.data_id = reader.ReadU64("data_id");
    }
    const uint32_t id = frame.frame_id;
    frames.emplace(id, std::move(frame));
  }
  reader.ExpectEnd();
  return frames;
}

void WriteRigsBinary(const RigMap& rigs, const std::string& path) {
  OutputFile file(path);
  file.PutU64(rigs.size());
  for (const auto& [id, rig] : rigs) {
    file.PutU32(id);
    if (!rig.ref_sensor) {
      file.PutU32(0);
      continue;
    }
    file.PutU32(static_cast<uint32_t>(rig.other_sensors.size() + 1));
    file.PutI32(rig.ref_sensor->type);
    file.PutU32(rig.ref_sensor->id);
    for (const RigSensor& sensor : rig.other_sensors) {
      file.PutI32(sensor.sensor.type);
      file.PutU32(sensor.sensor.id);
      file.PutU8(sensor.sensor_from_rig ? 1 : 0);
      if (sensor.sensor_from_rig) PutPose(file, *sensor.sensor_from_rig);
    }
  }
  file.Close();
}

void WriteFramesBinary(const FrameMap& frames, const std::string& path) {
  OutputFile file(path);
  file.PutU64(frames.size());
  for (const auto& [id, frame] : frames) {
    file.PutU32(id);
    file.PutU32(frame.rig_id);
    PutPose(file, frame.rig_from_world);
    file.PutU32(static_cast<uint32_t>(frame.data.size()));
    for (const FrameData& data : frame.data) {
      file.PutI32(data.sensor.type);
      file.PutU32(data.sensor.id);
      file.PutU64(data.data_id);
    }
  }
  file.Close();
}

}  // namespace odomcal::internal
