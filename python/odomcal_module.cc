// The Python module `odomcal` (docs/python.md), each function a command's
// pipeline returning its result JSON (docs/result_schema.md) as a dict:
//   calibrate(camera_poses, odometry, **options): `odomcal calibrate` on
//     files or numpy arrays;
//   calibrate_project(model_path, odometry, **options): `odomcal colmap`
//     (odomcal::plugin's CalibrateColmapProject), writing nothing;
//   reconstruct_and_calibrate(image_path, odometry, workspace_path,
//     progress, **options): `odomcal run` (ReconstructAndCalibrate); with
//     bag=PATH instead of image_path and odometry, `odomcal run --bag`;
//   extract(bag, output_path, **options): `odomcal extract`.
//
// The keywords are the command's flags: the module builds the same CLI11
// app (command_flags.h) and parses "--name=value" made from the keywords, so
// defaults, checks and the nearest-keyword suggestion for a typo are the
// CLI's. Errors are raised, never printed: TypeError for an unknown
// keyword or an argument of the wrong type, ValueError for bad values, files
// and arrays, each with the CLI's one-line message in keyword terms
// ("--max_odometry_gap_s" reads "max_odometry_gap_s").
#include "odomcal/adapters/colmap_cameras.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/plugin/cli/bag_commands.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/cli/colmap_rig_outputs.h"
#include "odomcal/plugin/cli/command_flags.h"
#include "odomcal/plugin/cli/command_line.h"
#include "odomcal/plugin/cli/rig_calibration.h"
#include "odomcal/plugin/cli/rig_report.h"
#include "odomcal/plugin/colmap/colmap_runner.h"
#include "odomcal/plugin/colmap/odometry_inputs.h"
#include "odomcal/plugin/odomcal_plugin.h"
#include "odomcal/plugin/options/bag_flags.h"
#include "odomcal/plugin/report/calibration_report.h"
#include "odomcal/plugin/report/colmap_report.h"
#include "odomcal/python/array_trajectory.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace py = pybind11;
namespace fs = std::filesystem;

namespace odomcal {
namespace {

// The CLI's message in keyword terms: "unknown flag --x (did you mean --y?)"
// -> "unknown keyword x (did you mean y?)". Drops "--" before a name at the
// start of the message or after a blank or '('.
std::string KeywordMessage(std::string message) {
  const std::string unknown_flag = "unknown flag ";
  if (message.compare(0, unknown_flag.size(), unknown_flag) == 0) {
    message.replace(0, unknown_flag.size(), "unknown keyword ");
  }
  for (size_t at = message.find("--"); at != std::string::npos;
       at = message.find("--", at + 1)) {
    const bool starts_word =
        at == 0 || message[at - 1] == ' ' || message[at - 1] == '(';
    if (starts_word && at + 2 < message.size() &&
        std::isalpha(static_cast<unsigned char>(message[at + 2]))) {
      message.erase(at, 2);
    }
  }
  return message;
}

bool IsUnknownKeyword(const std::string& message) {
  return message.rfind("unknown flag ", 0) == 0;
}

// The keywords of a function are the flags of its command: a CLI11 app
// with the command's flags (command_flags.h) parses "--name=value" made
// from them.
struct FlagParser {
  std::string function;  // "odomcal.calibrate", for the messages
  CLI::App* app;
};

bool IsPath(const py::handle& object) {
  return py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__");
}

std::string PathText(const py::handle& object) {
  return py::str(py::module_::import("os").attr("fspath")(object));
}

// "--name=value" for each keyword; a flag (no value) for True.
std::vector<std::string> ArgumentsFromKeywords(const FlagParser& parser,
                                               const py::kwargs& keywords) {
  std::vector<std::string> arguments = {parser.function};
  for (const auto& [key, value] : keywords) {
    const std::string name = py::str(key);
    if (value.is_none()) continue;
    if (name == "help") {
      throw py::type_error("unknown keyword help (see help(" + parser.function +
                           "))");
    }
    const CLI::Option* option = parser.app->get_option_no_throw("--" + name);
    const bool is_flag = option != nullptr && option->get_expected_max() == 0;
    if (is_flag) {
      if (!py::isinstance<py::bool_>(value)) {
        throw py::type_error(name + " takes True or False, got " +
                             std::string(py::str(py::repr(value))));
      }
      if (value.cast<bool>()) arguments.push_back("--" + name);
      continue;
    }
    std::string text;
    if (IsPath(value)) {
      text = PathText(value);  // a str or an os.PathLike
    } else if (!py::isinstance<py::bool_>(value) &&
               (py::hasattr(value, "__index__") ||
                py::hasattr(value, "__float__"))) {
      text = py::str(value);  // repr of a float: the shortest exact digits
    } else if (option != nullptr) {
      throw py::type_error(
          name + " takes a number or a string, got " +
          std::string(py::str(py::type::of(value).attr("__name__"))));
    }
    arguments.push_back("--" + name + "=" + text);
  }
  return arguments;
}

void ParseKeywords(const FlagParser& parser, const py::kwargs& keywords) {
  const std::vector<std::string> arguments =
      ArgumentsFromKeywords(parser, keywords);
  std::vector<const char*> argv;
  for (const std::string& argument : arguments)
    argv.push_back(argument.c_str());
  const std::string error =
      FlagError(parser.app, static_cast<int>(argv.size()), argv.data());
  if (error.empty()) return;
  if (IsUnknownKeyword(error)) throw py::type_error(KeywordMessage(error));
  throw py::value_error(KeywordMessage(error));
}

// `keywords` with the named arguments added (a function's own parameters,
// e.g. model_path, which are flags of its command too).
py::kwargs WithArguments(
    const py::kwargs& keywords,
    const std::vector<std::pair<const char*, py::object>>& named) {
  py::kwargs all;
  for (const auto& [name, value] : named) all[name] = value;
  for (const auto& [key, value] : keywords) all[key] = value;
  return all;
}

// The library's rejections of input as the exceptions of the module: a
// ValueError with the CLI's one-line message in keyword terms; COLMAP
// failing is a RuntimeError.
template <typename Body>
std::string ReportingErrors(const Body& body) {
  try {
    return body();
  } catch (const py::builtin_exception&) {
    throw;  // already a TypeError or ValueError
  } catch (const ColmapError& error) {
    throw std::runtime_error(KeywordMessage(error.what()));
  } catch (const std::invalid_argument& error) {
    throw py::value_error(KeywordMessage(error.what()));
  } catch (const std::runtime_error& error) {
    throw py::value_error(KeywordMessage(error.what()));
  }
}

py::object DictFromJson(const std::string& json_text) {
  return py::module_::import("json").attr("loads")(json_text);
}

// A 2-D numpy array of real numbers as rows of doubles.
NumericRows RowsFromArray(const py::array& array, const std::string& name) {
  if (array.ndim() != 2) {
    py::tuple shape(array.ndim());
    for (py::ssize_t i = 0; i < array.ndim(); ++i) shape[i] = array.shape(i);
    throw FormatError(name + ": expected a 2-D array, got shape " +
                      std::string(py::str(shape)));
  }
  const char kind = array.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw py::type_error(name +
                         ": expected an array of real numbers, got dtype " +
                         std::string(py::str(array.dtype())));
  }
  const auto doubles =
      py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
          array);
  NumericRows rows;
  rows.num_rows = static_cast<size_t>(array.shape(0));
  rows.num_cols = static_cast<size_t>(array.shape(1));
  rows.values.assign(doubles.data(),
                     doubles.data() + rows.num_rows * rows.num_cols);
  return rows;
}

// (times, values): a tuple of two whose first item is a 1-D array (never a
// segment's poses, which are 2-D).
bool IsTimesPair(const py::handle& object) {
  if (!py::isinstance<py::tuple>(object) || py::len(object) != 2) return false;
  const py::object times = py::reinterpret_borrow<py::tuple>(object)[0];
  return py::isinstance<py::array>(times) &&
         py::reinterpret_borrow<py::array>(times).ndim() == 1;
}

// (times, values): integer nanoseconds beside the other columns. The time
// column of the rows is a placeholder; stamps_ns holds the times.
NumericRows RowsFromTimesPair(const py::tuple& pair, const std::string& name) {
  const py::array times = pair[0];
  if (times.dtype().kind() != 'i') {
    throw py::type_error(name +
                         ": the times of (times, values) must be signed "
                         "integer nanoseconds (int64), got dtype " +
                         std::string(py::str(times.dtype())));
  }
  if (!py::isinstance<py::array>(pair[1])) {
    throw py::type_error(
        name + ": the values of (times, values) must be a numpy array, got " +
        std::string(py::str(py::type::of(pair[1]).attr("__name__"))));
  }
  const NumericRows values =
      RowsFromArray(py::reinterpret_borrow<py::array>(pair[1]), name);
  if (static_cast<size_t>(times.shape(0)) != values.num_rows) {
    throw FormatError(name + ": " + std::to_string(times.shape(0)) +
                      " times for " + std::to_string(values.num_rows) +
                      " rows of values");
  }
  const auto stamps =
      py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(
          times);
  NumericRows rows;
  rows.num_rows = values.num_rows;
  rows.num_cols = values.num_cols + 1;
  rows.values.reserve(rows.num_rows * rows.num_cols);
  for (size_t row = 0; row < values.num_rows; ++row) {
    rows.values.push_back(0.0);
    for (size_t col = 0; col < values.num_cols; ++col) {
      rows.values.push_back(values.values[row * values.num_cols + col]);
    }
  }
  rows.stamps_ns.assign(stamps.data(), stamps.data() + rows.num_rows);
  return rows;
}

// A path is read later (without the GIL); an array is converted now.
struct Input {
  std::string path;
  std::optional<NumericRows> rows;
  std::string name;
};

Input InputFrom(const py::handle& object, const std::string& name) {
  if (IsPath(object)) return {PathText(object), std::nullopt, name};
  if (py::isinstance<py::array>(object)) {
    return {"",
            RowsFromArray(py::reinterpret_borrow<py::array>(object), name),
            name};
  }
  if (IsTimesPair(object)) {
    return {"",
            RowsFromTimesPair(py::reinterpret_borrow<py::tuple>(object), name),
            name};
  }
  throw py::type_error(
      name + ": expected a file path or a numpy array, got " +
      std::string(py::str(py::type::of(object).attr("__name__"))));
}

// camera_poses: a path, array or (times, values), or a list of them (one
// per SfM segment).
std::vector<Input> CameraInputs(const py::object& camera_poses) {
  if ((py::isinstance<py::list>(camera_poses) ||
       py::isinstance<py::tuple>(camera_poses)) &&
      !IsTimesPair(camera_poses)) {
    std::vector<Input> inputs;
    size_t index = 0;
    for (const py::handle item : camera_poses) {
      inputs.push_back(
          InputFrom(item, "camera_poses[" + std::to_string(index++) + "]"));
    }
    if (inputs.empty())
      throw py::value_error("camera_poses: the list is empty");
    return inputs;
  }
  return {InputFrom(camera_poses, "camera_poses")};
}

// odomcal.calibrate: the calibrate command's flags.
struct CalibrateFlags {
  CLI::App app{"", "odomcal.calibrate"};
  CalibrateInputs inputs;
  CalibrateFlags() {
    AddCalibrationFlags(&app, &inputs);
    app.add_option("--reference_camera",
                   inputs.reference_camera,
                   "with camera_poses a dict: the camera of the top level");
  }
  FlagParser Parser() { return {"odomcal.calibrate", &app}; }
};

// odomcal.calibrate_project: `odomcal colmap`'s, but for its outputs.
struct ProjectFlagSet {
  CLI::App app{"", "odomcal.calibrate_project"};
  ColmapCalibrationInputs inputs;
  ProjectFlags flags;
  std::string reference_camera;
  ProjectFlagSet() {
    AddFlags(ColmapModelFlags(), &app, &inputs);
    AddProjectFlags(&app, &inputs, &flags);
    app.add_option("--reference_camera",
                   reference_camera,
                   "a project with several cameras: the camera of the top "
                   "level");
  }
  FlagParser Parser() { return {"odomcal.calibrate_project", &app}; }
};

// odomcal.reconstruct_and_calibrate: `odomcal run`'s.
struct RunFlagSet {
  CLI::App app{"", "odomcal.reconstruct_and_calibrate"};
  ReconstructionOptions options;
  ProjectFlags flags;
  // bag= instead of image_path, odometry and image_timestamps.
  std::string bag_path;
  bag::BagExtractionOptions bag_options;
  RunFlagSet() {
    AddRunFlags(&app, &options);
    AddProjectFlags(&app, &options.project, &flags);
    app.add_option("--bag", bag_path, "a robot bag (ROS 1 or ROS 2)");
    AddFlags(BagTopicFlags(), &app, &bag_options);
    for (const char* flag : {"--image_path", "--odometry"}) {
      app.get_option(flag)->required(false);
    }
  }
  FlagParser Parser() { return {"odomcal.reconstruct_and_calibrate", &app}; }
};

struct ExtractFlagSet {
  CLI::App app{"", "odomcal.extract"};
  std::string bag_path;
  bag::BagExtractionOptions options;
  ExtractFlagSet() {
    app.add_option("--bag", bag_path, "a robot bag (ROS 1 or ROS 2)")
        ->required();
    app.add_option("--output_path", options.output_folder, "the folder")
        ->required();
    AddFlags(BagTopicFlags(), &app, &options);
    app.add_option(
        "--wheel_track_m", options.wheel_track_m, "the nominal wheel track");
  }
  FlagParser Parser() { return {"odomcal.extract", &app}; }
};

// camera_poses as a dict {name: poses or a list of segments}: every camera
// calibrated against the odometry, as `odomcal calibrate --camera`.
py::object CalibrateRigCameras(const py::dict& camera_poses,
                               const py::object& odometry,
                               CalibrateFlags* flag_set) {
  const CalibrateInputs& inputs = flag_set->inputs;
  return DictFromJson(ReportingErrors([&] {
    std::vector<std::pair<std::string, std::vector<Input>>> named_in;
    std::vector<NamedCameraPaths> names;
    for (const auto& [key, value] : camera_poses) {
      if (!py::isinstance<py::str>(key)) {
        throw std::invalid_argument("camera_poses: the keys are camera names");
      }
      const std::string name = py::str(key);
      CheckCameraName(name, "camera_poses['" + name + "']");
      named_in.emplace_back(
          name, CameraInputs(py::reinterpret_borrow<py::object>(value)));
      names.push_back({name, {}});
    }
    if (named_in.empty()) {
      throw std::invalid_argument("camera_poses: the dict is empty");
    }
    const int reference = ReferenceCameraIndex(names, inputs.reference_camera);
    const Input odometry_in = InputFrom(odometry, "odometry");
    flag_set->inputs.odometry_path = odometry_in.path;
    inputs.association.Check();
    inputs.calibration.Check();
    py::gil_scoped_release no_gil;
    std::vector<NamedCamera> cameras;
    for (const auto& [name, segments] : named_in) {
      NamedCamera camera{name, {}};
      for (const Input& in : segments) {
        camera.segments.push_back(
            in.rows ? CameraTrajectoryFromRows(
                          *in.rows, inputs.camera_time_unit, in.name)
                    : ReadTumTrajectory(in.path, inputs.camera_time_unit));
      }
      cameras.push_back(std::move(camera));
    }
    const Trajectory odometry_trajectory =
        odometry_in.rows ? OdometryFromRows(*odometry_in.rows,
                                            inputs.odometry_time_unit,
                                            odometry_in.name)
                         : ReadOdometryOf(inputs);
    const RigCalibrationRun rig = CalibrateRig(
        cameras, odometry_trajectory, inputs, reference, "odomcal calibrate");
    return RigCalibrationToJson(rig).dump();
  }));
}

py::object Calibrate(const py::object& camera_poses,
                     const py::object& odometry,
                     const py::kwargs& keywords) {
  CalibrateFlags flag_set;
  ParseKeywords(flag_set.Parser(), keywords);
  const CalibrateInputs& inputs = flag_set.inputs;
  if (py::isinstance<py::dict>(camera_poses)) {
    return CalibrateRigCameras(
        py::reinterpret_borrow<py::dict>(camera_poses), odometry, &flag_set);
  }
  if (!inputs.reference_camera.empty()) {
    throw py::value_error(
        "reference_camera: given, but camera_poses is not a dict of cameras");
  }
  return DictFromJson(ReportingErrors([&] {
    const std::vector<Input> cameras_in = CameraInputs(camera_poses);
    const Input odometry_in = InputFrom(odometry, "odometry");
    flag_set.inputs.odometry_path = odometry_in.path;  // "" for arrays
    inputs.association.Check();
    inputs.calibration.Check();
    if (odometry_in.rows && inputs.systematics.wheel_ticks_per_m > 0.0) {
      // As on the command line: the flag applies to tick columns only.
      throw std::invalid_argument(
          "wheel_ticks_per_m: given, but the odometry is an array of poses "
          "(t, x, y, yaw), not wheel ticks; drop it");
    }
    py::gil_scoped_release no_gil;  // reading and calibrating take a while
    std::vector<Trajectory> cameras;
    for (const Input& in : cameras_in) {
      cameras.push_back(
          in.rows ? CameraTrajectoryFromRows(
                        *in.rows, inputs.camera_time_unit, in.name)
                  : ReadTumTrajectory(in.path, inputs.camera_time_unit));
    }
    const Trajectory odometry_trajectory =
        odometry_in.rows ? OdometryFromRows(*odometry_in.rows,
                                            inputs.odometry_time_unit,
                                            odometry_in.name)
                         : ReadOdometryOf(inputs);
    // The calibrate command's pipeline and writer: the same JSON.
    const CalibrationRun run = CalibrateTrajectories(
        cameras, odometry_trajectory, inputs, "odomcal calibrate");
    return CalibrationToJson(run.result, run.context).dump();
  }));
}

py::object CalibrateProject(const py::object& model_path,
                            const py::object& odometry,
                            const py::kwargs& keywords) {
  ProjectFlagSet flag_set;
  ParseKeywords(
      flag_set.Parser(),
      WithArguments(keywords,
                    {{"model_path", model_path}, {"odometry", odometry}}));
  FinishProjectFlags(flag_set.flags, &flag_set.inputs);
  const ColmapCalibrationInputs& inputs = flag_set.inputs;
  return DictFromJson(ReportingErrors([&] {
    py::gil_scoped_release no_gil;
    inputs.Check();
    // Several cameras: each from its own images, as `odomcal colmap` does.
    const ColmapProjectCameras cameras =
        FindColmapProjectCameras(inputs.model_path);
    if (cameras.IsRig()) {
      const ColmapRigRun rig = CalibrateColmapRig(
          inputs,
          cameras,
          ColmapReferenceCamera(cameras, flag_set.reference_camera));
      nlohmann::json echo = ProjectFlagsEcho(inputs);
      return ColmapRigToJson(rig, RigCalibrationOf(rig, "odomcal colmap", echo))
          .dump();
    }
    if (!flag_set.reference_camera.empty()) {
      throw std::invalid_argument(
          "reference_camera: the project has one camera; the keyword is for "
          "a project with several");
    }
    const ColmapCalibrationRun run = CalibrateColmapProject(inputs);
    // The JSON of `odomcal colmap`, with the echo of these options.
    return ColmapCalibrationToJson(
               run, ProjectReportContext(inputs, run, "odomcal colmap"))
        .dump();
  }));
}

py::object ReconstructAndCalibrateFolder(const py::object& image_path,
                                         const py::object& odometry,
                                         const py::object& workspace_path,
                                         const py::object& progress,
                                         const py::kwargs& keywords) {
  RunFlagSet flag_set;
  std::vector<std::pair<const char*, py::object>> named = {
      {"workspace_path", workspace_path}};
  if (!image_path.is_none()) named.emplace_back("image_path", image_path);
  if (!odometry.is_none()) named.emplace_back("odometry", odometry);
  ParseKeywords(flag_set.Parser(), WithArguments(keywords, named));
  const bool from_bag = !flag_set.bag_path.empty();
  const bool timestamps_given = keywords.contains("image_timestamps");
  if (from_bag &&
      (!image_path.is_none() || !odometry.is_none() || timestamps_given)) {
    throw py::value_error(
        "bag: gives the images, their times and the odometry: drop "
        "image_path, odometry and image_timestamps");
  }
  if (!from_bag && (image_path.is_none() || odometry.is_none())) {
    throw py::type_error(
        "reconstruct_and_calibrate: give image_path and odometry, or bag");
  }
  FinishProjectFlags(flag_set.flags, &flag_set.options.project);
  if (!progress.is_none() && !PyCallable_Check(progress.ptr())) {
    throw py::type_error(
        "progress: expected a callable or None, got " +
        std::string(py::str(py::type::of(progress).attr("__name__"))));
  }
  ReconstructionOptions& options = flag_set.options;
  return DictFromJson(ReportingErrors([&] {
    nlohmann::json bag_echo = {
        {"inputs", {{"bag", nullptr}}},
        {"options", {{"bag", nlohmann::json::object()}}}};
    EchoOptions(
        BagTopicFlags(), flag_set.bag_options, &bag_echo["options"]["bag"]);
    if (from_bag) {
      bag_echo["inputs"]["bag"] = flag_set.bag_path;
      std::ostringstream lines;  // the library prints nothing
      ExtractBagForRun(flag_set.bag_path,
                       keywords.contains("camera_params"),
                       &flag_set.bag_options,
                       &options,
                       lines);
    }
    ProgressCallback callback;
    if (!progress.is_none()) {
      callback = [&progress](const PipelineProgress& step) {
        py::gil_scoped_acquire gil;
        progress(step.stage, step.num_stages, step.fraction, step.message);
      };
    }
    py::gil_scoped_release no_gil;  // COLMAP takes minutes
    const ReconstructionResult result =
        ReconstructAndCalibrate(options, callback);
    // As `odomcal run` echoes it: the model and database the pipeline made
    // (null when it refused the drive before COLMAP) and the run's flags.
    ColmapCalibrationInputs calibrated = options.project;
    calibrated.model_path = result.model_path;
    calibrated.database_path = result.database_path;
    nlohmann::json echo = RunResultFlagsEcho(options, result);
    echo["inputs"]["bag"] = bag_echo["inputs"]["bag"];
    echo["options"]["bag"] = bag_echo["options"]["bag"];
    return ColmapCalibrationToJson(
               result.calibration,
               ProjectReportContext(
                   calibrated, result.calibration, "odomcal run", echo))
        .dump();
  }));
}

// odomcal.extract: `odomcal extract` as a call; its summary as a dict.
py::object Extract(const py::object& bag_path,
                   const py::object& output_path,
                   const py::kwargs& keywords) {
  ExtractFlagSet flag_set;
  ParseKeywords(
      flag_set.Parser(),
      WithArguments(keywords,
                    {{"bag", bag_path}, {"output_path", output_path}}));
  return DictFromJson(ReportingErrors([&] {
    std::ostringstream lines;  // the library prints nothing
    const bag::BagExtractionSummary summary =
        ExtractBagPrinting(flag_set.bag_path, flag_set.options, lines);
    const auto topic = [](const bag::TopicExtractionSummary& t) {
      return nlohmann::json{{"topic", t.topic},
                            {"type", t.type},
                            {"messages", t.messages},
                            {"used", t.used},
                            {"duplicate_stamps", t.duplicate_stamps},
                            {"first_stamp_ns", t.first_stamp_ns},
                            {"last_stamp_ns", t.last_stamp_ns},
                            {"rate_hz", t.rate_hz},
                            {"mean_abs_header_minus_receive_s",
                             t.mean_abs_header_minus_receive_s}};
    };
    const fs::path out(flag_set.options.output_folder);
    const bag::CameraExtractionSummary& camera = summary.cameras.front();
    const auto [model, params] = ExtractedCamera(camera);
    nlohmann::json result = {
        {"images", topic(camera.images)},
        {"odometry", topic(summary.odometry)},
        {"image_path", (out / "images").string()},
        {"image_timestamps", (out / "image_timestamps.csv").string()},
        {"odometry_path", ExtractedOdometryPath(flag_set.options, summary)},
        {"planar", summary.planar},
        {"bag_time", bag::BagTimeName(summary.time)},
        {"camera_model",
         model.empty() ? nlohmann::json() : nlohmann::json(model)},
        {"camera_params",
         params.empty() ? nlohmann::json() : nlohmann::json(params)},
        {"warnings", summary.warnings}};
    if (!camera.camera_info.topic.empty()) {
      result["camera_info"] = topic(camera.camera_info);
    }
    return result.dump();
  }));
}

// The keywords of `app` with their defaults and help, leaving out `skip`
// (a function's own parameters).
std::string KeywordHelp(const CLI::App& app,
                        const std::vector<std::string>& skip) {
  std::string help;
  for (const CLI::Option* option : app.get_options()) {
    const std::string name = option->get_lnames().empty()
                                 ? std::string()
                                 : option->get_lnames().front();
    if (name.empty() || name == "help") continue;
    if (std::find(skip.begin(), skip.end(), name) != skip.end()) continue;
    help += "    " + name;
    if (option->get_expected_max() == 0) {
      help += "=False";
    } else if (!option->get_default_str().empty()) {
      help += "=" + option->get_default_str();
    }
    help += ": " + KeywordMessage(option->get_description()) + "\n";
  }
  return help;
}

}  // namespace
}  // namespace odomcal

PYBIND11_MODULE(odomcal, module) {
  module.doc() =
      "odomcal: camera-to-odometry extrinsic (odom_from_cam) and metric scale "
      "from a camera trajectory, a COLMAP project or an image folder, and "
      "wheel odometry. See docs/python.md.";
  module.attr("__version__") = ODOMCAL_VERSION;
  static const std::string calibrate_doc =
      "calibrate(camera_poses, odometry, **options) -> dict\n\n"
      "Runs `odomcal calibrate` and returns its result JSON as a dict\n"
      "(docs/result_schema.md). Check result['status'] == 'success'.\n\n"
      "camera_poses: world_from_cam, a TUM file path or an (N, 8) array\n"
      "    [t, tx, ty, tz, qx, qy, qz, qw] (quaternion scalar LAST), or a "
      "pair\n"
      "    (times, values) of int64 nanoseconds and an (N, 7) array, or a "
      "list\n"
      "    of these, one per SfM segment with its own scale; or a dict\n"
      "    {name: poses} of several cameras, each calibrated against the\n"
      "    odometry (`--camera NAME=PATH`; reference_camera= names the top\n"
      "    level's), adding 'cameras' and 'camera_pairs' to the result.\n"
      "odometry: origin_from_odom, a file path (CSV t,x,y,yaw or TUM), an\n"
      "    (M, 4) array [t, x, y, yaw] (m, rad) or (M, 8) TUM array, or a "
      "pair\n"
      "    (times, values) of int64 nanoseconds and an (M, 3) or (M, 7) "
      "array.\n"
      "Times: column 0 in camera_time_unit / odometry_time_unit (default s),\n"
      "    as float64, rounded to integer nanoseconds; the times of a pair\n"
      "    are integer nanoseconds, exact, whatever the unit keywords say.\n"
      "Raises TypeError for an unknown keyword or a wrong argument type and\n"
      "ValueError for bad values, files or arrays.\n\n"
      "options (the calibrate command's flags, with their defaults):\n" +
      [] {
        odomcal::CalibrateFlags flag_set;
        return odomcal::KeywordHelp(flag_set.app, {});
      }();
  module.def("calibrate",
             &odomcal::Calibrate,
             py::arg("camera_poses"),
             py::arg("odometry"),
             calibrate_doc.c_str());
  static const std::string project_doc =
      "calibrate_project(model_path, odometry, **options) -> dict\n\n"
      "Runs `odomcal colmap` on an existing COLMAP project without writing\n"
      "anything and returns its calibration.json as a dict, with the\n"
      "'colmap' section (docs/result_schema.md).\n\n"
      "model_path: a COLMAP sparse model folder (binary or text), or the\n"
      "    mapper's output folder with sub-models 0, 1, ...\n"
      "odometry: the odometry file (CSV t,x,y,yaw or TUM).\n"
      "Image times come from image_timestamps (CSV image_name,timestamp)\n"
      "or from numeric image file names.\n"
      "Raises TypeError / ValueError as calibrate does.\n\n"
      "options (`odomcal colmap`'s flags, with their defaults):\n" +
      [] {
        odomcal::ProjectFlagSet flag_set;
        return odomcal::KeywordHelp(flag_set.app, {"model_path", "odometry"});
      }();
  module.def("calibrate_project",
             &odomcal::CalibrateProject,
             py::arg("model_path"),
             py::arg("odometry"),
             project_doc.c_str());
  static const std::string run_doc =
      "reconstruct_and_calibrate(image_path, odometry, workspace_path,\n"
      "                          progress=None, **options) -> dict\n"
      "reconstruct_and_calibrate(bag=PATH, workspace_path=WS, ...) -> dict\n\n"
      "Runs `odomcal run`'s pipeline (frame selection, COLMAP in\n"
      "workspace_path, calibration; COLMAP must be on the PATH or given as\n"
      "colmap_path) and returns its calibration.json as a dict. Writes only\n"
      "COLMAP's files in workspace_path, not odomcal's reports. A drive whose\n"
      "odometry cannot determine the calibration is refused before COLMAP:\n"
      "the dict's status says why (force=True runs COLMAP anyway).\n\n"
      "progress: None or a callable(stage, num_stages, fraction, message).\n"
      "Raises TypeError / ValueError as calibrate does, RuntimeError when\n"
      "COLMAP fails.\n\n"
      "options (`odomcal run`'s flags, with their defaults):\n" +
      [] {
        odomcal::RunFlagSet flag_set;
        return odomcal::KeywordHelp(
            flag_set.app, {"image_path", "odometry", "workspace_path"});
      }();
  module.def("reconstruct_and_calibrate",
             &odomcal::ReconstructAndCalibrateFolder,
             py::arg("image_path") = py::none(),
             py::arg("odometry") = py::none(),
             py::arg("workspace_path") = py::none(),
             py::arg("progress") = py::none(),
             run_doc.c_str());
  static const std::string extract_doc =
      "extract(bag, output_path, **options) -> dict\n\n"
      "Runs `odomcal extract`: writes a robot bag's images (images/),\n"
      "image_timestamps.csv, odometry.csv (or odometry.tum, wheels.csv) and\n"
      "camera.txt into output_path (created, must be empty) and returns\n"
      "what it wrote: the topics used, the files, camera_model and\n"
      "camera_params (None without CameraInfo), warnings.\n\n"
      "bag: a ROS 1 bag, or a ROS 2 bag (folder with metadata.yaml, .db3 or\n"
      "    .mcap).\n"
      "Raises ValueError naming the keyword or file.\n\n"
      "options (`odomcal extract`'s flags, with their defaults):\n" +
      [] {
        odomcal::ExtractFlagSet flag_set;
        return odomcal::KeywordHelp(flag_set.app, {"bag", "output_path"});
      }();
  module.def("extract",
             &odomcal::Extract,
             py::arg("bag"),
             py::arg("output_path"),
             extract_doc.c_str());
}
