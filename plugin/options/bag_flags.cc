#include "odomcal/plugin/options/bag_flags.h"

#include <string>

namespace odomcal {

using BagOptions = bag::BagExtractionOptions;

const OptionTable<BagOptions>& BagTopicFlags() {
  static const OptionTable<BagOptions> table = {
      // Echoed as given: "" (chosen), the topic, or the list of a rig's.
      RepeatedRow<BagOptions>(
          "image_topic",
          "sensor_msgs/Image or CompressedImage topic (default: the only "
          "one); repeated: a rig, one camera per topic (NAME=TOPIC names "
          "one; default: by its namespace)",
          [](BagOptions* o, const std::string& topic) {
            o->image_topics.push_back(topic);
          },
          [](const BagOptions& o) {
            if (o.image_topics.size() > 1)
              return nlohmann::json(o.image_topics);
            return nlohmann::json(
                o.image_topics.empty() ? "" : o.image_topics.front());
          }),
      NumberRow<BagOptions>(
          "odometry_topic",
          "nav_msgs/Odometry topic (default: the only one)",
          [](auto& o) -> auto& { return o.odometry_topic; }),
      NumberRow<BagOptions>(
          "joint_states_topic",
          "sensor_msgs/JointState topic of the wheels, instead of odometry "
          "(default: the only one, when the bag has no Odometry)",
          [](auto& o) -> auto& { return o.joint_state_topic; }),
      NumberRow<BagOptions>(
          "camera_info_topic",
          "sensor_msgs/CameraInfo topic: the intrinsics, held fixed "
          "(default: the only one, or the one beside the image topic)",
          [](auto& o) -> auto& { return o.camera_info_topic; }),
      ChoiceRow<BagOptions>(
          "bag_time",
          "header: each message's header.stamp (the capture time); "
          "receive: when the recorder received it",
          {"header", "receive"},
          [](const BagOptions& o) {
            return std::string(bag::BagTimeName(o.time));
          },
          [](BagOptions* o, const std::string& name) {
            o->time = bag::ParseBagTime(name);
          }),
      NumberRow<BagOptions>(
          "wheel_radius_m",
          "JointState wheels: the wheel radius; travel = joint angle (rad) * "
          "radius",
          [](auto& o) -> auto& { return o.wheel_radius_m; },
          FlagCheck::AtLeast(0.0)),
      NumberRow<BagOptions>(
          "left_wheel_joint",
          "JointState wheels: the left wheel's joint (default: the one "
          "named left)",
          [](auto& o) -> auto& { return o.left_wheel_joint; }),
      NumberRow<BagOptions>(
          "right_wheel_joint",
          "JointState wheels: the right wheel's joint (default: the one "
          "named right)",
          [](auto& o) -> auto& { return o.right_wheel_joint; }),
  };
  return table;
}

}  // namespace odomcal
