// Shared by the COLMAP model's files (colmap_model.cc and the formats'
// colmap_model_binary.cc and colmap_model_text.cc); internal: not installed.
#pragma once

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Geometry>

#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace odomcal::internal {

inline constexpr uint64_t kMaxPoint3DId =
    static_cast<uint64_t>(std::numeric_limits<int64_t>::max());

struct CameraModelInfo {
  ColmapCameraModel model;
  const char* name;
  int num_params;
  // 1: f, cx, cy first; 2: fx, fy, cx, cy first; 0: no focal length.
  int num_focal_params;
};

// The model's entry of the table (sensor/models.h of COLMAP 4.1). Throws
// std::invalid_argument for a value outside the enum.
const CameraModelInfo& ModelInfo(ColmapCameraModel model);

std::string UnknownModelIdText(int64_t id);
std::string ParamCountText(ColmapCameraModel model, size_t got);
// Empty when (w, x, y, z) is an acceptable stored quaternion.
std::string QuaternionProblem(double w, double x, double y, double z);
// Normalised, as COLMAP does.
Rigid3d MakeCamFromWorld(const double q_wxyz[4], const double t[3]);
std::string Quoted(const std::string& text);
// "image_id 3 ('cam0/000123.png')".
std::string ImageLabel(const ColmapImage& image);
// ": " and errno's text, or nothing when errno is 0.
std::string OpenReason();
// Empty when the track element names an image of `images` and a point2D
// index that image has; else the problem, naming `images_path`.
std::string TrackElementProblem(const ColmapTrackElement& element,
                                const std::map<uint32_t, ColmapImage>& images,
                                const std::string& images_path);
Eigen::Quaterniond NormalizedRotation(const ColmapImage& image);

// "%.17g" in the C locale, as COLMAP's ostreams with precision(17) print.
inline std::string FormatDouble(double value) {
  char buffer[64];
  const auto result = std::to_chars(
      buffer, buffer + sizeof(buffer), value, std::chars_format::general, 17);
  return std::string(buffer, result.ptr);
}

// ---------------------------------------------------------------------------
// Rigs and frames (rigs.bin/.txt, frames.bin/.txt; COLMAP >= 3.12).

// COLMAP's SensorType (src/colmap/util/types.h).
inline constexpr int32_t kSensorCamera = 0;
inline constexpr int32_t kSensorImu = 1;

struct SensorId {
  int32_t type = kSensorCamera;
  uint32_t id = 0;  // camera_id for cameras
};

struct RigSensor {
  SensorId sensor;
  std::optional<Rigid3d> sensor_from_rig;  // none: not calibrated
};

struct Rig {
  uint32_t rig_id = 0;
  std::optional<SensorId> ref_sensor;  // none: a rig without sensors
  std::vector<RigSensor> other_sensors;
};

struct FrameData {
  SensorId sensor;
  uint64_t data_id = 0;  // image_id for cameras
};

struct Frame {
  uint32_t frame_id = 0;
  uint32_t rig_id = 0;
  Rigid3d rig_from_world;  // normalised
  std::vector<FrameData> data;
};

using RigMap = std::map<uint32_t, Rig>;
using FrameMap = std::map<uint32_t, Frame>;

// One rig per camera (rig_id = camera_id, the camera its reference sensor)
// and one frame per image (frame_id = image_id, rig_id = camera_id,
// rig_from_world = the image's normalised cam_from_world): what COLMAP
// >= 3.12 builds for a model without rigs and frames.
RigMap TrivialRigs(const ColmapModel& model);
FrameMap TrivialFrames(const ColmapModel& model);

// Replaces each image's cam_from_world by its frame's pose, as COLMAP >= 3.12
// does: rig_from_world for the rig's reference camera, sensor_from_rig *
// rig_from_world for another camera. Throws FormatError naming the file on
// a frame naming no rig, an image in no frame or in two, and a camera that
// is not a posed sensor of its frame's rig.
void PoseImagesFromFrames(const RigMap& rigs,
                          const FrameMap& frames,
                          std::map<uint32_t, ColmapImage>* images,
                          const std::string& rigs_path,
                          const std::string& frames_path);

RigMap ReadRigsBinary(const std::string& path);
FrameMap ReadFramesBinary(const std::string& path);
void WriteRigsBinary(const RigMap& rigs, const std::string& path);
void WriteFramesBinary(const FrameMap& frames, const std::string& path);

RigMap ReadRigsText(const std::string& path);
FrameMap ReadFramesText(const std::string& path);
void WriteRigsText(const RigMap& rigs, const std::string& path);
void WriteFramesText(const FrameMap& frames, const std::string& path);

// Opens `path` for writing and throws FormatError naming it on failure.
class OutputFile {
 public:
  explicit OutputFile(const std::string& path) : path_(path) {
    errno = 0;
    stream_.open(path, std::ios::binary | std::ios::trunc);
    if (!stream_.is_open()) {
      throw FormatError(path + ": cannot open for writing" + OpenReason());
    }
  }

  void PutLittleEndian(uint64_t value, int num_bytes) {
    char bytes[8];
    for (int i = 0; i < num_bytes; ++i) {
      bytes[i] = static_cast<char>((value >> (8 * i)) & 0xff);
    }
    stream_.write(bytes, num_bytes);
  }
  void PutU8(uint8_t value) { PutLittleEndian(value, 1); }
  void PutU32(uint32_t value) { PutLittleEndian(value, 4); }
  void PutI32(int32_t value) {
    uint32_t bits = 0;
    std::memcpy(&bits, &value, sizeof(bits));
    PutLittleEndian(bits, 4);
  }
  void PutU64(uint64_t value) { PutLittleEndian(value, 8); }
  void PutDouble(double value) {
    uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof(bits));
    PutLittleEndian(bits, 8);
  }
  void PutText(std::string_view text) {
    stream_.write(text.data(), static_cast<std::streamsize>(text.size()));
  }

  void Close() {
    stream_.close();
    if (stream_.fail()) throw FormatError(path_ + ": write error");
  }

 private:
  std::string path_;
  std::ofstream stream_;
};

// The readers check everything but the point2D -> point3D references
// (ReadColmapModel checks those once all files are read); the writers
// expect a model that CheckWritable accepted.
std::map<uint32_t, ColmapCamera> ReadCamerasBinary(const std::string& path);
std::map<uint32_t, ColmapImage> ReadImagesBinary(
    const std::string& path,
    const std::map<uint32_t, ColmapCamera>& cameras,
    const std::string& cameras_path);
std::map<int64_t, ColmapPoint3D> ReadPoints3DBinary(
    const std::string& path,
    const std::map<uint32_t, ColmapImage>& images,
    const std::string& images_path);
void WriteBinary(const ColmapModel& model, const std::filesystem::path& dir);

std::map<uint32_t, ColmapCamera> ReadCamerasText(const std::string& path);
std::map<uint32_t, ColmapImage> ReadImagesText(
    const std::string& path,
    const std::map<uint32_t, ColmapCamera>& cameras,
    const std::string& cameras_path);
std::map<int64_t, ColmapPoint3D> ReadPoints3DText(
    const std::string& path,
    const std::map<uint32_t, ColmapImage>& images,
    const std::string& images_path);
void WriteText(const ColmapModel& model, const std::filesystem::path& dir);

}  // namespace odomcal::internal
