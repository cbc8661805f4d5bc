// COLMAP model files. Binary files are read through a BinaryReader that
// knows the file size and its own offset: every field read first checks that
// its bytes remain, every count is compared with the remaining bytes divided
// by the smallest possible record size before anything is reserved, and the
// failure message carries the path, the byte offset of the field and the
// record being read. Little-endian integers are assembled byte by byte, so
// the code does not depend on the host's byte order. Text files go through
// TextLineReader; images.txt is read in pairs of lines, the second taken raw
// (it may be empty). Cross references (an image's camera, a track's image and
// point2D index, a point2D's point3D) are checked once the files they point
// into have been read. Writers mirror COLMAP 3.8's WriteXxxBinary/Text: the
// same field order and widths, the same text headers, numbers printed as
// "%.17g" through std::to_chars (locale-independent, and what COLMAP's
// ostream with precision 17 prints).
#include "odomcal/adapters/colmap_model.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/text_reader.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// COLMAP writes normalised quaternions; a norm this far from 1 means the file
// is garbled or was not written as cam_from_world quaternions at all.
constexpr double kMaxQuaternionNormDeviation = 1e-2;
constexpr uint64_t kBinaryNoPoint3D = std::numeric_limits<uint64_t>::max();
constexpr uint64_t kMaxPoint3DId =
    static_cast<uint64_t>(std::numeric_limits<int64_t>::max());

// Smallest possible binary records, for bounding counts before allocating.
constexpr uint64_t kMinCameraBytes = 4 + 4 + 8 + 8 + 3 * 8;
constexpr uint64_t kMinImageBytes = 4 + 7 * 8 + 4 + 1 + 8;  // empty name
constexpr uint64_t kPoint2DBytes = 3 * 8;
constexpr uint64_t kMinPoint3DBytes = 8 + 3 * 8 + 3 + 8 + 8;
constexpr uint64_t kTrackElementBytes = 4 + 4;

struct CameraModelInfo {
  ColmapCameraModel model;
  const char* name;
  int num_params;
};

// Index = COLMAP model id (camera_models.h of COLMAP 3.8).
constexpr CameraModelInfo kCameraModels[] = {
    {ColmapCameraModel::kSimplePinhole, "SIMPLE_PINHOLE", 3},
    {ColmapCameraModel::kPinhole, "PINHOLE", 4},
    {ColmapCameraModel::kSimpleRadial, "SIMPLE_RADIAL", 4},
    {ColmapCameraModel::kRadial, "RADIAL", 5},
    {ColmapCameraModel::kOpenCV, "OPENCV", 8},
    {ColmapCameraModel::kOpenCVFisheye, "OPENCV_FISHEYE", 8},
    {ColmapCameraModel::kFullOpenCV, "FULL_OPENCV", 12},
    {ColmapCameraModel::kFov, "FOV", 5},
    {ColmapCameraModel::kSimpleRadialFisheye, "SIMPLE_RADIAL_FISHEYE", 4},
    {ColmapCameraModel::kRadialFisheye, "RADIAL_FISHEYE", 5},
    {ColmapCameraModel::kThinPrismFisheye, "THIN_PRISM_FISHEYE", 12},
};
constexpr int kNumCameraModels =
    static_cast<int>(sizeof(kCameraModels) / sizeof(kCameraModels[0]));

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
         " (COLMAP 3.8 models are 0 to " +
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

// ---------------------------------------------------------------------------
// Binary input.

class BinaryReader {
 public:
  explicit BinaryReader(const std::string& path) : path_(path) {
    std::error_code error;
    if (fs::is_directory(path, error)) {
      throw FormatError(path + ": cannot open for reading: is a directory");
    }
    errno = 0;
    stream_.open(path, std::ios::binary);
    if (!stream_.is_open()) {
      throw FormatError(path + ": cannot open for reading" + OpenReason());
    }
    size_ = fs::file_size(path, error);
    if (error) {
      throw FormatError(path +
                        ": cannot determine the file size: " + error.message());
    }
  }

  const std::string& path() const { return path_; }
  uint64_t offset() const { return offset_; }
  uint64_t remaining() const { return size_ - offset_; }
  void set_record(std::string record) { record_ = std::move(record); }

  uint8_t ReadU8(const char* what) {
    return static_cast<uint8_t>(ReadLittleEndian(1, what));
  }
  uint32_t ReadU32(const char* what) {
    return static_cast<uint32_t>(ReadLittleEndian(4, what));
  }
  int32_t ReadI32(const char* what) {
    const uint32_t bits = ReadU32(what);
    int32_t value = 0;
    std::memcpy(&value, &bits, sizeof(value));
    return value;
  }
  uint64_t ReadU64(const char* what) { return ReadLittleEndian(8, what); }

  double ReadFiniteDouble(const char* what) {
    const uint64_t start = offset_;
    const uint64_t bits = ReadLittleEndian(8, what);
    double value = 0.0;
    std::memcpy(&value, &bits, sizeof(value));
    if (!std::isfinite(value)) {
      FailAt(start, std::string(what) + " is not finite");
    }
    return value;
  }

  // A uint64 count of items that take at least `min_item_bytes` each; fails
  // unless that many items fit in the rest of the file.
  uint64_t ReadCount(const char* what, uint64_t min_item_bytes) {
    const uint64_t start = offset_;
    const uint64_t count = ReadU64(what);
    if (count > remaining() / min_item_bytes) {
      FailAt(start,
             std::string(what) + " is " + std::to_string(count) + ", but the " +
                 std::to_string(remaining()) +
                 " remaining bytes hold at most " +
                 std::to_string(remaining() / min_item_bytes) +
                 " (garbled or truncated file)");
    }
    return count;
  }

  // Bytes up to a '\0', which is consumed.
  std::string ReadNullTerminated(const char* what) {
    const uint64_t start = offset_;
    std::string text;
    while (true) {
      if (remaining() == 0) {
        FailAt(start,
               std::string("truncated: ") + what +
                   " has no terminating '\\0' before the end of the file");
      }
      const char c = static_cast<char>(ReadU8(what));
      if (c == '\0') return text;
      text.push_back(c);
    }
  }

  void ExpectEnd() {
    record_.clear();
    if (remaining() != 0) {
      Fail(std::to_string(remaining()) +
           " unexpected bytes after the last record (garbled count?)");
    }
  }

  [[noreturn]] void Fail(const std::string& what) const {
    FailAt(offset_, what);
  }

  [[noreturn]] void FailAt(uint64_t offset, const std::string& what) const {
    throw FormatError(path_ + ": byte " + std::to_string(offset) + ": " +
                      (record_.empty() ? "" : record_ + ": ") + what);
  }

 private:
  uint64_t ReadLittleEndian(int num_bytes, const char* what) {
    if (remaining() < static_cast<uint64_t>(num_bytes)) {
      Fail(std::string("truncated: ") + what + " needs " +
           std::to_string(num_bytes) + " bytes, " +
           std::to_string(remaining()) + " remain");
    }
    unsigned char bytes[8] = {};
    stream_.read(reinterpret_cast<char*>(bytes), num_bytes);
    if (stream_.gcount() != num_bytes)
      Fail(std::string("read error at ") + what);
    offset_ += num_bytes;
    uint64_t value = 0;
    for (int i = num_bytes - 1; i >= 0; --i) value = (value << 8) | bytes[i];
    return value;
  }

  std::string path_;
  std::ifstream stream_;
  uint64_t size_ = 0;
  uint64_t offset_ = 0;
  std::string record_;
};

std::string RecordName(const char* kind, uint64_t index, uint64_t count) {
  return std::string(kind) + " " + std::to_string(index + 1) + " of " +
         std::to_string(count);
}

std::map<uint32_t, ColmapCamera> ReadCamerasBinary(const std::string& path) {
  BinaryReader reader(path);
  std::map<uint32_t, ColmapCamera> cameras;
  const uint64_t count = reader.ReadCount("number of cameras", kMinCameraBytes);
  for (uint64_t i = 0; i < count; ++i) {
    const std::string record = RecordName("camera", i, count);
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
    // Bounded by the model table (at most 12), never by file content.
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
    const std::string record = RecordName("image", i, count);
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

std::map<int64_t, ColmapPoint3D> ReadPoints3DBinary(
    const std::string& path,
    const std::map<uint32_t, ColmapImage>& images,
    const std::string& images_path) {
  BinaryReader reader(path);
  std::map<int64_t, ColmapPoint3D> points;
  const uint64_t count =
      reader.ReadCount("number of points3D", kMinPoint3DBytes);
  for (uint64_t i = 0; i < count; ++i) {
    const std::string record = RecordName("point3D", i, count);
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

// ---------------------------------------------------------------------------
// Text input.

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

// "%.17g" in the C locale, as COLMAP's ostreams with precision(17) print.
std::string FormatDouble(double value) {
  char buffer[64];
  const auto result = std::to_chars(
      buffer, buffer + sizeof(buffer), value, std::chars_format::general, 17);
  return std::string(buffer, result.ptr);
}

Eigen::Quaterniond NormalizedRotation(const ColmapImage& image) {
  return image.cam_from_world.rotation.normalized();
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
  if (format == ColmapFormat::kBinary) {
    WriteBinary(model, dir);
  } else {
    WriteText(model, dir);
  }
}

}  // namespace odomcal
