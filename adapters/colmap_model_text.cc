// COLMAP's text model files (cameras.txt, images.txt, points3D.txt). They
// are read through TextLineReader; images.txt is read in pairs of lines, the
// second taken raw (it may be empty). The writer mirrors COLMAP 3.8's
// WriteXxxText: the same field order, the same headers, numbers printed as
// "%.17g" through std::to_chars (locale-independent, and what COLMAP's
// ostream with precision 17 prints).

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/colmap_model_internal.h"
#include "odomcal/adapters/text_reader.h"

#include <charconv>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace odomcal::internal {
namespace {

namespace fs = std::filesystem;

}  // namespace

std::map<uint32_t, ColmapCamera> ReadCamerasText(const std::string& path) {
  TextLineReader reader(path);
  std::map<uint32_t, ColmapCamera> cameras;
  std::string line;
  while (reader.NextDataLine(&line)) {
    const std::vector<std::string_view> fields = SplitOnBlanks(line);
    if (fields.size() < 4) {
      reader.Fail("expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[], got " +
                  std::to_string(fields.size()) + " fields");
    }
    ColmapCamera camera;
    camera.camera_id = static_cast<uint32_t>(ParseUnsigned(
        fields[0], "CAMERA_ID", std::numeric_limits<uint32_t>::max(), reader));
    if (cameras.count(camera.camera_id) != 0) {
      reader.Fail("duplicate camera_id " + std::to_string(camera.camera_id));
    }
    const std::optional<ColmapCameraModel> model =
        ColmapCameraModelFromName(fields[1]);
    if (!model) {
      reader.Fail("unknown camera model '" + std::string(fields[1]) + "'");
    }
    camera.model = *model;
    const uint64_t kMax = std::numeric_limits<uint64_t>::max();
    camera.width = ParseUnsigned(fields[2], "WIDTH", kMax, reader);
    camera.height = ParseUnsigned(fields[3], "HEIGHT", kMax, reader);
    if (fields.size() - 4 !=
        static_cast<size_t>(ModelInfo(camera.model).num_params)) {
      reader.Fail("camera_id " + std::to_string(camera.camera_id) + ": " +
                  ParamCountText(camera.model, fields.size() - 4));
    }
    for (size_t k = 4; k < fields.size(); ++k) {
      camera.params.push_back(ParseFiniteDouble(fields[k], "PARAMS", reader));
    }
    cameras.emplace(camera.camera_id, camera);
  }
  return cameras;
}

std::map<uint32_t, ColmapImage> ReadImagesText(
    const std::string& path,
    const std::map<uint32_t, ColmapCamera>& cameras,
    const std::string& cameras_path) {
  TextLineReader reader(path);
  std::map<uint32_t, ColmapImage> images;
  const uint32_t kMaxId = std::numeric_limits<uint32_t>::max();
  std::string line;
  while (reader.NextDataLine(&line)) {
    const std::vector<std::string_view> fields = SplitOnBlanks(line);
    if (fields.size() != 10) {
      reader.Fail(
          "expected 10 fields (IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME; "
          "names cannot contain blanks), got " +
          std::to_string(fields.size()));
    }
    ColmapImage image;
    image.image_id = static_cast<uint32_t>(
        ParseUnsigned(fields[0], "IMAGE_ID", kMaxId, reader));
    if (images.count(image.image_id) != 0) {
      reader.Fail("duplicate image_id " + std::to_string(image.image_id));
    }
    const char* const kPoseNames[] = {"QW", "QX", "QY", "QZ", "TX", "TY", "TZ"};
    double pose[7];
    for (int k = 0; k < 7; ++k) {
      pose[k] = ParseFiniteDouble(fields[1 + k], kPoseNames[k], reader);
    }
    const std::string problem =
        QuaternionProblem(pose[0], pose[1], pose[2], pose[3]);
    if (!problem.empty()) {
      reader.Fail("image_id " + std::to_string(image.image_id) + ": " +
                  problem);
    }
    image.cam_from_world = MakeCamFromWorld(pose, pose + 4);
    image.camera_id = static_cast<uint32_t>(
        ParseUnsigned(fields[8], "CAMERA_ID", kMaxId, reader));
    image.name = std::string(fields[9]);
    if (cameras.count(image.camera_id) == 0) {
      reader.Fail(ImageLabel(image) + ": camera_id " +
                  std::to_string(image.camera_id) + " is not in " +
                  cameras_path);
    }
    if (!reader.NextRawLine(&line)) {
      reader.Fail(ImageLabel(image) +
                  ": missing its POINTS2D line (images.txt has two lines per "
                  "image; the second may be empty)");
    }
    const std::string_view points_line = TrimBlanks(line);
    if (!points_line.empty() && points_line.front() == '#') {
      reader.Fail("expected the POINTS2D line of " + ImageLabel(image) +
                  ", found a comment");
    }
    const std::vector<std::string_view> values = SplitOnBlanks(points_line);
    if (values.size() % 3 != 0) {
      reader.Fail("POINTS2D of " + ImageLabel(image) +
                  ": expected triples X Y POINT3D_ID, got " +
                  std::to_string(values.size()) + " values");
    }
    image.points2D.resize(values.size() / 3);
    for (size_t k = 0; k < image.points2D.size(); ++k) {
      ColmapPoint2D& point = image.points2D[k];
      point.xy.x() = ParseFiniteDouble(values[3 * k], "X", reader);
      point.xy.y() = ParseFiniteDouble(values[3 * k + 1], "Y", reader);
      const std::string_view id = values[3 * k + 2];
      point.point3D_id = id == "-1"
                             ? kColmapNoPoint3D
                             : static_cast<int64_t>(ParseUnsigned(
                                   id, "POINT3D_ID", kMaxPoint3DId, reader));
    }
    const uint32_t id = image.image_id;
    images.emplace(id, std::move(image));
  }
  return images;
}

std::map<int64_t, ColmapPoint3D> ReadPoints3DText(
    const std::string& path,
    const std::map<uint32_t, ColmapImage>& images,
    const std::string& images_path) {
  TextLineReader reader(path);
  std::map<int64_t, ColmapPoint3D> points;
  const uint32_t kMaxU32 = std::numeric_limits<uint32_t>::max();
  std::string line;
  while (reader.NextDataLine(&line)) {
    const std::vector<std::string_view> fields = SplitOnBlanks(line);
    if (fields.size() < 8 || (fields.size() - 8) % 2 != 0) {
      reader.Fail(
          "expected POINT3D_ID X Y Z R G B ERROR and pairs IMAGE_ID "
          "POINT2D_IDX, got " +
          std::to_string(fields.size()) + " fields");
    }
    ColmapPoint3D point;
    point.point3D_id = static_cast<int64_t>(
        ParseUnsigned(fields[0], "POINT3D_ID", kMaxPoint3DId, reader));
    if (points.count(point.point3D_id) != 0) {
      reader.Fail("duplicate point3D_id " + std::to_string(point.point3D_id));
    }
    const char* const kXyzNames[] = {"X", "Y", "Z"};
    const char* const kRgbNames[] = {"R", "G", "B"};
    for (int k = 0; k < 3; ++k) {
      point.xyz[k] = ParseFiniteDouble(fields[1 + k], kXyzNames[k], reader);
      point.rgb[k] = static_cast<uint8_t>(
          ParseUnsigned(fields[4 + k], kRgbNames[k], 255, reader));
    }
    point.error = ParseFiniteDouble(fields[7], "ERROR", reader);
    point.track.resize((fields.size() - 8) / 2);
    for (size_t k = 0; k < point.track.size(); ++k) {
      ColmapTrackElement& element = point.track[k];
      element.image_id = static_cast<uint32_t>(
          ParseUnsigned(fields[8 + 2 * k], "IMAGE_ID", kMaxU32, reader));
      element.point2D_idx = static_cast<uint32_t>(
          ParseUnsigned(fields[9 + 2 * k], "POINT2D_IDX", kMaxU32, reader));
      const std::string problem =
          TrackElementProblem(element, images, images_path);
      if (!problem.empty()) {
        reader.Fail("point3D_id " + std::to_string(point.point3D_id) + ": " +
                    problem);
      }
    }
    const int64_t id = point.point3D_id;
    points.emplace(id, std::move(point));
  }
  return points;
}

void WriteText(const ColmapModel& model, const fs::path& dir) {
  {
    OutputFile file((dir / "cameras.txt").string());
    file.PutText(
        "# Camera list with one line of data per camera:\n"
        "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
        "# Number of cameras: " +
        std::to_string(model.cameras.size()) + "\n");
    for (const auto& [id, camera] : model.cameras) {
      std::string line =
          std::to_string(id) + " " + ModelInfo(camera.model).name + " " +
          std::to_string(camera.width) + " " + std::to_string(camera.height);
      for (const double param : camera.params) {
        line += " " + FormatDouble(param);
      }
      file.PutText(line + "\n");
    }
    file.Close();
  }
  {
    size_t num_observations = 0;
    for (const auto& [id, image] : model.images) {
      for (const ColmapPoint2D& point : image.points2D) {
        if (point.point3D_id != kColmapNoPoint3D) ++num_observations;
      }
    }
    const double mean_observations =
        model.images.empty() ? 0.0
                             : static_cast<double>(num_observations) /
                                   static_cast<double>(model.images.size());
    OutputFile file((dir / "images.txt").string());
    file.PutText(
        "# Image list with two lines of data per image:\n"
        "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
        "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
        "# Number of images: " +
        std::to_string(model.images.size()) +
        ", mean observations per image: " + FormatDouble(mean_observations) +
        "\n");
    for (const auto& [id, image] : model.images) {
      const Eigen::Quaterniond q = NormalizedRotation(image);
      const Eigen::Vector3d& t = image.cam_from_world.translation;
      std::string line = std::to_string(id);
      for (const double value :
           {q.w(), q.x(), q.y(), q.z(), t.x(), t.y(), t.z()}) {
        line += " " + FormatDouble(value);
      }
      line += " " + std::to_string(image.camera_id) + " " + image.name + "\n";
      std::string points;
      for (const ColmapPoint2D& point : image.points2D) {
        if (!points.empty()) points += " ";
        points += FormatDouble(point.xy.x()) + " " +
                  FormatDouble(point.xy.y()) + " " +
                  std::to_string(point.point3D_id);
      }
      file.PutText(line + points + "\n");
    }
    file.Close();
  }
  {
    size_t track_sum = 0;
    for (const auto& [id, point] : model.points3D) {
      track_sum += point.track.size();
    }
    const double mean_track_length =
        model.points3D.empty() ? 0.0
                               : static_cast<double>(track_sum) /
                                     static_cast<double>(model.points3D.size());
    OutputFile file((dir / "points3D.txt").string());
    file.PutText(
        "# 3D point list with one line of data per point:\n"
        "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, "
        "POINT2D_IDX)\n"
        "# Number of points: " +
        std::to_string(model.points3D.size()) +
        ", mean track length: " + FormatDouble(mean_track_length) + "\n");
    for (const auto& [id, point] : model.points3D) {
      // COLMAP ends the fixed columns with a blank even without a track.
      std::string line = std::to_string(id);
      for (int k = 0; k < 3; ++k) line += " " + FormatDouble(point.xyz[k]);
      for (const uint8_t channel : point.rgb) {
        line += " " + std::to_string(channel);
      }
      line += " " + FormatDouble(point.error) + " ";
      std::string track;
      for (const ColmapTrackElement& element : point.track) {
        if (!track.empty()) track += " ";
        track += std::to_string(element.image_id) + " " +
                 std::to_string(element.point2D_idx);
      }
      file.PutText(line + track + "\n");
    }
    file.Close();
  }
}

}  // namespace odomcal::internal
