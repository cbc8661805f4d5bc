// COLMAP model files: the camera model table, the checks both formats
// share, and the entry points, which pick the format's reader or writer
// (colmap_model_binary.cc, colmap_model_text.cc). Cross references (an
// image's camera, a track's image and point2D index, a point2D's point3D)
// are checked once the files they point into have been read.
#include "odomcal/adapters/colmap_model.h"

#include "odomcal/adapters/colmap_model_internal.h"
#include "odomcal/adapters/format_error.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

using internal::CameraModelInfo;
using internal::ImageLabel;
using internal::ModelInfo;
using internal::ParamCountText;
using internal::ReadCamerasBinary;
using internal::ReadCamerasText;
using internal::ReadImagesBinary;
using internal::ReadImagesText;
using internal::ReadPoints3DBinary;
using internal::ReadPoints3DText;
using internal::TrackElementProblem;
using internal::UnknownModelIdText;
using internal::WriteBinary;
using internal::WriteText;

// COLMAP writes normalised quaternions; a norm this far from 1 means the file
// is garbled or was not written as cam_from_world quaternions at all.
constexpr double kMaxQuaternionNormDeviation = 1e-2;

// Index = COLMAP model id (src/colmap/sensor/models.h of COLMAP 4.1; ids
// 0-10 as in 3.8's src/base/camera_models.h, 11 from 3.11, 12-15 from 4.0).
constexpr CameraModelInfo kCameraModels[] = {
    {ColmapCameraModel::kSimplePinhole, "SIMPLE_PINHOLE", 3, 1},
    {ColmapCameraModel::kPinhole, "PINHOLE", 4, 2},
    {ColmapCameraModel::kSimpleRadial, "SIMPLE_RADIAL", 4, 1},
    {ColmapCameraModel::kRadial, "RADIAL", 5, 1},
    {ColmapCameraModel::kOpenCV, "OPENCV", 8, 2},
    {ColmapCameraModel::kOpenCVFisheye, "OPENCV_FISHEYE", 8, 2},
    {ColmapCameraModel::kFullOpenCV, "FULL_OPENCV", 12, 2},
    {ColmapCameraModel::kFov, "FOV", 5, 2},
    {ColmapCameraModel::kSimpleRadialFisheye, "SIMPLE_RADIAL_FISHEYE", 4, 1},
    {ColmapCameraModel::kRadialFisheye, "RADIAL_FISHEYE", 5, 1},
    {ColmapCameraModel::kThinPrismFisheye, "THIN_PRISM_FISHEYE", 12, 2},
    {ColmapCameraModel::kRadTanThinPrismFisheye,
     "RAD_TAN_THIN_PRISM_FISHEYE",
     16,
     2},
    {ColmapCameraModel::kSimpleDivision, "SIMPLE_DIVISION", 4, 1},
    {ColmapCameraModel::kDivision, "DIVISION", 5, 2},
    {ColmapCameraModel::kSimpleFisheye, "SIMPLE_FISHEYE", 3, 1},
    {ColmapCameraModel::kFisheye, "FISHEYE", 4, 2},
    {ColmapCameraModel::kEucm, "EUCM", 6, 2},
    {ColmapCameraModel::kEquirectangular, "EQUIRECTANGULAR", 2, 0},
};
constexpr int kNumCameraModels =
    static_cast<int>(sizeof(kCameraModels) / sizeof(kCameraModels[0]));

}  // namespace

namespace internal {

const CameraModelInfo& ModelInfo(ColmapCameraModel model) {
  const int id = static_cast<int>(model);
  if (id < 0 || id >= kNumCameraModels) {
    throw std::invalid_argument("unknown COLMAP camera model value " +
                                std::to_string(id));
  }
  return kCameraModels[id];
}

std::string UnknownModelIdText(int64_t id) {
  return "unknown camera model id " + std::to_string(id) +
         " (COLMAP 3.8 to 4.1 models are 0 to " +
         std::to_string(kNumCameraModels - 1) + ")";
}

std::string ParamCountText(ColmapCameraModel model, size_t got) {
  const CameraModelInfo& info = ModelInfo(model);
  return std::string("model ") + info.name + " takes " +
         std::to_string(info.num_params) + " parameters, got " +
         std::to_string(got);
}

// Empty when (w, x, y, z) is an acceptable stored quaternion.
std::string QuaternionProblem(double w, double x, double y, double z) {
  const double norm = std::sqrt(w * w + x * x + y * y + z * z);
  if (std::abs(norm - 1.0) > kMaxQuaternionNormDeviation) {
    return "quaternion (QW QX QY QZ) has norm " + std::to_string(norm) +
           ", expected 1";
  }
  return "";
}

Rigid3d MakeCamFromWorld(const double q_wxyz[4], const double t[3]) {
  return Rigid3d(Eigen::Quaterniond(q_wxyz[0], q_wxyz[1], q_wxyz[2], q_wxyz[3])
                     .normalized(),
                 Eigen::Vector3d(t[0], t[1], t[2]));
}

std::string Quoted(const std::string& text) { return "'" + text + "'"; }

std::string ImageLabel(const ColmapImage& image) {
  return "image_id " + std::to_string(image.image_id) + " (" +
         Quoted(image.name) + ")";
}

std::string OpenReason() {
  return errno != 0 ? std::string(": ") + std::strerror(errno) : std::string();
}

std::string TrackElementProblem(const ColmapTrackElement& element,
                                const std::map<uint32_t, ColmapImage>& images,
                                const std::string& images_path) {
  const auto image = images.find(element.image_id);
  if (image == images.end()) {
    return "track names image_id " + std::to_string(element.image_id) +
           ", which is not in " + images_path;
  }
  if (element.point2D_idx >= image->second.points2D.size()) {
    return "track names point2D_idx " + std::to_string(element.point2D_idx) +
           " of " + ImageLabel(image->second) + ", which has " +
           std::to_string(image->second.points2D.size()) + " points2D";
  }
  return "";
}

Eigen::Quaterniond NormalizedRotation(const ColmapImage& image) {
  return image.cam_from_world.rotation.normalized();
}

}  // namespace internal

namespace {

// Every point2D -> point3D reference must name a point of the model.
void CheckPoint3DReferences(const ColmapModel& model,
                            const std::string& images_path,
                            const std::string& points_path) {
  for (const auto& [image_id, image] : model.images) {
    for (size_t k = 0; k < image.points2D.size(); ++k) {
      const int64_t id = image.points2D[k].point3D_id;
      if (id != kColmapNoPoint3D && model.points3D.count(id) == 0) {
        throw FormatError(images_path + ": " + ImageLabel(image) +
                          ": point2D " + std::to_string(k) +
                          " names point3D_id " + std::to_string(id) +
                          ", which is not in " + points_path);
      }
    }
  }
}

// A model with rigs and frames (COLMAP >= 3.12) takes its images' poses
// from them; one without both files keeps the poses of images.bin/.txt
// (COLMAP builds trivial rigs and frames from those). A model of one format
// never looks at the other format's rigs and frames.
void ApplyRigsAndFrames(const std::string& dir,
                        const std::string& extension,
                        std::map<uint32_t, ColmapImage>* images) {
  const std::string rigs_path = (fs::path(dir) / ("rigs" + extension)).string();
  const std::string frames_path =
      (fs::path(dir) / ("frames" + extension)).string();
  std::error_code error;
  const bool has_rigs = fs::exists(rigs_path, error);
  const bool has_frames = fs::exists(frames_path, error);
  if (!has_rigs && !has_frames) return;
  if (has_rigs != has_frames) {
    throw FormatError((has_rigs ? rigs_path : frames_path) + ": no " +
                      (has_rigs ? "frames" : "rigs") + extension +
                      " beside it: COLMAP >= 3.12 reads the two together "
                      "(each image's pose comes from its frame); restore the "
                      "missing file or remove both");
  }
  const bool binary = extension == ".bin";
  const internal::RigMap rigs = binary ? internal::ReadRigsBinary(rigs_path)
                                       : internal::ReadRigsText(rigs_path);
  const internal::FrameMap frames =
      binary ? internal::ReadFramesBinary(frames_path)
             : internal::ReadFramesText(frames_path);
  internal::PoseImagesFromFrames(rigs, frames, images, rigs_path, frames_path);
}

// ---------------------------------------------------------------------------
// Output.

void CheckFinite(double value, const std::string& what) {
  if (!std::isfinite(value)) {
    throw std::invalid_argument("WriteColmapModel: " + what + " is not finite");
  }
}

// Throws std::invalid_argument unless ReadColmapModel would read the model
// written in `format` back unchanged.
void CheckWritable(const ColmapModel& model, ColmapFormat format) {
  const std::string prefix = "WriteColmapModel: ";
  for (const auto& [id, camera] : model.cameras) {
    const std::string label = "camera_id " + std::to_string(camera.camera_id);
    if (id != camera.camera_id) {
      throw std::invalid_argument(prefix + "cameras[" + std::to_string(id) +
                                  "] holds " + label);
    }
    const int model_id = static_cast<int>(camera.model);
    if (model_id < 0 || model_id >= kNumCameraModels) {
      throw std::invalid_argument(prefix + label + ": " +
                                  UnknownModelIdText(model_id));
    }
    if (camera.params.size() !=
        static_cast<size_t>(ModelInfo(camera.model).num_params)) {
      throw std::invalid_argument(
          prefix + label + ": " +
          ParamCountText(camera.model, camera.params.size()));
    }
    for (const double param : camera.params) CheckFinite(param, label);
  }
  for (const auto& [id, image] : model.images) {
    const std::string label = ImageLabel(image);
    if (id != image.image_id) {
      throw std::invalid_argument(prefix + "images[" + std::to_string(id) +
                                  "] holds " + label);
    }
    if (image.name.empty() || image.name.find('\0') != std::string::npos) {
      throw std::invalid_argument(
          prefix + label + ": names must be non-empty and without '\\0'");
    }
    if (format == ColmapFormat::kText &&
        image.name.find_first_of(" \t\r\n") != std::string::npos) {
      throw std::invalid_argument(
          prefix + label +
          ": names with blanks or line breaks cannot be written as text "
          "(COLMAP splits text lines on blanks); use the binary format");
    }
    if (model.cameras.count(image.camera_id) == 0) {
      throw std::invalid_argument(prefix + label + ": camera_id " +
                                  std::to_string(image.camera_id) +
                                  " is not in the model");
    }
    if (!IsFinite(image.cam_from_world)) {
      throw std::invalid_argument(prefix + label +
                                  ": cam_from_world is not finite");
    }
    if (image.cam_from_world.rotation.norm() == 0.0) {
      throw std::invalid_argument(prefix + label + ": zero quaternion");
    }
    for (const ColmapPoint2D& point : image.points2D) {
      CheckFinite(point.xy.x(), label + " point2D");
      CheckFinite(point.xy.y(), label + " point2D");
      if (point.point3D_id != kColmapNoPoint3D &&
          model.points3D.count(point.point3D_id) == 0) {
        throw std::invalid_argument(
            prefix + label + ": a point2D names " + "point3D_id " +
            std::to_string(point.point3D_id) + ", which is not in the model");
      }
    }
  }
  for (const auto& [id, point] : model.points3D) {
    const std::string label = "point3D_id " + std::to_string(point.point3D_id);
    if (id != point.point3D_id || id < 0) {
      throw std::invalid_argument(prefix + "points3D[" + std::to_string(id) +
                                  "] holds " + label +
                                  " (ids must be equal and >= 0)");
    }
    for (int k = 0; k < 3; ++k) CheckFinite(point.xyz[k], label);
    CheckFinite(point.error, label + " error");
    for (const ColmapTrackElement& element : point.track) {
      const std::string problem =
          TrackElementProblem(element, model.images, "the model");
      if (!problem.empty()) {
        throw std::invalid_argument(prefix + label + ": " + problem);
      }
    }
  }
}

}  // namespace

const char* ColmapCameraModelName(ColmapCameraModel model) {
  return ModelInfo(model).name;
}

int ColmapCameraModelNumParams(ColmapCameraModel model) {
  return ModelInfo(model).num_params;
}

std::optional<ColmapCameraModel> ColmapCameraModelFromId(int model_id) {
  if (model_id < 0 || model_id >= kNumCameraModels) return std::nullopt;
  return kCameraModels[model_id].model;
}

std::optional<ColmapPinholeIndices> ColmapCameraModelPinholeIndices(
    ColmapCameraModel model) {
  const CameraModelInfo& info = ModelInfo(model);
  if (info.num_focal_params == 0) return std::nullopt;
  ColmapPinholeIndices indices;
  indices.fx = 0;
  indices.fy = info.num_focal_params - 1;
  indices.cx = info.num_focal_params;
  indices.cy = info.num_focal_params + 1;
  return indices;
}

std::optional<ColmapCameraModel> ColmapCameraModelFromName(
    std::string_view name) {
  for (const CameraModelInfo& info : kCameraModels) {
    if (name == info.name) return info.model;
  }
  return std::nullopt;
}

std::optional<ColmapFormat> DetectColmapModelFormat(const std::string& dir) {
  const auto all_exist = [&](const char* extension) {
    std::error_code error;
    for (const char* stem : {"cameras", "images", "points3D"}) {
      if (!fs::is_regular_file(fs::path(dir) / (std::string(stem) + extension),
                               error)) {
        return false;
      }
    }
    return true;
  };
  if (all_exist(".bin")) return ColmapFormat::kBinary;
  if (all_exist(".txt")) return ColmapFormat::kText;
  return std::nullopt;
}

ColmapModel ReadColmapModel(const std::string& dir,
                            const ColmapReadOptions& options) {
  const std::optional<ColmapFormat> format = DetectColmapModelFormat(dir);
  if (!format) {
    std::error_code error;
    if (!fs::is_directory(dir, error)) {
      throw FormatError(dir + ": not a COLMAP model: no such directory");
    }
    std::string found;
    for (const char* name : {"cameras.bin",
                             "images.bin",
                             "points3D.bin",
                             "cameras.txt",
                             "images.txt",
                             "points3D.txt"}) {
      if (fs::exists(fs::path(dir) / name, error)) {
        found += found.empty() ? name : std::string(", ") + name;
      }
    }
    throw FormatError(dir +
                      ": not a COLMAP model: expected cameras, images and "
                      "points3D as .bin or as .txt files, found " +
                      (found.empty() ? std::string("none") : found));
  }
  const std::string extension =
      *format == ColmapFormat::kBinary ? ".bin" : ".txt";
  const std::string cameras_path =
      (fs::path(dir) / ("cameras" + extension)).string();
  const std::string images_path =
      (fs::path(dir) / ("images" + extension)).string();
  const std::string points_path =
      (fs::path(dir) / ("points3D" + extension)).string();

  ColmapModel model;
  if (*format == ColmapFormat::kBinary) {
    model.cameras = ReadCamerasBinary(cameras_path);
    model.images = ReadImagesBinary(images_path, model.cameras, cameras_path);
    if (options.read_points3D) {
      model.points3D =
          ReadPoints3DBinary(points_path, model.images, images_path);
    }
  } else {
    model.cameras = ReadCamerasText(cameras_path);
    model.images = ReadImagesText(images_path, model.cameras, cameras_path);
    if (options.read_points3D) {
      model.points3D = ReadPoints3DText(points_path, model.images, images_path);
    }
  }
  ApplyRigsAndFrames(dir, extension, &model.images);
  if (options.read_points3D) {
    CheckPoint3DReferences(model, images_path, points_path);
  }
  return model;
}

void WriteColmapModel(const ColmapModel& model,
                      const std::string& dir,
                      ColmapFormat format) {
  CheckWritable(model, format);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) {
    throw FormatError(dir +
                      ": cannot create the directory: " + error.message());
  }
  // Rigs and frames of this format go first, so that a write that stops
  // half-way never leaves stale frames beside new images.
  const std::string extension =
      format == ColmapFormat::kBinary ? ".bin" : ".txt";
  const std::string rigs_path = (fs::path(dir) / ("rigs" + extension)).string();
  const std::string frames_path =
      (fs::path(dir) / ("frames" + extension)).string();
  for (const std::string& stale : {frames_path, rigs_path}) {
    fs::remove(stale, error);
    if (error) {
      throw FormatError(stale + ": cannot remove: " + error.message());
    }
  }
  const internal::RigMap rigs = internal::TrivialRigs(model);
  const internal::FrameMap frames = internal::TrivialFrames(model);
  if (format == ColmapFormat::kBinary) {
    WriteBinary(model, dir);
    internal::WriteRigsBinary(rigs, rigs_path);
    internal::WriteFramesBinary(frames, frames_path);
  } else {
    WriteText(model, dir);
    internal::WriteRigsText(rigs, rigs_path);
    internal::WriteFramesText(frames, frames_path);
  }
}

}  // namespace odomcal
