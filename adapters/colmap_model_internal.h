// Shared by the COLMAP model's files (colmap_model.cc and the formats'
// colmap_model_binary.cc and colmap_model_text.cc); internal: not installed.
#pragma once

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Geometry>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <string_view>

namespace odomcal::internal {

inline constexpr uint64_t kMaxPoint3DId =
    static_cast<uint64_t>(std::numeric_limits<int64_t>::max());

struct CameraModelInfo {
  ColmapCameraModel model;
  const char* name;
  int num_params;
};

// The model's entry of the table (camera_models.h of COLMAP 3.8). Throws
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
