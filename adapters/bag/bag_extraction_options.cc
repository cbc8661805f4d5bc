// BagExtractionOptions and the choice of topics (bag_extraction.h).
#include "odomcal/adapters/bag/bag_extraction.h"
#include "odomcal/adapters/colmap_cameras.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
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
  throw std::invalid_argument(
      "the bag has " + std::to_string(candidates.size()) + " " + what +
      " topics: " + TopicList(candidates) + "; pass " + flag +
      " to choose one" +
      (what == "image" ? " (several --image_topic: a rig, one camera each)"
                       : ""));
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

// Camera info is optional: empty topics do not count when choosing.
std::string ChooseCameraInfo(const std::vector<BagTopic>& topics,
                             const BagExtractionOptions& options,
                             const ChosenCamera& camera) {
  std::vector<BagTopic> infos;
  for (const BagTopic& topic : topics) {
    if (topic.type == kCameraInfoType &&
        (topic.message_count > 0 || !options.camera_info_topic.empty())) {
      infos.push_back(topic);
    }
  }
  const std::string beside = CameraInfoBeside(camera);
  if (options.camera_info_topic.empty() && infos.size() > 1) {
    for (const BagTopic& info : infos) {
      if (info.topic == beside) return info.topic;
    }
  }
  const BagTopic* info =
      ChooseOne(options.camera_info_topic.empty() ? infos : topics,
                {kCameraInfoType},
                "--camera_info_topic",
                options.camera_info_topic,
                "camera info",
                false);
  return info == nullptr ? std::string() : info->topic;
}

// A rig camera's name from its image topic: its namespace, or the topic
// itself when it has none.
std::string RigCameraName(const ChosenCamera& camera) {
  std::string name = CameraNamespace(camera.image, camera.image_compressed);
  if (name.empty()) name = camera.image;
  while (!name.empty() && name.front() == '/') name.erase(0, 1);
  return CameraNameFromText(name);
}

std::vector<ChosenCamera> ChooseRigCameras(
    const std::vector<BagTopic>& topics, const BagExtractionOptions& options) {
  if (!options.camera_info_topic.empty()) {
    throw std::invalid_argument(
        "--camera_info_topic " + options.camera_info_topic +
        " names one camera's CameraInfo; a rig's cameras take theirs beside "
        "their image topics (<namespace>/camera_info)");
  }
  // (given name or "", topic)
  std::vector<std::pair<std::string, const BagTopic*>> images;
  if (options.image_topics.empty()) {
    for (const BagTopic* image :
         TopicsOfTypes(topics, {kImageType, kCompressedImageType})) {
      if (image->message_count > 0) images.emplace_back("", image);
    }
    if (images.empty()) {
      throw std::invalid_argument(
          "--rig: the bag has no image topic with messages (" +
          TypesText({kImageType, kCompressedImageType}) +
          "); its topics: " + TopicList(AllTopics(topics)));
    }
  }
  for (const std::string& given : options.image_topics) {
    const size_t equals = given.find('=');
    const std::string name =
        equals == std::string::npos ? "" : given.substr(0, equals);
    const std::string topic =
        equals == std::string::npos ? given : given.substr(equals + 1);
    if (equals != std::string::npos &&
        (name.empty() || CameraNameFromText(name) != name)) {
      throw std::invalid_argument(
          "--image_topic '" + given +
          "': a camera name is 1-100 characters of A-Z a-z 0-9 _ - .");
    }
    for (const auto& [other_name, other] : images) {
      if (other->topic == topic) {
        throw std::invalid_argument("--image_topic " + topic +
                                    " is given twice");
      }
    }
    images.emplace_back(name,
                        ChooseOne(topics,
                                  {kImageType, kCompressedImageType},
                                  "--image_topic",
                                  topic,
                                  "image",
                                  true));
  }
  std::map<std::string, ChosenCamera> cameras;
  for (const auto& [given_name, image] : images) {
    ChosenCamera camera;
    camera.image = image->topic;
    camera.image_compressed = image->type == kCompressedImageType;
    camera.name = given_name.empty() ? RigCameraName(camera) : given_name;
    const auto [it, added] = cameras.emplace(camera.name, camera);
    if (!added) {
      throw std::invalid_argument(
          "image topics " + it->second.image + " and " + camera.image +
          " both make camera '" + camera.name + "' (" +
          (given_name.empty() ? "a camera is named by its topic's namespace"
                              : "named by --image_topic NAME=TOPIC") +
          "): give one of them, or name each with --image_topic NAME=TOPIC");
    }
    // Only the CameraInfo beside the images: a lone CameraInfo of another
    // namespace is no rig camera's.
    const std::string beside = CameraInfoBeside(camera);
    for (const BagTopic& topic : topics) {
      if (topic.topic == beside && topic.type == kCameraInfoType &&
          topic.message_count > 0) {
        it->second.camera_info = beside;
      }
    }
  }
  std::vector<ChosenCamera> chosen;
  std::map<std::string, std::string> image_of_info;
  for (auto& [name, camera] : cameras) {
    if (!camera.camera_info.empty()) {
      const auto [it, added] =
          image_of_info.emplace(camera.camera_info, camera.image);
      if (!added) {
        throw std::invalid_argument(
            "image topics " + it->second + " and " + camera.image +
            " share the CameraInfo " + camera.camera_info +
            ": they are one camera's; give one of them");
      }
    }
    chosen.push_back(std::move(camera));
  }
  return chosen;
}

}  // namespace

std::string CameraInfoBeside(const ChosenCamera& camera) {
  return CameraNamespace(camera.image, camera.image_compressed) +
         "/camera_info";
}

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
  chosen.rig = options.IsRig();
  if (chosen.rig) {
    chosen.cameras = ChooseRigCameras(topics, options);
  } else {
    const std::string given =
        options.image_topics.empty() ? "" : options.image_topics.front();
    if (given.find('=') != std::string::npos) {
      throw std::invalid_argument(
          "--image_topic " + given +
          ": NAME=TOPIC names a camera of a rig (several --image_topic, or "
          "--rig); one camera takes the topic alone");
    }
    ChosenCamera camera;
    const BagTopic* image = ChooseOne(topics,
                                      {kImageType, kCompressedImageType},
                                      "--image_topic",
                                      given,
                                      "image",
                                      true);
    camera.image = image->topic;
    camera.image_compressed = image->type == kCompressedImageType;
    camera.camera_info = ChooseCameraInfo(topics, options, camera);
    chosen.cameras.push_back(camera);
  }

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
  return chosen;
}

}  // namespace odomcal::bag
