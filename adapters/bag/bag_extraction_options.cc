// BagExtractionOptions and the choice of topics (bag_extraction.h).
#include "odomcal/adapters/bag/bag_extraction.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal::bag {
namespace {

constexpr const char* kImageType = "sensor_msgs/Image";
constexpr const char* kCompressedImageType = "sensor_msgs/CompressedImage";
constexpr const char* kOdometryType = "nav_msgs/Odometry";
constexpr const char* kJointStateType = "sensor_msgs/JointState";
constexpr const char* kCameraInfoType = "sensor_msgs/CameraInfo";

std::string TopicList(const std::vector<const BagTopic*>& topics) {
  std::string text;
  for (const BagTopic* topic : topics) {
    if (!text.empty()) text += ", ";
    text += topic->topic + " (" + topic->type + ", " +
            std::to_string(topic->message_count) + " messages)";
  }
  return text.empty() ? "none" : text;
}

std::vector<const BagTopic*> TopicsOfTypes(
    const std::vector<BagTopic>& topics,
    const std::vector<std::string>& types) {
  std::vector<const BagTopic*> found;
  for (const BagTopic& topic : topics) {
    for (const std::string& type : types) {
      if (topic.type == type) found.push_back(&topic);
    }
  }
  return found;
}

std::vector<const BagTopic*> AllTopics(const std::vector<BagTopic>& topics) {
  std::vector<const BagTopic*> all;
  all.reserve(topics.size());
  for (const BagTopic& topic : topics) all.push_back(&topic);
  return all;
}

std::string TypesText(const std::vector<std::string>& types) {
  std::string text;
  for (size_t i = 0; i < types.size(); ++i) {
    if (i > 0) text += i + 1 == types.size() ? " or " : ", ";
    text += types[i];
  }
  return text;
}

void CheckHasMessages(const BagTopic& topic) {
  if (topic.message_count <= 0) {
    throw std::invalid_argument("topic " + topic.topic + " (" + topic.type +
                                ") has no messages in the bag");
  }
}

// The topic named by `flag_value` (checked), or the only one of `types`;
// nullptr when there is none and `required` is false.
const BagTopic* ChooseOne(const std::vector<BagTopic>& topics,
                          const std::vector<std::string>& types,
                          const std::string& flag,
                          const std::string& flag_value,
                          const std::string& what,
                          bool required) {
  const std::vector<const BagTopic*> candidates = TopicsOfTypes(topics, types);
  if (!flag_value.empty()) {
    for (const BagTopic& topic : topics) {
      if (topic.topic != flag_value) continue;
      for (const std::string& type : types) {
        if (topic.type == type) {
          CheckHasMessages(topic);
          return &topic;
        }
      }
      throw std::invalid_argument(flag + " " + flag_value + " is a " +
                                  topic.type + " topic, not " +
                                  TypesText(types));
    }
    throw std::invalid_argument(flag + " " + flag_value +
                                " is not in the bag; " + what +
                                " topics: " + TopicList(candidates));
  }
  if (candidates.size() == 1) {
    CheckHasMessages(*candidates.front());
    return candidates.front();
  }
  if (candidates.empty()) {
    if (!required) return nullptr;
    throw std::invalid_argument(
        "the bag has no " + what + " topic (" + TypesText(types) +
        "); its topics: " + TopicList(AllTopics(topics)));
  }
  throw std::invalid_argument("the bag has " +
                              std::to_string(candidates.size()) + " " + what +
                              " topics: " + TopicList(candidates) + "; pass " +
                              flag + " to choose one");
}

// "/cam/image_raw" -> "/cam"; "/cam/image_raw/compressed" -> "/cam".
std::string CameraNamespace(const std::string& image_topic, bool compressed) {
  std::string name = image_topic;
  const std::string suffix = "/compressed";
  if (compressed && name.size() > suffix.size() &&
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
    name.resize(name.size() - suffix.size());
  }
  const size_t slash = name.rfind('/');
  return slash == std::string::npos ? std::string() : name.substr(0, slash);
}

}  // namespace

BagTime ParseBagTime(const std::string& name) {
  if (name == "header") return BagTime::kHeader;
  if (name == "receive") return BagTime::kReceive;
  throw std::invalid_argument(
      "--bag_time must be 'header' (header.stamp) or "
      "'receive' (when the recorder got the "
      "message), got '" +
      name + "'");
}

const char* BagTimeName(BagTime time) {
  return time == BagTime::kHeader ? "header" : "receive";
}

void BagExtractionOptions::Check() const {
  if (output_folder.empty()) {
    throw std::invalid_argument(
        "--output: the folder to extract into is "
        "missing");
  }
  const auto check_length = [](double value, const char* flag) {
    if (!std::isfinite(value) || value < 0.0) {
      throw std::invalid_argument(std::string(flag) +
                                  " must be a non-negative number of metres, "
                                  "got " +
                                  std::to_string(value));
    }
  };
  check_length(wheel_radius_m, "--wheel_radius_m");
  check_length(wheel_track_m, "--wheel_track_m");
  if (!std::isfinite(planarity.max_z_range_m) || planarity.max_z_range_m < 0 ||
      !std::isfinite(planarity.max_tilt_rad) || planarity.max_tilt_rad < 0) {
    throw std::invalid_argument(
        "planarity tolerances must be non-negative "
        "and finite");
  }
  if (left_wheel_joint.empty() != right_wheel_joint.empty()) {
    throw std::invalid_argument(
        "--left_wheel_joint and --right_wheel_joint "
        "go together: pass both or neither");
  }
  if (!odometry_topic.empty() && !joint_state_topic.empty()) {
    throw std::invalid_argument(
        "--odometry_topic and --joint_state_topic "
        "both given: the calibration takes one "
        "odometry source");
  }
}

ChosenTopics ChooseTopics(const std::vector<BagTopic>& topics,
                          const BagExtractionOptions& options) {
  ChosenTopics chosen;
  const BagTopic* image = ChooseOne(topics,
                                    {kImageType, kCompressedImageType},
                                    "--image_topic",
                                    options.image_topic,
                                    "image",
                                    true);
  chosen.image = image->topic;
  chosen.image_compressed = image->type == kCompressedImageType;

  const BagTopic* odometry = nullptr;
  if (!options.joint_state_topic.empty()) {
    odometry = ChooseOne(topics,
                         {kJointStateType},
                         "--joint_state_topic",
                         options.joint_state_topic,
                         "joint state",
                         true);
  } else if (!options.odometry_topic.empty() ||
             !TopicsOfTypes(topics, {kOdometryType}).empty()) {
    odometry = ChooseOne(topics,
                         {kOdometryType},
                         "--odometry_topic",
                         options.odometry_topic,
                         "odometry",
                         true);
  } else if (!TopicsOfTypes(topics, {kJointStateType}).empty()) {
    odometry = ChooseOne(topics,
                         {kJointStateType},
                         "--joint_state_topic",
                         "",
                         "joint state",
                         true);
  } else {
    throw std::invalid_argument(
        "the bag has no odometry topic (nav_msgs/Odometry or "
        "sensor_msgs/JointState); its topics: " +
        TopicList(AllTopics(topics)));
  }
  chosen.odometry = odometry->topic;
  chosen.odometry_joint_state = odometry->type == kJointStateType;

  // Camera info is optional: empty topics do not count when choosing.
  std::vector<BagTopic> infos;
  for (const BagTopic& topic : topics) {
    if (topic.type == kCameraInfoType &&
        (topic.message_count > 0 || !options.camera_info_topic.empty())) {
      infos.push_back(topic);
    }
  }
  if (options.camera_info_topic.empty() && infos.size() > 1) {
    const std::string beside =
        CameraNamespace(chosen.image, chosen.image_compressed) + "/camera_info";
    for (const BagTopic& info : infos) {
      if (info.topic == beside) {
        chosen.camera_info = info.topic;
        return chosen;
      }
    }
  }
  const BagTopic* info =
      ChooseOne(options.camera_info_topic.empty() ? infos : topics,
                {kCameraInfoType},
                "--camera_info_topic",
                options.camera_info_topic,
                "camera info",
                false);
  if (info != nullptr) chosen.camera_info = info->topic;
  return chosen;
}

}  // namespace odomcal::bag
