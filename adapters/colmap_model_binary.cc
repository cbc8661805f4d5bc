// COLMAP's binary model files (cameras.bin, images.bin, points3D.bin),
// read through BinaryReader (colmap_model_binary_reader.h). The writer
// mirrors COLMAP's WriteXxxBinary (unchanged from 3.8 to 4.1): the same field
// order and widths.

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/colmap_model_binary_reader.h"
#include "odomcal/adapters/colmap_model_internal.h"
#include "odomcal/adapters/format_error.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <system_error>
#include <utility>

namespace odomcal::internal {
namespace {

namespace fs = std::filesystem;

constexpr uint64_t kBinaryNoPoint3D = std::numeric_limits<uint64_t>::max();

// Smallest possible binary records, for bounding counts before allocating.
constexpr uint64_t kMinCameraBytes = 4 + 4 + 8 + 8 + 2 * 8;
constexpr uint64_t kMinImageBytes = 4 + 7 * 8 + 4 + 1 + 8;  // empty name
constexpr uint64_t kPoint2DBytes = uint64_t{3} * 8;
constexpr uint64_t kMinPoint3DBytes = 8 + 3 * 8 + 3 + 8 + 8;
constexpr uint64_t kTrackElementBytes = 4 + 4;

}  // namespace

std::map<uint32_t, ColmapCamera> ReadCamerasBinary(const std::string& path) {
  BinaryReader reader(path);
  std::map<uint32_t, ColmapCamera> cameras;
  const uint64_t count = reader.ReadCount("number of cameras", kMinCameraBytes);
  for (uint64_t i = 0; i < count; ++i) {
    const std::string record = BinaryRecordName("camera", i, count);
    reader.set_record(record);
    ColmapCamera camera;
    camera.camera_id = reader.ReadU32("camera_id");
    reader.set_record(record + " (camera_id " +
                      std::to_string(camera.camera_id) + ")");
    if (cameras.count(camera.camera_id) != 0) {
      reader.FailAt(reader.offset() - 4,
                    "duplicate camera_id " + std::to_string(camera.camera_id));
    }
    const uint64_t model_offset = reader.offset();
    const int32_t model_id = reader.ReadI32("model_id");
    const std::optional<ColmapCameraModel> model =
        ColmapCameraModelFromId(model_id);
    if (!model) reader.FailAt(model_offset, UnknownModelIdText(model_id));
    camera.model = *model;
    camera.width = reader.ReadU64("width");
    camera.height = reader.ReadU64("height");
    // Bounded by the model table (at most 16), never by file content.
    camera.params.resize(ModelInfo(camera.model).num_params);
    for (double& param : camera.params)
      param = reader.ReadFiniteDouble("param");
    cameras.emplace(camera.camera_id, camera);
  }
  reader.ExpectEnd();
  return cameras;
}

std::map<uint32_t, ColmapImage> ReadImagesBinary(
    const std::string& path,
    const std::map<uint32_t, ColmapCamera>& cameras,
    const std::string& cameras_path) {
  BinaryReader reader(path);
  std::map<uint32_t, ColmapImage> images;
  const uint64_t count = reader.ReadCount("number of images", kMinImageBytes);
  for (uint64_t i = 0; i < count; ++i) {
    const std::string record = BinaryRecordName("image", i, count);
    reader.set_record(record);
    ColmapImage image;
    image.image_id = reader.ReadU32("image_id");
    reader.set_record(record + " (image_id " + std::to_string(image.image_id) +
                      ")");
    if (images.count(image.image_id) != 0) {
      reader.FailAt(reader.offset() - 4,
                    "duplicate image_id " + std::to_string(image.image_id));
    }
    double q[4];
    double t[3];
    for (double& value : q) value = reader.ReadFiniteDouble("quaternion");
    for (double& value : t) value = reader.ReadFiniteDouble("translation");
    const std::string problem = QuaternionProblem(q[0], q[1], q[2], q[3]);
    if (!problem.empty()) reader.Fail(problem);
    image.cam_from_world = MakeCamFromWorld(q, t);
    image.camera_id = reader.ReadU32("camera_id");
    image.name = reader.ReadNullTerminated("name");
    reader.set_record(record + " (image_id " + std::to_string(image.image_id) +
                      ", " + Quoted(image.name) + ")");
    if (image.name.empty()) reader.Fail("empty image name");
    if (cameras.count(image.camera_id) == 0) {
      reader.Fail("camera_id " + std::to_string(image.camera_id) +
                  " is not in " + cameras_path);
    }
    const uint64_t num_points2D =
        reader.ReadCount("number of points2D", kPoint2DBytes);
    image.points2D.resize(num_points2D);
    for (ColmapPoint2D& point : image.points2D) {
      point.xy.x() = reader.ReadFiniteDouble("point2D x");
      point.xy.y() = reader.ReadFiniteDouble("point2D y");
      const uint64_t id = reader.ReadU64("point2D point3D_id");
      if (id == kBinaryNoPoint3D) {
        point.point3D_id = kColmapNoPoint3D;
      } else if (id > kMaxPoint3DId) {
        reader.Fail("point3D_id " + std::to_string(id) + " is out of range");
      } else {
        point.point3D_id = static_cast<int64_t>(id);
      }
    }
    const uint32_t id = image.image_id;
    images.emplace(id, std::move(image));
  }
  reader.ExpectEnd();
  return images;
}

std::map<int64_t, ColmapPoint3D> ReadPoints3DBinary(
    const std::string& path,
    const std::map<uint32_t, ColmapImage>& images,
    const std::string& images_path) {
  BinaryReader reader(path);
  std::map<int64_t, ColmapPoint3D> points;
  const uint64_t count =
      reader.ReadCount("number of points3D", kMinPoint3DBytes);
  for (uint64_t i = 0; i < count; ++i) {
    const std::string record = BinaryRecordName("point3D", i, count);
    reader.set_record(record);
    ColmapPoint3D point;
    const uint64_t id = reader.ReadU64("point3D_id");
    if (id > kMaxPoint3DId) {
      reader.Fail("point3D_id " + std::to_string(id) + " is out of range");
    }
    point.point3D_id = static_cast<int64_t>(id);
    reader.set_record(record + " (point3D_id " + std::to_string(id) + ")");
    if (points.count(point.point3D_id) != 0) {
      reader.FailAt(reader.offset() - 8,
                    "duplicate point3D_id " + std::to_string(id));
    }
    for (int k = 0; k < 3; ++k) point.xyz[k] = reader.ReadFiniteDouble("xyz");
    for (uint8_t& channel : point.rgb) channel = reader.ReadU8("rgb");
    point.error = reader.ReadFiniteDouble("error");
    const uint64_t track_length =
        reader.ReadCount("track length", kTrackElementBytes);
    point.track.resize(track_length);
    for (ColmapTrackElement& element : point.track) {
      element.image_id = reader.ReadU32("track image_id");
      element.point2D_idx = reader.ReadU32("track point2D_idx");
      const std::string problem =
          TrackElementProblem(element, images, images_path);
      if (!problem.empty()) reader.Fail(problem);
    }
    points.emplace(point.point3D_id, std::move(point));
  }
  reader.ExpectEnd();
  return points;
}

void WriteBinary(const ColmapModel& model, const fs::path& dir) {
  {
    OutputFile file((dir / "cameras.bin").string());
    file.PutU64(model.cameras.size());
    for (const auto& [id, camera] : model.cameras) {
      file.PutU32(id);
      file.PutI32(static_cast<int32_t>(camera.model));
      file.PutU64(camera.width);
      file.PutU64(camera.height);
      for (const double param : camera.params) file.PutDouble(param);
    }
    file.Close();
  }
  {
    OutputFile file((dir / "images.bin").string());
    file.PutU64(model.images.size());
    for (const auto& [id, image] : model.images) {
      file.PutU32(id);
      const Eigen::Quaterniond q = NormalizedRotation(image);
      for (const double value : {q.w(), q.x(), q.y(), q.z()}) {
        file.PutDouble(value);
      }
      for (int k = 0; k < 3; ++k) {
        file.PutDouble(image.cam_from_world.translation[k]);
      }
      file.PutU32(image.camera_id);
      file.PutText(image.name);
      file.PutU8(0);
      file.PutU64(image.points2D.size());
      for (const ColmapPoint2D& point : image.points2D) {
        file.PutDouble(point.xy.x());
        file.PutDouble(point.xy.y());
        file.PutU64(point.point3D_id == kColmapNoPoint3D
                        ? kBinaryNoPoint3D
                        : static_cast<uint64_t>(point.point3D_id));
      }
    }
    file.Close();
  }
  {
    OutputFile file((dir / "points3D.bin").string());
    file.PutU64(model.points3D.size());
    for (const auto& [id, point] : model.points3D) {
      file.PutU64(static_cast<uint64_t>(id));
      for (int k = 0; k < 3; ++k) file.PutDouble(point.xyz[k]);
      for (const uint8_t channel : point.rgb) file.PutU8(channel);
      file.PutDouble(point.error);
      file.PutU64(point.track.size());
      for (const ColmapTrackElement& element : point.track) {
        file.PutU32(element.image_id);
        file.PutU32(element.point2D_idx);
      }
    }
    file.Close();
  }
}

}  // namespace odomcal::internal
