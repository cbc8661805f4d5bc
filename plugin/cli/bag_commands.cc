#include "odomcal/plugin/cli/bag_commands.h"

#include "odomcal/adapters/bag/bag_reader.h"
#include "odomcal/adapters/bag/camera_info_conversion.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/plugin/cli/command_flags.h"
#include "odomcal/plugin/cli/command_line.h"
#include "odomcal/plugin/cli/rig_run.h"
#include "odomcal/plugin/cli/run_command.h"
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

// One camera's topics: "images /cam/image_raw, camera info
// /cam/camera_info".
std::string CameraChoice(const bag::ChosenCamera& camera) {
  return "images " + camera.image +
         (camera.camera_info.empty()
              ? ", no camera info (give --camera_params" +
                    (camera.name.empty() ? std::string()
                                         : " " + camera.name + "=PARAMS") +
                    ")"
              : ", camera info " + camera.camera_info);
}

// The chosen topics in one line: "images /cam/image_raw, odometry /odom,
// camera info /cam/camera_info"; a rig's "cameras left (images
// /left/image_raw, camera info /left/camera_info), right (...), odometry
// /odom".
std::string ChoiceLine(const bag::ChosenTopics& topics) {
  const std::string odometry =
      (topics.odometry_joint_state ? "wheel joint states " : "odometry ") +
      topics.odometry;
  if (!topics.rig) {
    const bag::ChosenCamera& camera = topics.cameras.front();
    return "images " + camera.image + ", " + odometry +
           (camera.camera_info.empty()
                ? ", no camera info (give --camera_params)"
                : ", camera info " + camera.camera_info);
  }
  std::string line = std::to_string(topics.cameras.size()) + " cameras ";
  for (size_t k = 0; k < topics.cameras.size(); ++k) {
    const bag::ChosenCamera& camera = topics.cameras[k];
    line +=
        (k == 0 ? "" : ", ") + camera.name + " (" + CameraChoice(camera) + ")";
  }
  return line + ", " + odometry;
}

std::vector<std::string> SelectedTopics(const bag::ChosenTopics& topics) {
  std::vector<std::string> selected = {topics.odometry};
  for (const bag::ChosenCamera& camera : topics.cameras) {
    selected.push_back(camera.image);
    if (!camera.camera_info.empty()) selected.push_back(camera.camera_info);
  }
  return selected;
}

// The camera flags of the `odomcal run` command that `extract` prints: the
// one camera's from its CameraInfo; a rig's NAME=PARAMS when its cameras
// share one model (run --rig takes one --camera_model), else none.
std::string RunCameraFlags(const bag::BagExtractionSummary& summary) {
  std::string model, params;
  for (const bag::CameraExtractionSummary& camera : summary.cameras) {
    if (!camera.camera) continue;
    const auto [camera_model, camera_params] = ExtractedCamera(camera);
    if (!model.empty() && camera_model != model) return "";
    model = camera_model;
    params += " --camera_params " +
              (camera.name.empty() ? "" : camera.name + "=") + camera_params;
  }
  return model.empty() ? "" : " --camera_model " + model + params;
}

// One error line for the bag commands: the exit code they return.
int ReportBagError(const std::string& command, const std::exception& error) {
  std::cerr << "odomcal " << command << ": error: " << error.what() << "\n";
  return kExitBadInput;
}

}  // namespace

bag::ChosenTopics ChooseBagTopics(const std::string& bag_path,
                                  const bag::BagExtractionOptions& options) {
  const std::unique_ptr<bag::BagReader> index = bag::OpenBag(bag_path);
  return bag::ChooseTopics(index->Topics(), options);
}

bag::BagExtractionSummary ExtractBagPrinting(
    const std::string& bag_path,
    const bag::BagExtractionOptions& options,
    std::ostream& out,
    const bag::ChosenTopics* chosen) {
  options.Check();
  const bag::ChosenTopics topics =
      chosen != nullptr ? *chosen : ChooseBagTopics(bag_path, options);
  out << "  topics: " << ChoiceLine(topics) << "\n" << std::flush;
  const std::unique_ptr<bag::BagReader> reader =
      bag::OpenBag(bag_path, SelectedTopics(topics));
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
  for (const bag::CameraExtractionSummary& camera : summary.cameras) {
    out << "  "
        << TopicLine(camera.images,
                     camera.name.empty() ? "images" : "images " + camera.name)
        << "\n";
  }
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
  for (const bag::CameraExtractionSummary& camera : summary.cameras) {
    if (!camera.camera) continue;
    out << "  camera" << (camera.name.empty() ? "" : " " + camera.name) << ": "
        << bag::ColmapCameraLine(*camera.camera) << " -> "
        << (summary.topics.rig ? "cameras.txt" : "camera.txt")
        << " (COLMAP's pixel centre: ROS's cx, cy + 0.5)\n";
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
    const bag::CameraExtractionSummary& camera) {
  if (!camera.camera) return {};
  const std::string flags = bag::OdomcalCameraFlags(*camera.camera);
  const std::string params_flag = "--camera_params ";
  const size_t at = flags.find(params_flag);
  return {ColmapCameraModelName(camera.camera->model),
          at == std::string::npos ? std::string()
                                  : flags.substr(at + params_flag.size())};
}

namespace {

// The workspace claimed for WS/bag_inputs (an earlier extraction removed),
// the bag extracted into it, and `run` pointed at its images, image times
// and odometry.
bag::BagExtractionSummary ExtractIntoWorkspace(
    const std::string& bag_path,
    const bag::ChosenTopics& chosen,
    bag::BagExtractionOptions* bag_options,
    ReconstructionOptions* run,
    std::ostream& out) {
  const fs::path inputs = fs::path(run->workspace_path) / "bag_inputs";
  PrepareOutputFolder({run->workspace_path, "--workspace_path"},
                      {{bag_path, "--bag"}},
                      {"bag_inputs"},
                      ExistingOutputs::kReplaceOwn);
  RemoveOwnedOutput(run->workspace_path, "bag_inputs");
  bag::BagExtractionSummary summary =
      ExtractBagPrinting(bag_path, *bag_options, out, &chosen);
  run->extracted_inputs_path = inputs.string();
  run->image_path = (inputs / "images").string();
  run->project.image_timestamps_path =
      (inputs / "image_timestamps.csv").string();
  run->project.odometry_path = ExtractedOdometryPath(*bag_options, summary);
  return summary;
}

// The output folder and the wheel track of `run --bag`'s extraction.
void SetRunExtraction(const ReconstructionOptions& run,
                      bag::BagExtractionOptions* bag_options) {
  bag_options->output_folder =
      (fs::path(run.workspace_path) / "bag_inputs").string();
  bag_options->wheel_track_m = run.project.systematics.wheel_track_m;
  bag_options->Check();
}

}  // namespace

bag::BagExtractionSummary ExtractBagForRun(
    const std::string& bag_path,
    bool camera_params_given,
    bag::BagExtractionOptions* bag_options,
    ReconstructionOptions* run,
    std::ostream& out) {
  if (bag_options->IsRig()) {
    throw std::invalid_argument(
        "several image topics are the cameras of a rig: odomcal run --bag "
        "calibrates them");
  }
  SetRunExtraction(*run, bag_options);
  const bag::ChosenTopics chosen = ChooseBagTopics(bag_path, *bag_options);
  bag::BagExtractionSummary summary =
      ExtractIntoWorkspace(bag_path, chosen, bag_options, run, out);
  const auto [model, params] = ExtractedCamera(summary.cameras.front());
  if (!model.empty() && !camera_params_given) {
    run->camera_model = model;
    run->camera_params = params;
  }
  return summary;
}

BagRigCameras ExtractBagRigForRun(const std::string& bag_path,
                                  const BagRigFlags& flags,
                                  bag::BagExtractionOptions* bag_options,
                                  ReconstructionOptions* run,
                                  std::ostream& out) {
  SetRunExtraction(*run, bag_options);
  bag_options->rig = true;
  const bag::ChosenTopics chosen = ChooseBagTopics(bag_path, *bag_options);
  BagRigCameras rig;
  for (const bag::ChosenCamera& camera : chosen.cameras) {
    rig.names.push_back(camera.name);
  }
  // Every camera flag checked against the cameras before the extraction.
  const std::string cameras_from = "--bag";
  const std::map<std::string, std::string> given =
      RigCameraParams(flags.camera_params, rig.names, cameras_from);
  if (!flags.reference_camera.empty() &&
      std::find(rig.names.begin(), rig.names.end(), flags.reference_camera) ==
          rig.names.end()) {
    throw std::invalid_argument(
        "--reference_camera '" + flags.reference_camera +
        "' names no camera of --bag (its cameras: " + JoinNames(rig.names) +
        ")");
  }
  for (const bag::ChosenCamera& camera : chosen.cameras) {
    if (camera.camera_info.empty() && given.count(camera.name) == 0) {
      throw std::invalid_argument(
          "--image_topic " + camera.image + " (camera " + camera.name +
          "): the bag has no CameraInfo beside it (" +
          bag::CameraInfoBeside(camera) + ") and no --camera_params " +
          camera.name + "=PARAMS is given");
    }
  }
  const bag::BagExtractionSummary summary =
      ExtractIntoWorkspace(bag_path, chosen, bag_options, run, out);
  for (size_t k = 0; k < summary.cameras.size(); ++k) {
    const bag::CameraExtractionSummary& camera = summary.cameras[k];
    const auto user = given.find(camera.name);
    if (user != given.end()) {
      rig.camera_params.push_back(camera.name + "=" + user->second);
      continue;
    }
    const auto [model, params] = ExtractedCamera(camera);
    if (model.empty()) {
      throw FormatError(bag_path + ": " + chosen.cameras[k].camera_info +
                        ": no CameraInfo read for camera " + camera.name);
    }
    rig.camera_params.push_back(camera.name + "=" + params);
    rig.camera_models[camera.name] = model;
  }
  return rig;
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
    // Several image topics: what a rig run (a camera per topic) would take.
    size_t image_topics = 0;
    for (const bag::BagTopic& topic : topics) {
      image_topics += topic.message_count > 0 &&
                      (topic.type == "sensor_msgs/Image" ||
                       topic.type == "sensor_msgs/CompressedImage");
    }
    if (!options.IsRig() && image_topics > 1) {
      bag::BagExtractionOptions rig = options;
      rig.rig = true;
      rig.image_topics.clear();
      try {
        const std::string choice = ChoiceLine(bag::ChooseTopics(topics, rig));
        std::cout << "run --bag --rig would use: " << choice << "\n";
      } catch (const std::invalid_argument& why) {
        std::cout << "run --bag --rig cannot choose by itself: " << why.what()
                  << "\n";
      }
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
    if (summary.topics.rig) {
      next.insert(std::string("odomcal run").size(), " --rig");
    }
    const std::string camera_flags = RunCameraFlags(summary);
    next += camera_flags;
    std::cout << "odomcal extract: done; next:\n  " << next
              << " --workspace_path WS\n";
    if (summary.topics.rig && camera_flags.empty()) {
      std::cout << "  (with the cameras' intrinsics: run --rig takes one "
                   "--camera_model and the cameras' differ, see cameras.txt; "
                   "odomcal run --bag takes each camera's own)\n";
    }
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
