// A robot's bag -> the folder of inputs odomcal calibrates from:
//
//   <output>/images/<stamp_ns>.png|.jpg  one file per image message, named by
//                                        its stamp in integer ns (the header
//                                        stamp by default), e.g.
//                                        1690000000123456789.png; a rig's
//                                        in images/<camera>/ (COLMAP's rig
//                                        layout)
//   <output>/image_timestamps.csv        image_name,timestamp (names relative
//                                        to images/, as COLMAP names them;
//                                        exact decimal seconds;
//                                        image_timestamps.h)
//   <output>/odometry.csv                timestamp,x,y,yaw  for a planar
//                                        nav_msgs/Odometry log, or
//   <output>/odometry.tum                TUM (timestamp tx ty tz qx qy qz qw,
//                                        origin_from_odom) for an SE(3) one,
//                                        or
//   <output>/wheels.csv                  timestamp,left_m,right_m from
//                                        sensor_msgs/JointState wheel angles
//   <output>/camera.txt                  one COLMAP cameras.txt line from
//                                        sensor_msgs/CameraInfo, when the bag
//                                        has one (camera_info_conversion.h:
//                                        COLMAP's pixel centre, cx + 0.5),
//                                        after '#' lines: the convention and
//                                        odomcal run's --camera_model and
//                                        --camera_params; a rig's
//   <output>/cameras.txt                 one line per camera with a
//                                        CameraInfo (camera_id k + 1 for the
//                                        k-th camera), each after a '#' line
//                                        naming the camera and its flags
//
// Raw images are stored as lossless PNG (image_conversion.h), compressed
// ones with their original bytes. Time is integer nanoseconds throughout;
// which stamp (header.stamp, the capture time, or the recorder's receive
// time) is BagExtractionOptions::time. The bag is streamed once; only one
// image is in memory at a time.
//
// Errors: bad options and topic choices throw std::invalid_argument (one
// line naming the flag); problems with the bag's content or the output
// folder throw FormatError starting with the bag path and topic (or the
// output path). Nothing is printed.
#pragma once

#include "odomcal/adapters/bag/bag_reader.h"
#include "odomcal/adapters/bag/odometry_conversion.h"
#include "odomcal/adapters/colmap_model.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace odomcal::bag {

// Which time stamps a message: its header.stamp (when the sensor captured
// it) or when the recorder received it (BagMessage::log_time_ns).
enum class BagTime { kHeader, kReceive };

// "header" or "receive"; std::invalid_argument otherwise.
BagTime ParseBagTime(const std::string& name);
const char* BagTimeName(BagTime time);

struct BagExtractionOptions {
  // Empty: chosen automatically (ChooseTopics). Several: the cameras of a
  // rig, each given as TOPIC or NAME=TOPIC.
  std::vector<std::string> image_topics;  // --image_topic, repeatable
  // A rig even with fewer than two image_topics: none given, every image
  // topic of the bag is a camera.
  bool rig = false;                 // run --bag --rig
  std::string odometry_topic;       // --odometry_topic (nav_msgs/Odometry)
  std::string joint_state_topic;    // --joint_state_topic
  std::string camera_info_topic;    // --camera_info_topic
  BagTime time = BagTime::kHeader;  // --bag_time
  // Joint states only: wheel joint positions are angles in rad, travel =
  // angle * wheel_radius_m. Joints named, or found by "left"/"right".
  double wheel_radius_m = 0.0;    // --wheel_radius_m
  std::string left_wheel_joint;   // --left_wheel_joint
  std::string right_wheel_joint;  // --right_wheel_joint
  // The nominal track the calibration integrates wheels.csv with; optional
  // here (0: not given), reported in the summary.
  double wheel_track_m = 0.0;  // --wheel_track_m
  PlanarityTolerance planarity;
  // Created when missing; must be empty when it exists.
  std::string output_folder;  // --output

  // Several image topics, or `rig`.
  bool IsRig() const { return rig || image_topics.size() > 1; }

  // std::invalid_argument naming the flag: no output folder, a negative or
  // non-finite radius, track or tolerance, one wheel joint without the
  // other, both --odometry_topic and --joint_state_topic.
  void Check() const;
};

struct ChosenCamera {
  // A rig's camera name (its images in images/<name>/); "" for one camera.
  std::string name;
  std::string image;
  bool image_compressed = false;  // sensor_msgs/CompressedImage
  std::string camera_info;        // empty: none
};

struct ChosenTopics {
  std::vector<ChosenCamera> cameras;  // one, or a rig's in name order
  bool rig = false;
  std::string odometry;
  bool odometry_joint_state = false;  // sensor_msgs/JointState
};

// The topics to extract. A topic given in the options must exist with a
// fitting type and messages. Otherwise the one topic of its kind is taken:
// images sensor_msgs/Image or sensor_msgs/CompressedImage; odometry
// nav_msgs/Odometry, else sensor_msgs/JointState; camera info
// sensor_msgs/CameraInfo (optional; with several, the one beside the image
// topic, "<namespace>/camera_info"). No candidate, or several, throws
// std::invalid_argument listing the candidates with their types and counts
// and naming the flag to pass. A chosen topic without messages is an error.
//
// A rig (options.IsRig()): the image topics given, or every image topic
// with messages. Each is a camera named NAME when given as NAME=TOPIC, else
// by its namespace ("/left/image_raw" -> "left", "/stereo/left/image_raw"
// -> "stereo_left"; a topic without one by its own name), characters other
// than A-Z a-z 0-9 _ - . becoming '_'. Its camera info is
// "<namespace>/camera_info" when the bag has it with messages, else none
// (--camera_info_topic names one camera's and is refused). Throws
// std::invalid_argument naming the topics for a topic given twice, two
// cameras of one name, a NAME that is no camera name, NAME=TOPIC without a
// rig.
ChosenTopics ChooseTopics(const std::vector<BagTopic>& topics,
                          const BagExtractionOptions& options);

// "<namespace>/camera_info": the CameraInfo topic beside an image topic
// ("/cam/image_raw" or "/cam/image_raw/compressed" -> "/cam/camera_info").
std::string CameraInfoBeside(const ChosenCamera& camera);

struct TopicExtractionSummary {
  std::string topic;
  std::string type;
  int64_t messages = 0;          // read from the bag
  int64_t used = 0;              // written (images) or kept (odometry)
  int64_t duplicate_stamps = 0;  // skipped: same stamp as the previous one
  // Of the used messages, in the chosen time; 0 when none.
  int64_t first_stamp_ns = 0;
  int64_t last_stamp_ns = 0;
  double rate_hz = 0.0;  // (used - 1) / span; 0 for fewer than 2
  // Mean |header.stamp - receive time| over the messages read, seconds.
  double mean_abs_header_minus_receive_s = 0.0;
};

struct CameraExtractionSummary {
  std::string name;  // as ChosenCamera::name
  TopicExtractionSummary images;
  TopicExtractionSummary camera_info;  // topic empty when there is none
  // Written to camera.txt (a rig's to cameras.txt); none without a
  // CameraInfo.
  std::optional<ColmapCamera> camera;
};

struct BagExtractionSummary {
  ChosenTopics topics;
  BagTime time = BagTime::kHeader;
  std::vector<CameraExtractionSummary> cameras;  // as topics.cameras
  TopicExtractionSummary odometry;
  // "odometry.csv", "odometry.tum" or "wheels.csv", in the output folder.
  std::string odometry_file;
  bool planar = false;           // nav_msgs/Odometry written as odometry.csv
  std::string left_wheel_joint;  // joint states: the joints used
  std::string right_wheel_joint;
  double wheel_track_m = 0.0;  // as given
  // One line each: duplicate stamps, skipped joint states, changing
  // CameraInfo, header stamps far from the receive times.
  std::vector<std::string> warnings;
};

// Called after each message with the messages read so far and the total the
// bag's index gives for the chosen topics.
using ExtractionProgress = std::function<void(int64_t done, int64_t total)>;

// Extracts the chosen topics of `reader` into options.output_folder; see the
// top of this file. Opening the reader with only the chosen topics selected
// (ChooseTopics first) saves reading the others. Errors beyond the ones
// named above: a stamp before the previous one on the same topic
// (FormatError naming the topic and both stamps), a header stamp of 0 with
// BagTime::kHeader (pass --bag_time receive), images of different sizes on
// one topic, a CameraInfo whose size differs from its images', a chosen
// topic that yields no messages. An error can leave the folder partly
// written.
BagExtractionSummary ExtractBag(BagReader& reader,
                                const BagExtractionOptions& options,
                                const ExtractionProgress& progress = {});

}  // namespace odomcal::bag
