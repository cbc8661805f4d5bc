// ExtractBag (bag_extraction.h): one pass over the bag, writing each image as
// it arrives and keeping only stamps and poses.
#include "odomcal/adapters/bag/bag_extraction.h"

#include "odomcal/adapters/bag/camera_info_conversion.h"
#include "odomcal/adapters/bag/image_conversion.h"
#include "odomcal/adapters/bag/ros_messages.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"

#include <opencv2/imgcodecs.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace odomcal::bag {
namespace {

namespace fs = std::filesystem;

// Per chosen topic: stamp order, duplicates, rates and header/receive
// offsets.
class TopicStamps {
 public:
  TopicStamps(std::string context, std::string topic, std::string type)
      : context_(std::move(context)) {
    summary_.topic = std::move(topic);
    summary_.type = std::move(type);
  }

  // Counts a message and returns its stamp in the chosen time. Throws for
  // an unset header stamp when header stamps are chosen.
  int64_t Stamp(int64_t header_ns, int64_t receive_ns, BagTime time) {
    ++summary_.messages;
    offset_sum_s_ += std::abs(ElapsedSeconds(receive_ns, header_ns));
    if (time == BagTime::kHeader && header_ns == 0) {
      throw FormatError(context_ + ": message " +
                        std::to_string(summary_.messages) +
                        " has no header stamp (0); pass --bag_time receive "
                        "to use the receive times");
    }
    return time == BagTime::kHeader ? header_ns : receive_ns;
  }

  // True when a message at `stamp` is to be used; false for a repeat of the
  // previous stamp. Throws for a stamp before the previous one.
  bool Use(int64_t stamp, BagTime time) {
    if (summary_.used > 0) {
      if (stamp < summary_.last_stamp_ns) {
        throw FormatError(context_ + ": " + BagTimeName(time) + " stamp " +
                          std::to_string(stamp) + " ns comes after " +
                          std::to_string(summary_.last_stamp_ns) +
                          " ns (stamps go backwards)");
      }
      if (stamp == summary_.last_stamp_ns) {
        ++summary_.duplicate_stamps;
        return false;
      }
    } else {
      summary_.first_stamp_ns = stamp;
    }
    summary_.last_stamp_ns = stamp;
    ++summary_.used;
    return true;
  }

  const std::string& context() const { return context_; }
  int64_t last_stamp_ns() const { return summary_.last_stamp_ns; }

  TopicExtractionSummary Finish() const {
    TopicExtractionSummary summary = summary_;
    if (summary.messages > 0) {
      summary.mean_abs_header_minus_receive_s =
          offset_sum_s_ / static_cast<double>(summary.messages);
    }
    if (summary.used > 1) {
      summary.rate_hz =
          static_cast<double>(summary.used - 1) /
          ElapsedSeconds(summary.first_stamp_ns, summary.last_stamp_ns);
    }
    return summary;
  }

 private:
  std::string context_;
  TopicExtractionSummary summary_;
  double offset_sum_s_ = 0.0;
};

std::string ErrnoText() { return std::strerror(errno); }

void WriteBytes(const std::string& path, const std::vector<uint8_t>& data) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) {
    throw FormatError(path + ": cannot open for writing: " + ErrnoText());
  }
  file.write(reinterpret_cast<const char*>(data.data()),
             static_cast<std::streamsize>(data.size()));
  file.close();
  if (!file) throw FormatError(path + ": write failed");
}

void WriteText(const std::string& path, const std::string& text) {
  WriteBytes(path, std::vector<uint8_t>(text.begin(), text.end()));
}

// The output folder, created, and empty so that no earlier extraction's
// files mix with this one's.
void PrepareOutputFolder(const std::string& folder) {
  std::error_code error;
  if (fs::exists(folder, error)) {
    if (!fs::is_directory(folder, error)) {
      throw FormatError(folder + ": exists and is not a folder");
    }
    if (!fs::is_empty(folder, error)) {
      throw FormatError(folder +
                        ": the output folder is not empty; choose a "
                        "new or empty folder");
    }
  }
  fs::create_directories(fs::path(folder) / "images", error);
  if (error) {
    throw FormatError(folder +
                      ": cannot create the folder: " + error.message());
  }
}

// Decode* throws "<type>: <problem>"; the bag path and topic go in front.
template <typename Decode>
auto DecodeIn(const std::string& context, Decode decode) {
  try {
    return decode();
  } catch (const FormatError& error) {
    throw FormatError(context + ": " + error.what());
  }
}

bool SameCalibration(const CameraInfoMessage& a, const CameraInfoMessage& b) {
  return a.width == b.width && a.height == b.height &&
         a.distortion_model == b.distortion_model && a.d == b.d && a.k == b.k;
}

std::string Milliseconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f ms", seconds * 1e3);
  return text;
}

struct ImageSize {
  int width = 0;
  int height = 0;
};

enum class TopicRole { kNone, kImage, kOdometry, kCameraInfo };

struct TopicUse {
  TopicRole role = TopicRole::kNone;
  size_t camera = 0;  // kImage, kCameraInfo: which camera's
};

// What one camera keeps between messages: its stamps, its image size and
// its first CameraInfo.
struct CameraState {
  ChosenCamera chosen;
  std::optional<TopicStamps> images;
  std::optional<TopicStamps> infos;
  std::optional<ImageSize> image_size;
  std::optional<CameraInfoMessage> first_info;
  std::optional<ColmapCamera> camera;
  int64_t changed_infos = 0;
};

// One extraction: the chosen topics, the output folder, and what is kept
// between messages (stamps, poses or wheel travels, each camera's first
// CameraInfo).
class Extraction {
 public:
  Extraction(BagReader& reader, const BagExtractionOptions& options)
      : reader_(reader), options_(options) {
    options.Check();
    summary_.topics = ChooseTopics(reader.Topics(), options);
    summary_.time = options.time;
    summary_.wheel_track_m = options.wheel_track_m;
    const ChosenTopics& chosen = summary_.topics;
    if (chosen.odometry_joint_state && !(options.wheel_radius_m > 0.0)) {
      throw std::invalid_argument(
          chosen.odometry +
          " holds joint states (wheel angles in rad): pass --wheel_radius_m "
          "to turn them into travels");
    }
    const std::vector<BagTopic>& topics = reader.Topics();
    uses_.assign(topics.size(), TopicUse{});
    cameras_.resize(chosen.cameras.size());
    std::string odometry_type;
    for (size_t k = 0; k < chosen.cameras.size(); ++k) {
      cameras_[k].chosen = chosen.cameras[k];
    }
    for (size_t i = 0; i < topics.size(); ++i) {
      const std::string& name = topics[i].topic;
      if (name == chosen.odometry) {
        uses_[i].role = TopicRole::kOdometry;
        odometry_type = topics[i].type;
      }
      for (size_t k = 0; k < cameras_.size(); ++k) {
        CameraState& camera = cameras_[k];
        if (name == camera.chosen.image) {
          uses_[i] = {TopicRole::kImage, k};
          camera.images.emplace(ContextOf(name), name, topics[i].type);
        } else if (!camera.chosen.camera_info.empty() &&
                   name == camera.chosen.camera_info) {
          uses_[i] = {TopicRole::kCameraInfo, k};
          camera.infos.emplace(ContextOf(name), name, topics[i].type);
        }
      }
      if (uses_[i].role != TopicRole::kNone) total_ += topics[i].message_count;
    }
    for (CameraState& camera : cameras_) {
      if (!camera.infos) camera.infos.emplace(ContextOf(""), "", "");
    }
    odometry_.emplace(
        ContextOf(chosen.odometry), chosen.odometry, odometry_type);
    if (chosen.odometry_joint_state) {
      WheelJointOptions joints;
      joints.left_joint = options.left_wheel_joint;
      joints.right_joint = options.right_wheel_joint;
      joints.wheel_radius_m = options.wheel_radius_m;
      wheels_.emplace(joints, odometry_->context());
    }
    // Last: nothing is created for options or topics that are refused.
    PrepareOutputFolder(options.output_folder);
    for (const CameraState& camera : cameras_) {
      if (camera.chosen.name.empty()) continue;
      std::error_code error;
      const fs::path folder = Output() / "images" / camera.chosen.name;
      fs::create_directories(folder, error);
      if (error) {
        throw FormatError(folder.string() +
                          ": cannot create the folder: " + error.message());
      }
    }
  }

  void Run(const ExtractionProgress& progress) {
    BagMessage message;
    int64_t done = 0;
    while (reader_.Next(&message)) {
      if (message.topic_index >= uses_.size()) continue;
      const MessageEncoding encoding =
          reader_.Topics()[message.topic_index].encoding;
      const TopicUse use = uses_[message.topic_index];
      switch (use.role) {
        case TopicRole::kNone:
          continue;
        case TopicRole::kImage:
          if (cameras_[use.camera].chosen.image_compressed) {
            OnCompressedImage(message, encoding, &cameras_[use.camera]);
          } else {
            OnRawImage(message, encoding, &cameras_[use.camera]);
          }
          break;
        case TopicRole::kOdometry:
          if (wheels_) {
            OnJointState(message, encoding);
          } else {
            OnOdometry(message, encoding);
          }
          break;
        case TopicRole::kCameraInfo:
          OnCameraInfo(message, encoding, &cameras_[use.camera]);
          break;
      }
      ++done;
      if (progress) progress(done, total_);
    }
  }

  BagExtractionSummary Finish() {
    for (const CameraState& camera : cameras_) {
      CameraExtractionSummary extracted;
      extracted.name = camera.chosen.name;
      extracted.images = camera.images->Finish();
      if (extracted.images.used == 0) {
        throw FormatError(camera.images->context() + ": no image messages");
      }
      summary_.cameras.push_back(std::move(extracted));
    }
    summary_.odometry = odometry_->Finish();
    if (summary_.odometry.messages == 0) {
      throw FormatError(odometry_->context() + ": no odometry messages");
    }
    WriteText((Output() / "image_timestamps.csv").string(), image_csv_);
    WriteOdometry();
    WriteCameras();
    AddStampWarnings();
    return std::move(summary_);
  }

 private:
  std::string ContextOf(const std::string& topic) const {
    return reader_.Path() + ": " + topic;
  }
  fs::path Output() const { return fs::path(options_.output_folder); }

  // "<stamp>.png", or a rig camera's "<name>/<stamp>.png": the name in
  // image_timestamps.csv, relative to images/.
  static std::string ImageName(const CameraState& camera,
                               const std::string& file) {
    return camera.chosen.name.empty() ? file : camera.chosen.name + "/" + file;
  }

  void OnCompressedImage(const BagMessage& message,
                         MessageEncoding encoding,
                         CameraState* camera) {
    const std::string& context = camera->images->context();
    const CompressedImageMessage image = DecodeIn(
        context, [&] { return DecodeCompressedImage(encoding, message.data); });
    const int64_t stamp = camera->images->Stamp(
        image.header.stamp_ns, message.log_time_ns, options_.time);
    if (!camera->images->Use(stamp, options_.time)) return;
    const std::string name = ImageName(
        *camera,
        std::to_string(stamp) + CompressedImageExtension(image, context));
    // Every image is decoded: COLMAP would skip one that does not decode
    // without a word, and all must have the size CameraInfo gives.
    cv::Mat pixels;
    try {
      pixels = cv::imdecode(image.data, cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception&) {
      pixels.release();
    }
    if (pixels.empty()) {
      throw FormatError(context + ": the image at " + std::to_string(stamp) +
                        " ns (" + name + ") does not decode");
    }
    CheckImageSize(pixels, stamp, camera);
    WriteBytes((Output() / "images" / name).string(), image.data);
    AddImageLine(name, stamp);
  }

  void OnRawImage(const BagMessage& message,
                  MessageEncoding encoding,
                  CameraState* camera) {
    const std::string& context = camera->images->context();
    const ImageMessage image =
        DecodeIn(context, [&] { return DecodeImage(encoding, message.data); });
    const int64_t stamp = camera->images->Stamp(
        image.header.stamp_ns, message.log_time_ns, options_.time);
    if (!camera->images->Use(stamp, options_.time)) return;
    const cv::Mat pixels = ImageMessageToMat(image, context);
    CheckImageSize(pixels, stamp, camera);
    const std::string name = ImageName(*camera, std::to_string(stamp) + ".png");
    const std::string path = (Output() / "images" / name).string();
    bool written = false;
    try {
      written = cv::imwrite(path, pixels);
    } catch (const cv::Exception& error) {
      throw FormatError(path + ": write failed: " + error.what());
    }
    if (!written) throw FormatError(path + ": write failed");
    AddImageLine(name, stamp);
  }

  // A camera's first image sets its size; every later one must have it.
  static void CheckImageSize(const cv::Mat& pixels,
                             int64_t stamp_ns,
                             CameraState* camera) {
    if (!camera->image_size) {
      camera->image_size = ImageSize{pixels.cols, pixels.rows};
      CheckCameraSize(*camera);
    } else if (pixels.cols != camera->image_size->width ||
               pixels.rows != camera->image_size->height) {
      throw FormatError(camera->images->context() + ": image at " +
                        std::to_string(stamp_ns) + " ns is " +
                        std::to_string(pixels.cols) + " x " +
                        std::to_string(pixels.rows) + ", the first is " +
                        std::to_string(camera->image_size->width) + " x " +
                        std::to_string(camera->image_size->height));
    }
  }

  void AddImageLine(const std::string& name, int64_t stamp_ns) {
    image_csv_ += name + "," + FormatTimestampSeconds(stamp_ns) + "\n";
  }

  // As soon as both are known, so that a wrong CameraInfo stops early.
  static void CheckCameraSize(const CameraState& camera) {
    if (!camera.image_size || !camera.first_info) return;
    CheckCameraInfoImageSize(*camera.first_info,
                             static_cast<uint32_t>(camera.image_size->width),
                             static_cast<uint32_t>(camera.image_size->height),
                             camera.infos->context());
  }

  void OnJointState(const BagMessage& message, MessageEncoding encoding) {
    const JointStateMessage joints = DecodeIn(odometry_->context(), [&] {
      return DecodeJointState(encoding, message.data);
    });
    const int64_t stamp = odometry_->Stamp(
        joints.header.stamp_ns, message.log_time_ns, options_.time);
    // Messages without the wheels (other joints) take no part in the stamp
    // checks.
    const std::optional<WheelTravelSample> sample =
        wheels_->Sample(stamp, joints);
    if (sample && odometry_->Use(stamp, options_.time)) {
      wheels_->Append(*sample);
    }
  }

  void OnOdometry(const BagMessage& message, MessageEncoding encoding) {
    const std::string& context = odometry_->context();
    const OdometryMessage odometry = DecodeIn(
        context, [&] { return DecodeOdometry(encoding, message.data); });
    const int64_t stamp = odometry_->Stamp(
        odometry.header.stamp_ns, message.log_time_ns, options_.time);
    if (odometry_->Use(stamp, options_.time)) {
      poses_.push_back({stamp, PoseFromOdometry(odometry, context)});
    }
  }

  void OnCameraInfo(const BagMessage& message,
                    MessageEncoding encoding,
                    CameraState* camera) {
    CameraInfoMessage info = DecodeIn(camera->infos->context(), [&] {
      return DecodeCameraInfo(encoding, message.data);
    });
    // Only the first CameraInfo is used; its stamps are not checked.
    camera->infos->Stamp(
        info.header.stamp_ns, message.log_time_ns, BagTime::kReceive);
    if (!camera->first_info) {
      // Converted now, so that an unusable calibration stops early.
      camera->camera =
          ColmapCameraFromCameraInfo(info, camera->infos->context());
      camera->first_info = std::move(info);
      CheckCameraSize(*camera);
    } else if (!SameCalibration(*camera->first_info, info)) {
      ++camera->changed_infos;
    }
  }

  void WriteOdometry() {
    const std::string& topic = summary_.topics.odometry;
    if (wheels_) {
      const WheelTravels travels = wheels_->Finish();
      summary_.odometry_file = "wheels.csv";
      WriteWheelTravelCsv(travels, (Output() / "wheels.csv").string());
      summary_.left_wheel_joint = wheels_->left_joint();
      summary_.right_wheel_joint = wheels_->right_joint();
      if (wheels_->skipped() > 0) {
        summary_.warnings.push_back(
            topic + ": " + std::to_string(wheels_->skipped()) +
            " joint states without both wheel joints were skipped");
      }
      return;
    }
    const Trajectory trajectory = OdometryTrajectory(
        std::move(poses_), odometry_->context(), options_.planarity);
    summary_.planar = trajectory.planar;
    summary_.odometry_file =
        trajectory.planar ? "odometry.csv" : "odometry.tum";
    const std::string path = (Output() / summary_.odometry_file).string();
    if (trajectory.planar) {
      WriteOdometryCsv(trajectory, path);
    } else {
      WriteTumTrajectory(trajectory, path);
    }
  }

  // camera.txt for one camera, cameras.txt for a rig (camera_id k + 1 for
  // the k-th camera); nothing when no camera has a CameraInfo.
  void WriteCameras() {
    const std::string convention =
        " (K and D of the unrectified images); principal point in COLMAP's "
        "convention, top-left pixel centre at (0.5, 0.5): cx = K[2] + 0.5, "
        "cy = K[5] + 0.5\n";
    std::string text;
    for (size_t k = 0; k < cameras_.size(); ++k) {
      CameraState& camera = cameras_[k];
      CameraExtractionSummary& extracted = summary_.cameras[k];
      if (!camera.first_info) continue;
      const std::string& topic = camera.chosen.camera_info;
      extracted.camera_info = camera.infos->Finish();
      camera.camera->camera_id = static_cast<uint32_t>(k + 1);
      extracted.camera = camera.camera;
      if (summary_.topics.rig) {
        std::string flags = OdomcalCameraFlags(*camera.camera);
        const std::string params = "--camera_params ";
        flags.insert(flags.find(params) + params.size(),
                     camera.chosen.name + "=");
        text += "# camera " + camera.chosen.name + " from " + topic +
                convention + "# odomcal run --rig: " + flags + "\n" +
                ColmapCameraLine(*camera.camera) + "\n";
      } else {
        text += "# COLMAP camera from " + topic + convention +
                "# odomcal run: " + OdomcalCameraFlags(*camera.camera) + "\n" +
                ColmapCameraLine(*camera.camera) + "\n";
      }
      if (camera.changed_infos > 0) {
        summary_.warnings.push_back(
            topic + ": " + std::to_string(camera.changed_infos) +
            " messages differ from the first CameraInfo; the first is used");
      }
    }
    if (text.empty()) return;
    WriteText((Output() / (summary_.topics.rig ? "cameras.txt" : "camera.txt"))
                  .string(),
              text);
  }

  void AddStampWarnings() {
    std::vector<const TopicExtractionSummary*> topics;
    for (const CameraExtractionSummary& camera : summary_.cameras) {
      topics.push_back(&camera.images);
    }
    topics.push_back(&summary_.odometry);
    for (const TopicExtractionSummary* topic : topics) {
      if (topic->duplicate_stamps > 0) {
        summary_.warnings.push_back(
            topic->topic + ": " + std::to_string(topic->duplicate_stamps) +
            " messages repeat the previous " + BagTimeName(options_.time) +
            " stamp and are skipped");
      }
    }
    // Header stamps far from the receive times, compared with the
    // odometry's sampling interval: then the choice of stamp matters to the
    // calibration.
    if (summary_.odometry.rate_hz <= 0.0) return;
    const double interval_s = 1.0 / summary_.odometry.rate_hz;
    for (const TopicExtractionSummary* topic : topics) {
      if (topic->mean_abs_header_minus_receive_s > interval_s) {
        summary_.warnings.push_back(
            topic->topic + ": header stamps differ from the receive times by " +
            Milliseconds(topic->mean_abs_header_minus_receive_s) +
            " on average, more than the odometry interval (" +
            Milliseconds(interval_s) + "); " +
            (options_.time == BagTime::kHeader
                 ? "header stamps are used (--bag_time header)"
                 : "receive times are used (--bag_time receive)") +
            ": check that this is the clock to trust");
      }
    }
  }

  BagReader& reader_;
  const BagExtractionOptions& options_;
  BagExtractionSummary summary_;
  std::vector<TopicUse> uses_;
  int64_t total_ = 0;
  std::vector<CameraState> cameras_;
  std::optional<TopicStamps> odometry_;
  std::string image_csv_ = "image_name,timestamp\n";
  std::vector<StampedPose> poses_;
  std::optional<WheelTravelCollector> wheels_;
};

}  // namespace

BagExtractionSummary ExtractBag(BagReader& reader,
                                const BagExtractionOptions& options,
                                const ExtractionProgress& progress) {
  Extraction extraction(reader, options);
  extraction.Run(progress);
  return extraction.Finish();
}

}  // namespace odomcal::bag
