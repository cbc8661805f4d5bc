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

}  // namespace

BagExtractionSummary ExtractBag(BagReader& reader,
                                const BagExtractionOptions& options,
                                const ExtractionProgress& progress) {
  options.Check();
  const std::vector<BagTopic>& topics = reader.Topics();
  BagExtractionSummary summary;
  summary.topics = ChooseTopics(topics, options);
  summary.time = options.time;
  summary.wheel_track_m = options.wheel_track_m;
  const ChosenTopics& chosen = summary.topics;

  // Topic index -> role.
  enum class Role { kNone, kImage, kOdometry, kCameraInfo };
  std::vector<Role> roles(topics.size(), Role::kNone);
  int64_t total = 0;
  const auto context_of = [&](const std::string& topic) {
    return reader.Path() + ": " + topic;
  };
  std::string image_type, odometry_type, info_type;
  for (size_t i = 0; i < topics.size(); ++i) {
    const std::string& name = topics[i].topic;
    if (name == chosen.image) {
      roles[i] = Role::kImage;
      image_type = topics[i].type;
    } else if (name == chosen.odometry) {
      roles[i] = Role::kOdometry;
      odometry_type = topics[i].type;
    } else if (!chosen.camera_info.empty() && name == chosen.camera_info) {
      roles[i] = Role::kCameraInfo;
      info_type = topics[i].type;
    }
    if (roles[i] != Role::kNone) total += topics[i].message_count;
  }
  TopicStamps image_stamps(context_of(chosen.image), chosen.image, image_type);
  TopicStamps odometry_stamps(
      context_of(chosen.odometry), chosen.odometry, odometry_type);
  TopicStamps info_stamps(
      context_of(chosen.camera_info), chosen.camera_info, info_type);

  const fs::path output(options.output_folder);
  PrepareOutputFolder(options.output_folder);
  const fs::path image_folder = output / "images";

  std::string image_csv = "image_name,timestamp\n";
  std::optional<ImageSize> image_size;
  std::vector<StampedPose> poses;
  std::optional<WheelTravelCollector> wheels;
  if (chosen.odometry_joint_state) {
    WheelJointOptions joint_options;
    joint_options.left_joint = options.left_wheel_joint;
    joint_options.right_joint = options.right_wheel_joint;
    joint_options.wheel_radius_m = options.wheel_radius_m;
    if (!(options.wheel_radius_m > 0.0)) {
      throw std::invalid_argument(
          chosen.odometry +
          " holds joint states (wheel angles in rad): pass "
          "--wheel_radius_m to turn them into travels");
    }
    wheels.emplace(joint_options, odometry_stamps.context());
  }
  std::optional<CameraInfoMessage> first_info;
  int64_t changed_infos = 0;

  BagMessage message;
  int64_t done = 0;
  while (reader.Next(&message)) {
    if (message.topic_index >= roles.size()) continue;
    const Role role = roles[message.topic_index];
    if (role == Role::kNone) continue;
    const MessageEncoding encoding = topics[message.topic_index].encoding;
    if (role == Role::kImage) {
      const std::string& context = image_stamps.context();
      if (chosen.image_compressed) {
        const CompressedImageMessage image = DecodeIn(context, [&] {
          return DecodeCompressedImage(encoding, message.data);
        });
        const int64_t stamp = image_stamps.Stamp(
            image.header.stamp_ns, message.log_time_ns, options.time);
        if (image_stamps.Use(stamp, options.time)) {
          const std::string name =
              std::to_string(image_stamps.last_stamp_ns()) +
              CompressedImageExtension(image, context);
          if (!image_size) {
            // Only the first is decoded, for its size.
            const cv::Mat pixels =
                cv::imdecode(image.data, cv::IMREAD_UNCHANGED);
            if (pixels.empty()) {
              throw FormatError(context + ": the first image (" + name +
                                ") does not decode");
            }
            image_size = ImageSize{pixels.cols, pixels.rows};
          }
          WriteBytes((image_folder / name).string(), image.data);
          image_csv += name + "," +
                       FormatTimestampSeconds(image_stamps.last_stamp_ns()) +
                       "\n";
        }
      } else {
        const ImageMessage image = DecodeIn(
            context, [&] { return DecodeImage(encoding, message.data); });
        const int64_t stamp = image_stamps.Stamp(
            image.header.stamp_ns, message.log_time_ns, options.time);
        if (image_stamps.Use(stamp, options.time)) {
          const cv::Mat pixels = ImageMessageToMat(image, context);
          if (!image_size) {
            image_size = ImageSize{pixels.cols, pixels.rows};
          } else if (pixels.cols != image_size->width ||
                     pixels.rows != image_size->height) {
            throw FormatError(context + ": image at " +
                              std::to_string(image_stamps.last_stamp_ns()) +
                              " ns is " + std::to_string(pixels.cols) + " x " +
                              std::to_string(pixels.rows) + ", the first was " +
                              std::to_string(image_size->width) + " x " +
                              std::to_string(image_size->height));
          }
          const std::string name =
              std::to_string(image_stamps.last_stamp_ns()) + ".png";
          const std::string path = (image_folder / name).string();
          bool written = false;
          try {
            written = cv::imwrite(path, pixels);
          } catch (const cv::Exception& error) {
            throw FormatError(path + ": write failed: " + error.what());
          }
          if (!written) throw FormatError(path + ": write failed");
          image_csv += name + "," +
                       FormatTimestampSeconds(image_stamps.last_stamp_ns()) +
                       "\n";
        }
      }
    } else if (role == Role::kOdometry) {
      const std::string& context = odometry_stamps.context();
      if (wheels) {
        const JointStateMessage joints = DecodeIn(
            context, [&] { return DecodeJointState(encoding, message.data); });
        const int64_t stamp = odometry_stamps.Stamp(
            joints.header.stamp_ns, message.log_time_ns, options.time);
        // Messages without the wheels (other joints) do not take part in
        // the stamp checks.
        const std::optional<WheelTravelSample> sample =
            wheels->Sample(stamp, joints);
        if (sample && odometry_stamps.Use(stamp, options.time)) {
          wheels->Append(*sample);
        }
      } else {
        const OdometryMessage odometry = DecodeIn(
            context, [&] { return DecodeOdometry(encoding, message.data); });
        const int64_t stamp = odometry_stamps.Stamp(
            odometry.header.stamp_ns, message.log_time_ns, options.time);
        if (odometry_stamps.Use(stamp, options.time)) {
          poses.push_back({odometry_stamps.last_stamp_ns(),
                           PoseFromOdometry(odometry, context)});
        }
      }
    } else {
      const std::string& context = info_stamps.context();
      CameraInfoMessage info = DecodeIn(
          context, [&] { return DecodeCameraInfo(encoding, message.data); });
      // Only the first CameraInfo is used; its stamps are not checked.
      info_stamps.Stamp(
          info.header.stamp_ns, message.log_time_ns, BagTime::kReceive);
      if (!first_info) {
        first_info = std::move(info);
      } else if (!SameCalibration(*first_info, info)) {
        ++changed_infos;
      }
    }
    ++done;
    if (progress) progress(done, total);
  }

  summary.images = image_stamps.Finish();
  summary.odometry = odometry_stamps.Finish();
  if (summary.images.used == 0) {
    throw FormatError(image_stamps.context() + ": no image messages");
  }
  if (summary.odometry.messages == 0) {
    throw FormatError(odometry_stamps.context() + ": no odometry messages");
  }
  WriteText((output / "image_timestamps.csv").string(), image_csv);

  if (wheels) {
    const WheelTravels travels = wheels->Finish();
    summary.odometry_file = "wheels.csv";
    WriteWheelTravelCsv(travels, (output / summary.odometry_file).string());
    summary.left_wheel_joint = wheels->left_joint();
    summary.right_wheel_joint = wheels->right_joint();
    if (wheels->skipped() > 0) {
      summary.warnings.push_back(
          chosen.odometry + ": " + std::to_string(wheels->skipped()) +
          " joint states without both wheel joints were skipped");
    }
  } else {
    const Trajectory trajectory = OdometryTrajectory(
        std::move(poses), odometry_stamps.context(), options.planarity);
    summary.planar = trajectory.planar;
    summary.odometry_file = trajectory.planar ? "odometry.csv" : "odometry.tum";
    const std::string path = (output / summary.odometry_file).string();
    if (trajectory.planar) {
      WriteOdometryCsv(trajectory, path);
    } else {
      WriteTumTrajectory(trajectory, path);
    }
  }

  if (first_info) {
    summary.camera_info = info_stamps.Finish();
    const std::string& context = info_stamps.context();
    ColmapCamera camera = ColmapCameraFromCameraInfo(*first_info, context);
    CheckCameraInfoImageSize(*first_info,
                             static_cast<uint32_t>(image_size->width),
                             static_cast<uint32_t>(image_size->height),
                             context);
    WriteText((output / "camera.txt").string(),
              "# COLMAP camera from " + chosen.camera_info +
                  " (K and D of the unrectified images); principal point in "
                  "COLMAP's convention, top-left pixel centre at (0.5, 0.5): "
                  "cx = K[2] + 0.5, cy = K[5] + 0.5\n" +
                  ColmapCameraLine(camera) + "\n");
    summary.camera = std::move(camera);
    if (changed_infos > 0) {
      summary.warnings.push_back(
          chosen.camera_info + ": " + std::to_string(changed_infos) +
          " messages differ from the first CameraInfo, which was used");
    }
  }

  for (const TopicExtractionSummary* topic :
       {&summary.images, &summary.odometry}) {
    if (topic->duplicate_stamps > 0) {
      summary.warnings.push_back(
          topic->topic + ": " + std::to_string(topic->duplicate_stamps) +
          " messages repeat the previous " + BagTimeName(options.time) +
          " stamp and were skipped");
    }
  }
  // Header stamps far from the receive times, compared with the odometry's
  // sampling interval: then the choice of stamp matters to the calibration.
  if (summary.odometry.rate_hz > 0.0) {
    const double interval_s = 1.0 / summary.odometry.rate_hz;
    for (const TopicExtractionSummary* topic :
         {&summary.images, &summary.odometry}) {
      if (topic->mean_abs_header_minus_receive_s > interval_s) {
        summary.warnings.push_back(
            topic->topic + ": header stamps differ from the receive times by " +
            Milliseconds(topic->mean_abs_header_minus_receive_s) +
            " on average, more than the odometry interval (" +
            Milliseconds(interval_s) + "); " +
            (options.time == BagTime::kHeader
                 ? "header stamps are used (--bag_time header)"
                 : "receive times are used (--bag_time receive)") +
            ": check that this is the clock to trust");
      }
    }
  }
  return summary;
}

}  // namespace odomcal::bag
