#include "odomcal/adapters/bag/bag_extraction.h"
#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal::bag {
namespace {

BagTopic Topic(const std::string& name,
               const std::string& type,
               int64_t count = 100) {
  BagTopic topic;
  topic.topic = name;
  topic.type = type;
  topic.message_count = count;
  return topic;
}

std::string InvalidArgumentOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  ADD_FAILURE() << "no std::invalid_argument thrown";
  return "";
}

const std::vector<BagTopic> kRobot = {
    Topic("/tf", "tf2_msgs/TFMessage"),
    Topic("/cam/image_raw", "sensor_msgs/Image", 300),
    Topic("/cam/camera_info", "sensor_msgs/CameraInfo", 300),
    Topic("/odom", "nav_msgs/Odometry", 1500),
    Topic("/joint_states", "sensor_msgs/JointState", 1500),
};

TEST(BagTopicChoiceTest, OneTopicOfEachKindIsChosen) {
  const ChosenTopics chosen = ChooseTopics(kRobot, {});
  EXPECT_EQ(chosen.image, "/cam/image_raw");
  EXPECT_FALSE(chosen.image_compressed);
  // Odometry is preferred over joint states.
  EXPECT_EQ(chosen.odometry, "/odom");
  EXPECT_FALSE(chosen.odometry_joint_state);
  EXPECT_EQ(chosen.camera_info, "/cam/camera_info");
}

TEST(BagTopicChoiceTest, JointStatesWithoutOdometry) {
  std::vector<BagTopic> topics = kRobot;
  topics.erase(topics.begin() + 3);  // /odom
  topics.erase(topics.begin() + 2);  // camera info is optional
  const ChosenTopics chosen = ChooseTopics(topics, {});
  EXPECT_EQ(chosen.odometry, "/joint_states");
  EXPECT_TRUE(chosen.odometry_joint_state);
  EXPECT_EQ(chosen.camera_info, "");

  BagExtractionOptions options;
  options.joint_state_topic = "/joint_states";
  EXPECT_TRUE(ChooseTopics(kRobot, options).odometry_joint_state);
}

TEST(BagTopicChoiceTest, SeveralCandidatesNameTheFlag) {
  std::vector<BagTopic> topics = kRobot;
  topics.push_back(
      Topic("/cam/image_raw/compressed", "sensor_msgs/CompressedImage", 298));
  topics.push_back(Topic("/odometry/filtered", "nav_msgs/Odometry", 900));
  std::string error = InvalidArgumentOf([&] { ChooseTopics(topics, {}); });
  EXPECT_TRUE(Contains(error, "--image_topic")) << error;
  EXPECT_TRUE(
      Contains(error, "/cam/image_raw (sensor_msgs/Image, 300 messages)"))
      << error;
  EXPECT_TRUE(Contains(
      error, "/cam/image_raw/compressed (sensor_msgs/CompressedImage, 298"))
      << error;

  BagExtractionOptions options;
  options.image_topic = "/cam/image_raw/compressed";
  error = InvalidArgumentOf([&] { ChooseTopics(topics, options); });
  EXPECT_TRUE(Contains(error, "--odometry_topic")) << error;
  EXPECT_TRUE(Contains(error, "/odometry/filtered (nav_msgs/Odometry, 900"))
      << error;

  options.odometry_topic = "/odometry/filtered";
  const ChosenTopics chosen = ChooseTopics(topics, options);
  EXPECT_TRUE(chosen.image_compressed);
  EXPECT_EQ(chosen.odometry, "/odometry/filtered");
  EXPECT_EQ(chosen.camera_info, "/cam/camera_info");
}

TEST(BagTopicChoiceTest, CameraInfoBesideTheImages) {
  std::vector<BagTopic> topics = kRobot;
  topics.push_back(Topic("/left/image_raw", "sensor_msgs/Image"));
  topics.push_back(Topic("/left/camera_info", "sensor_msgs/CameraInfo"));
  BagExtractionOptions options;
  options.image_topic = "/left/image_raw";
  EXPECT_EQ(ChooseTopics(topics, options).camera_info, "/left/camera_info");
  // No image namespace to go by: ambiguous.
  topics.push_back(Topic("/image", "sensor_msgs/Image"));
  options.image_topic = "/image";
  const std::string error =
      InvalidArgumentOf([&] { ChooseTopics(topics, options); });
  EXPECT_TRUE(Contains(error, "--camera_info_topic")) << error;
}

TEST(BagTopicChoiceTest, GivenTopicsAreChecked) {
  BagExtractionOptions options;
  options.image_topic = "/cam/image_rect";
  std::string error = InvalidArgumentOf([&] { ChooseTopics(kRobot, options); });
  EXPECT_TRUE(
      Contains(error, "--image_topic /cam/image_rect is not in the bag"))
      << error;
  EXPECT_TRUE(Contains(error, "/cam/image_raw")) << error;

  options.image_topic = "/odom";
  error = InvalidArgumentOf([&] { ChooseTopics(kRobot, options); });
  EXPECT_TRUE(Contains(error, "nav_msgs/Odometry topic")) << error;

  std::vector<BagTopic> topics = kRobot;
  topics[1].message_count = 0;
  error = InvalidArgumentOf([&] { ChooseTopics(topics, {}); });
  EXPECT_TRUE(Contains(error, "/cam/image_raw")) << error;
  EXPECT_TRUE(Contains(error, "no messages")) << error;

  error = InvalidArgumentOf([&] {
    ChooseTopics({Topic("/cam/image_raw", "sensor_msgs/Image")}, {});
  });
  EXPECT_TRUE(Contains(error, "no odometry topic")) << error;
}

TEST(BagTopicChoiceTest, OptionsCheck) {
  BagExtractionOptions options;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options.output_folder = "out";
  options.Check();
  options.left_wheel_joint = "l";
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options.right_wheel_joint = "r";
  options.Check();
  options.wheel_radius_m = -0.1;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options.wheel_radius_m = 0.1;
  options.odometry_topic = "/odom";
  options.joint_state_topic = "/joint_states";
  EXPECT_THROW(options.Check(), std::invalid_argument);
  EXPECT_EQ(ParseBagTime("receive"), BagTime::kReceive);
  EXPECT_THROW(ParseBagTime("log"), std::invalid_argument);
}

}  // namespace
}  // namespace odomcal::bag
