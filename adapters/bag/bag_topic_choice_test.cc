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
  EXPECT_EQ(chosen.cameras[0].image, "/cam/image_raw");
  EXPECT_FALSE(chosen.cameras[0].image_compressed);
  // Odometry is preferred over joint states.
  EXPECT_EQ(chosen.odometry, "/odom");
  EXPECT_FALSE(chosen.odometry_joint_state);
  EXPECT_EQ(chosen.cameras[0].camera_info, "/cam/camera_info");
}

TEST(BagTopicChoiceTest, JointStatesWithoutOdometry) {
  std::vector<BagTopic> topics = kRobot;
  topics.erase(topics.begin() + 3);  // /odom
  topics.erase(topics.begin() + 2);  // camera info is optional
  const ChosenTopics chosen = ChooseTopics(topics, {});
  EXPECT_EQ(chosen.odometry, "/joint_states");
  EXPECT_TRUE(chosen.odometry_joint_state);
  EXPECT_EQ(chosen.cameras[0].camera_info, "");

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
  options.image_topics = {"/cam/image_raw/compressed"};
  error = InvalidArgumentOf([&] { ChooseTopics(topics, options); });
  EXPECT_TRUE(Contains(error, "--odometry_topic")) << error;
  EXPECT_TRUE(Contains(error, "/odometry/filtered (nav_msgs/Odometry, 900"))
      << error;

  options.odometry_topic = "/odometry/filtered";
  const ChosenTopics chosen = ChooseTopics(topics, options);
  EXPECT_TRUE(chosen.cameras[0].image_compressed);
  EXPECT_EQ(chosen.odometry, "/odometry/filtered");
  EXPECT_EQ(chosen.cameras[0].camera_info, "/cam/camera_info");
}

TEST(BagTopicChoiceTest, CameraInfoBesideTheImages) {
  std::vector<BagTopic> topics = kRobot;
  topics.push_back(Topic("/left/image_raw", "sensor_msgs/Image"));
  topics.push_back(Topic("/left/camera_info", "sensor_msgs/CameraInfo"));
  BagExtractionOptions options;
  options.image_topics = {"/left/image_raw"};
  EXPECT_EQ(ChooseTopics(topics, options).cameras[0].camera_info,
            "/left/camera_info");
  // No image namespace to go by: ambiguous.
  topics.push_back(Topic("/image", "sensor_msgs/Image"));
  options.image_topics = {"/image"};
  const std::string error =
      InvalidArgumentOf([&] { ChooseTopics(topics, options); });
  EXPECT_TRUE(Contains(error, "--camera_info_topic")) << error;
}

TEST(BagTopicChoiceTest, GivenTopicsAreChecked) {
  BagExtractionOptions options;
  options.image_topics = {"/cam/image_rect"};
  std::string error = InvalidArgumentOf([&] { ChooseTopics(kRobot, options); });
  EXPECT_TRUE(
      Contains(error, "--image_topic /cam/image_rect is not in the bag"))
      << error;
  EXPECT_TRUE(Contains(error, "/cam/image_raw")) << error;

  options.image_topics = {"/odom"};
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

// Several image topics: a rig, each camera named by its topic's namespace
// and paired with the CameraInfo beside it, in name order.
TEST(BagTopicChoiceTest, RigCamerasAreNamedByTheirNamespaces) {
  const std::vector<BagTopic> topics = {
      Topic("/right/image_raw/compressed", "sensor_msgs/CompressedImage"),
      Topic("/right/camera_info", "sensor_msgs/CameraInfo"),
      Topic("/left/image_raw", "sensor_msgs/Image"),
      Topic("/left/camera_info", "sensor_msgs/CameraInfo"),
      Topic("/stereo/mid cam/image_raw", "sensor_msgs/Image"),
      Topic("/image", "sensor_msgs/Image"),
      Topic("/camera_info", "sensor_msgs/CameraInfo", 0),
      Topic("/odom", "nav_msgs/Odometry"),
  };
  BagExtractionOptions options;
  options.image_topics = {"/right/image_raw/compressed",
                          "/left/image_raw",
                          "/stereo/mid cam/image_raw",
                          "/image"};
  const ChosenTopics chosen = ChooseTopics(topics, options);
  EXPECT_TRUE(chosen.rig);
  EXPECT_EQ(chosen.odometry, "/odom");
  ASSERT_EQ(chosen.cameras.size(), 4u);
  EXPECT_EQ(chosen.cameras[0].name, "image");
  EXPECT_EQ(chosen.cameras[0].camera_info, "");  // /camera_info is empty
  EXPECT_EQ(chosen.cameras[1].name, "left");
  EXPECT_EQ(chosen.cameras[1].image, "/left/image_raw");
  EXPECT_EQ(chosen.cameras[1].camera_info, "/left/camera_info");
  EXPECT_EQ(chosen.cameras[2].name, "right");
  EXPECT_TRUE(chosen.cameras[2].image_compressed);
  EXPECT_EQ(chosen.cameras[2].camera_info, "/right/camera_info");
  EXPECT_EQ(chosen.cameras[3].name, "stereo_mid_cam");
  EXPECT_EQ(chosen.cameras[3].camera_info, "");

  // NAME=TOPIC names a camera.
  options.image_topics = {"front=/left/image_raw",
                          "/right/image_raw/compressed"};
  const ChosenTopics named = ChooseTopics(topics, options);
  ASSERT_EQ(named.cameras.size(), 2u);
  EXPECT_EQ(named.cameras[0].name, "front");
  EXPECT_EQ(named.cameras[0].camera_info, "/left/camera_info");
  EXPECT_EQ(named.cameras[1].name, "right");

  // --rig without topics: every image topic with messages; one with it: a
  // rig of that camera.
  BagExtractionOptions every;
  every.rig = true;
  EXPECT_EQ(ChooseTopics(topics, every).cameras.size(), 4u);
  every.image_topics = {"/left/image_raw"};
  const ChosenTopics one = ChooseTopics(topics, every);
  ASSERT_EQ(one.cameras.size(), 1u);
  EXPECT_TRUE(one.rig);
  EXPECT_EQ(one.cameras[0].name, "left");
}

TEST(BagTopicChoiceTest, RigTopicErrorsNameTheTopics) {
  std::vector<BagTopic> topics = {
      Topic("/left/image_raw", "sensor_msgs/Image"),
      Topic("/left/image_raw/compressed", "sensor_msgs/CompressedImage"),
      Topic("/left/camera_info", "sensor_msgs/CameraInfo"),
      Topic("/right/image_raw", "sensor_msgs/Image"),
      Topic("/odom", "nav_msgs/Odometry"),
  };
  const auto error_of = [&](const std::vector<std::string>& image_topics,
                            bool rig = false) {
    BagExtractionOptions options;
    options.image_topics = image_topics;
    options.rig = rig;
    return InvalidArgumentOf([&] { ChooseTopics(topics, options); });
  };
  EXPECT_EQ(error_of({"/left/image_raw", "/rear/image_raw"}),
            "--image_topic /rear/image_raw is not in the bag; image topics: "
            "/left/image_raw (sensor_msgs/Image, 100 messages), "
            "/left/image_raw/compressed (sensor_msgs/CompressedImage, 100 "
            "messages), /right/image_raw (sensor_msgs/Image, 100 messages)");
  EXPECT_EQ(error_of({"/left/image_raw", "/left/image_raw"}),
            "--image_topic /left/image_raw is given twice");
  EXPECT_EQ(error_of({"/left/image_raw", "/left/image_raw/compressed"}),
            "image topics /left/image_raw and /left/image_raw/compressed both "
            "make camera 'left' (a camera is named by its topic's namespace): "
            "give one of them, or name each with --image_topic NAME=TOPIC");
  // Every image topic: the same two.
  EXPECT_TRUE(Contains(error_of({}, true), "both make camera 'left'"));
  EXPECT_EQ(error_of({"a=/left/image_raw", "a=/right/image_raw"}),
            "image topics /left/image_raw and /right/image_raw both make "
            "camera 'a' (named by --image_topic NAME=TOPIC): give one of "
            "them, or name each with --image_topic NAME=TOPIC");
  EXPECT_EQ(error_of({"raw=/left/image_raw",
                      "compressed=/left/image_raw/compressed"}),
            "image topics /left/image_raw/compressed and /left/image_raw "
            "share the CameraInfo /left/camera_info: they are one camera's; "
            "give one of them");
  EXPECT_EQ(error_of({"front cam=/left/image_raw", "/right/image_raw"}),
            "--image_topic 'front cam=/left/image_raw': a camera name is "
            "1-100 characters of A-Z a-z 0-9 _ - .");
  EXPECT_EQ(error_of({"=/left/image_raw", "/right/image_raw"}),
            "--image_topic '=/left/image_raw': a camera name is 1-100 "
            "characters of A-Z a-z 0-9 _ - .");
  EXPECT_TRUE(Contains(error_of({"front=/left/image_raw"}),
                       "NAME=TOPIC names a camera of a rig"));
  BagExtractionOptions options;
  options.image_topics = {"/left/image_raw", "/right/image_raw"};
  options.camera_info_topic = "/left/camera_info";
  EXPECT_TRUE(
      Contains(InvalidArgumentOf([&] { ChooseTopics(topics, options); }),
               "--camera_info_topic /left/camera_info names one "
               "camera's CameraInfo"));
  topics = {Topic("/odom", "nav_msgs/Odometry"),
            Topic("/cam/image_raw", "sensor_msgs/Image", 0)};
  EXPECT_TRUE(Contains(error_of({}, true),
                       "--rig: the bag has no image topic with messages"));
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
