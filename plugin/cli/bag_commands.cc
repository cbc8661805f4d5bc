#include "odomcal/plugin/cli/bag_commands.h"

#include "odomcal/adapters/bag/bag_reader.h"
#include "odomcal/adapters/bag/camera_info_conversion.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/plugin/cli/command_flags.h"
#include "odomcal/plugin/cli/command_line.h"
#include "odomcal/plugin/colmap/reconstruction_pipeline.h"
#include "odomcal/plugin/options/bag_flags.h"
#include "odomcal/plugin/output/output_file.h"
#include "odomcal/plugin/output/output_folder.h"
#include "odomcal/solver/format_number.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// printf into a string, for the aligned columns of `inspect`.
std::string BagText(const char* format, ...)
    __attribute__((format(printf, 1, 2)));
std::string BagText(const char* format, ...) {
  va_list arguments;
  va_start(arguments, format);
  va_list again;
  va_copy(again, arguments);
  const int size = std::vsnprintf(nullptr, 0, format, arguments);
  va_end(arguments);
  std::string text(size > 0 ? static_cast<size_t>(size) : 0, '\0');
  if (size > 0) std::vsnprintf(text.data(), text.size() + 1, format, again);
  va_end(again);
  return text;
}

// Messages per second between the first and the last message.
double RateHz(int64_t count, int64_t first_ns, int64_t last_ns) {
  return count > 1 && last_ns > first_ns
             ? static_cast<double>(count - 1) / (1e-9 * (last_ns - first_ns))
             : 0.0;
}

std::string TopicLine(const bag::TopicExtractionSummary& topic,
                      const std::string& what) {
  return BagText("%s: %s (%s), %lld of %lld messages, %.1f s at %.1f Hz",
                 what.c_str(),
                 topic.topic.c_str(),
                 topic.type.c_str(),
                 static_cast<long long>(topic.used),
                 static_cast<long long>(topic.messages),
                 1e-9 * (topic.last_stamp_ns - topic.first_stamp_ns),
                 topic.rate_hz);
}

// The chosen topics in one line: "images /cam/image_raw, odometry /odom,
// camera info /cam/camera_info".
std::string ChoiceLine(const bag::ChosenTopics& topics) {
  std::string line =
      "images " + topics.image + ", " +
      (topics.odometry_joint_state ? "wheel joint states " : "odometry ") +
      topics.odometry;
  line += topics.camera_info.empty() ? ", no camera info (give --camera_params)"
                                     : ", camera info " + topics.camera_info;
  return line;
}

std::vector<std::string> SelectedTopics(const bag::ChosenTopics& topics) {
  std::vector<std::string> selected = {topics.image, topics.odometry};
  if (!topics.camera_info.empty()) selected.push_back(topics.camera_info);
  return selected;
}

// One error line for the bag commands: the exit code they return.
int ReportBagError(const std::string& command, const std::exception& error) {
  std::cerr << "odomcal " << command << ": error: " << error.what() << "\n";
  return kExitBadInput;
}

}  // namespace

bag::BagExtractionSummary ExtractBagPrinting(
    const std::string& bag_path,
    const bag::BagExtractionOptions& options,
    std::ostream& out) {
  options.Check();
  bag::ChosenTopics chosen;
  {
    const std::unique_ptr<bag::BagReader> index = bag::OpenBag(bag_path);
    chosen = bag::ChooseTopics(index->Topics(), options);
  }
  out << "  topics: " << ChoiceLine(chosen) << "\n" << std::flush;
  const std::unique_ptr<bag::BagReader> reader =
      bag::OpenBag(bag_path, SelectedTopics(chosen));
  int last_tenth = -1;
  bag::BagExtractionSummary summary =
      bag::ExtractBag(*reader, options, [&](int64_t done, int64_t total) {
        const int tenth = total > 0 ? static_cast<int>(10 * done / total) : 0;
        if (tenth > last_tenth) {
          last_tenth = tenth;
          out << "  read " << done << " of " << total << " messages\n"
              << std::flush;
        }
      });
  out << "  " << TopicLine(summary.images, "images") << "\n";
  out << "  "
      << TopicLine(summary.odometry,
                   summary.topics.odometry_joint_state ? "wheels" : "odometry")
      << " -> " << summary.odometry_file
      << (summary.topics.odometry_joint_state
              ? " (joints " + summary.left_wheel_joint + ", " +
                    summary.right_wheel_joint + ")"
          : summary.planar ? " (planar: x, y, yaw)"
                           : " (SE(3): the odometry leaves the plane)")
      << "\n";
  if (summary.camera) {
    out << "  camera: " << bag::ColmapCameraLine(*summary.camera)
        << " -> camera.txt (COLMAP's pixel centre: ROS's cx, cy + 0.5)\n";
  }
  out << "  time: " << bag::BagTimeName(summary.time)
      << (summary.time == bag::BagTime::kHeader
              ? " stamps (the capture times; --bag_time receive for the "
                "recorder's)"
              : " times (when the recorder received each message)")
      << "\n";
  for (const std::string& warning : summary.warnings) {
    out << "  warning: " << warning << "\n";
  }
  return summary;
}

std::string ExtractedOdometryPath(const bag::BagExtractionOptions& options,
                                  const bag::BagExtractionSummary& summary) {
  return (fs::path(options.output_folder) / summary.odometry_file).string();
}

std::pair<std::string, std::string> ExtractedCamera(
    const bag::BagExtractionSummary& summary) {
  if (!summary.camera) return {};
  const std::string flags = bag::OdomcalCameraFlags(*summary.camera);
  const std::string params_flag = "--camera_params ";
  const size_t at = flags.find(params_flag);
  return {ColmapCameraModelName(summary.camera->model),
          at == std::string::npos ? std::string()
                                  : flags.substr(at + params_flag.size())};
}

// `odomcal run --bag`: the workspace claimed, the bag extracted into
// WS/bag_inputs (replacing an earlier extraction), and `run` pointed at the
// files: images, image times, odometry, and the camera from CameraInfo
// unless --camera_params was given.
bag::BagExtractionSummary ExtractBagForRun(
    const std::string& bag_path,
    bool camera_params_given,
    bag::BagExtractionOptions* bag_options,
    ReconstructionOptions* run,
    std::ostream& out) {
  const fs::path inputs = fs::path(run->workspace_path) / "bag_inputs";
  PrepareOutputFolder({run->workspace_path, "--workspace_path"},
                      {{bag_path, "--bag"}},
                      {"bag_inputs"},
                      ExistingOutputs::kReplaceOwn);
  RemoveOwnedOutput(run->workspace_path, "bag_inputs");
  bag_options->output_folder = inputs.string();
  bag_options->wheel_track_m = run->project.systematics.wheel_track_m;
  bag::BagExtractionSummary summary =
      ExtractBagPrinting(bag_path, *bag_options, out);
  run->extracted_inputs_path = inputs.string();
  run->image_path = (inputs / "images").string();
  run->project.image_timestamps_path =
      (inputs / "image_timestamps.csv").string();
  run->project.odometry_path = ExtractedOdometryPath(*bag_options, summary);
  const auto [model, params] = ExtractedCamera(summary);
  if (!model.empty() && !camera_params_given) {
    run->camera_model = model;
    run->camera_params = params;
  }
  return summary;
}

int RunInspect(int argc, char** argv) {
  CLI::App app{
      "Lists a robot bag's topics (types, counts, rates, time spans) and the "
      "topics `odomcal run --bag` would take.",
      "odomcal inspect"};
  std::string bag_path;
  app.add_option("--bag",
                 bag_path,
                 "ROS 1 bag, or ROS 2 bag (folder with metadata.yaml, .db3 or "
                 ".mcap)")
      ->required();
  bag::BagExtractionOptions options;
  AddFlags(BagTopicFlags(), &app, &options);
  if (const auto exit_code = ParseFlags(&app, argc, argv)) return *exit_code;
  try {
    const std::unique_ptr<bag::BagReader> reader = bag::OpenBag(bag_path);
    const std::vector<bag::BagTopic>& topics = reader->Topics();
    std::cout << "odomcal inspect: " << bag_path << ", " << topics.size()
              << " topics\n";
    size_t width = 5;
    size_t type_width = 4;
    for (const bag::BagTopic& topic : topics) {
      width = std::max(width, topic.topic.size());
      type_width = std::max(type_width, topic.type.size());
    }
    std::cout << "  "
              << BagText("%-*s  %-*s  %9s  %9s  %9s",
                         static_cast<int>(width),
                         "topic",
                         static_cast<int>(type_width),
                         "type",
                         "messages",
                         "rate",
                         "span")
              << "\n";
    for (const bag::BagTopic& topic : topics) {
      const double rate = RateHz(
          topic.message_count, topic.first_log_time_ns, topic.last_log_time_ns);
      std::cout << "  "
                << BagText("%-*s  %-*s  %9lld  %6.1f Hz  %7.1f s",
                           static_cast<int>(width),
                           topic.topic.c_str(),
                           static_cast<int>(type_width),
                           topic.type.c_str(),
                           static_cast<long long>(topic.message_count),
                           rate,
                           1e-9 * (topic.last_log_time_ns -
                                   topic.first_log_time_ns))
                << "\n";
    }
    std::cout << "  (rates and spans from the recorder's receive times)\n";
    try {
      const std::string choice = ChoiceLine(bag::ChooseTopics(topics, options));
      std::cout << "run --bag would use: " << choice << "\n";
    } catch (const std::invalid_argument& why) {
      std::cout << "run --bag cannot choose by itself: " << why.what() << "\n";
    }
    return kExitSuccess;
  } catch (const FormatError& error) {
    return ReportBagError("inspect", error);
  } catch (const std::invalid_argument& error) {
    return ReportBagError("inspect", error);
  } catch (const std::runtime_error& error) {
    return ReportBagError("inspect", error);
  }
}

int RunExtract(int argc, char** argv) {
  CLI::App app{
      "Writes a robot bag's images, image times, odometry (or wheel travels) "
      "and camera as the input files of odomcal's other commands.",
      "odomcal extract"};
  std::string bag_path;
  bag::BagExtractionOptions options;
  app.add_option("--bag",
                 bag_path,
                 "ROS 1 bag, or ROS 2 bag (folder with metadata.yaml, .db3 or "
                 ".mcap)")
      ->required();
  app.add_option("--output_path",
                 options.output_folder,
                 "folder for images/, image_timestamps.csv, odometry.csv (or "
                 "odometry.tum, wheels.csv) and camera.txt (created; must be "
                 "empty)")
      ->required();
  AddFlags(BagTopicFlags(), &app, &options);
  app.add_option("--wheel_track_m",
                 options.wheel_track_m,
                 "JointState wheels: the nominal wheel track (shown in the "
                 "next command; calibrate and run need it for wheels.csv)")
      ->check(AtLeast(0.0));
  if (const auto exit_code = ParseFlags(&app, argc, argv)) return *exit_code;
  try {
    std::cout << "odomcal extract: " << bag_path << " -> "
              << options.output_folder << "\n";
    const bag::BagExtractionSummary summary =
        ExtractBagPrinting(bag_path, options, std::cout);
    const fs::path out(options.output_folder);
    std::string next = "odomcal run --image_path " + (out / "images").string() +
                       " --image_timestamps " +
                       (out / "image_timestamps.csv").string() +
                       " --odometry " + ExtractedOdometryPath(options, summary);
    if (summary.topics.odometry_joint_state) {
      next += " --wheel_track_m " +
              (options.wheel_track_m > 0.0
                   ? FormatPrintf("%.12g", options.wheel_track_m)
                   : std::string("TRACK"));
    }
    const auto [model, params] = ExtractedCamera(summary);
    if (!model.empty()) {
      next += " --camera_model " + model + " --camera_params " + params;
    }
    std::cout << "odomcal extract: done; next:\n  " << next
              << " --workspace_path WS\n";
    return kExitSuccess;
  } catch (const FormatError& error) {
    return ReportBagError("extract", error);
  } catch (const std::invalid_argument& error) {
    return ReportBagError("extract", error);
  } catch (const std::runtime_error& error) {  // OutputError, file system
    return ReportBagError("extract", error);
  }
}

}  // namespace odomcal
