// The Python module `odomcal`: odomcal.calibrate(camera_poses=...,
// odometry=...,
// **options) runs the `odomcal calibrate` pipeline on files or numpy arrays
// and returns the result JSON (docs/result_schema.md) as a dict.
//
// The keywords are the calibrate command's flags: the module builds the same
// CLI11 app (AddCalibrationFlags) and parses "--name=value" made from the
// keywords, so defaults, checks and the nearest-keyword suggestion for a typo
// are the CLI's. Errors are raised, never printed: TypeError for an unknown
// keyword or an argument of the wrong type, ValueError for bad values, files
// and arrays, each with the CLI's one-line message in keyword terms
// ("--max_odometry_gap_s" reads "max_odometry_gap_s").
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/plugin/calibrate_command.h"
#include "odomcal/plugin/calibration_report.h"
#include "odomcal/plugin/cli_flags.h"
#include "odomcal/plugin/command_line.h"
#include "odomcal/python/array_trajectory.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cctype>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace py = pybind11;

namespace odomcal {
namespace {

constexpr const char* kCommand = "odomcal.calibrate";

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

// One calibrate app: the flags shared with the CLI's `calibrate` command.
struct FlagApp {
  CLI::App app{"", kCommand};
  CalibrateInputs inputs;
  FlagApp() { AddCalibrationFlags(&app, &inputs); }
};

// "--name=value" for each keyword; a flag (no value) for True.
std::vector<std::string> ArgumentsFromKeywords(const CLI::App& app,
                                               const py::kwargs& keywords) {
  std::vector<std::string> arguments = {kCommand};
  for (const auto& [key, value] : keywords) {
    const std::string name = py::str(key);
    if (value.is_none()) continue;
    if (name == "help") {
      throw py::type_error(
          "unknown keyword help (see help(odomcal.calibrate))");
    }
    const CLI::Option* option = app.get_option_no_throw("--" + name);
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
    if (py::isinstance<py::str>(value)) {
      text = value.cast<std::string>();
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

void ParseKeywords(FlagApp* flag_app, const py::kwargs& keywords) {
  const std::vector<std::string> arguments =
      ArgumentsFromKeywords(flag_app->app, keywords);
  std::vector<const char*> argv;
  for (const std::string& argument : arguments)
    argv.push_back(argument.c_str());
  const std::string error =
      FlagError(&flag_app->app, static_cast<int>(argv.size()), argv.data());
  if (error.empty()) return;
  if (IsUnknownKeyword(error)) throw py::type_error(KeywordMessage(error));
  throw py::value_error(KeywordMessage(error));
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

bool IsPath(const py::handle& object) {
  return py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__");
}

std::string PathText(const py::handle& object) {
  return py::str(py::module_::import("os").attr("fspath")(object));
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
  throw py::type_error(
      name + ": expected a file path or a numpy array, got " +
      std::string(py::str(py::type::of(object).attr("__name__"))));
}

// camera_poses: a path or array, or a list of them (one per SfM segment).
std::vector<Input> CameraInputs(const py::object& camera_poses) {
  if (py::isinstance<py::list>(camera_poses) ||
      py::isinstance<py::tuple>(camera_poses)) {
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

py::object Calibrate(const py::object& camera_poses,
                     const py::object& odometry,
                     const py::kwargs& keywords) {
  FlagApp flag_app;
  ParseKeywords(&flag_app, keywords);
  CalibrateInputs& inputs = flag_app.inputs;
  std::string json_text;
  try {
    const std::vector<Input> cameras_in = CameraInputs(camera_poses);
    const Input odometry_in = InputFrom(odometry, "odometry");
    inputs.association.Check();
    inputs.calibration.Check();
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
                         : ReadOdometry(odometry_in.path,
                                        inputs.odometry_format,
                                        inputs.odometry_time_unit,
                                        inputs.odometry_time_unit_given);
    // The calibrate command's pipeline and writer: the same JSON.
    const CalibrationRun run = CalibrateTrajectories(
        cameras, odometry_trajectory, inputs, "odomcal calibrate");
    json_text = CalibrationToJson(run.result, run.context).dump();
  } catch (const py::builtin_exception&) {
    throw;  // already a TypeError or ValueError
  } catch (const std::invalid_argument& error) {
    throw py::value_error(KeywordMessage(error.what()));
  } catch (const std::runtime_error& error) {
    throw py::value_error(KeywordMessage(error.what()));
  }
  return py::module_::import("json").attr("loads")(json_text);
}

// The keywords with their defaults and help, from the CLI's flags.
std::string KeywordHelp() {
  FlagApp flag_app;
  std::string help;
  for (const CLI::Option* option : flag_app.app.get_options()) {
    const std::string name = option->get_lnames().empty()
                                 ? std::string()
                                 : option->get_lnames().front();
    if (name.empty() || name == "help") continue;
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
      "from a camera trajectory and wheel odometry. See docs/python.md.";
  module.attr("__version__") = ODOMCAL_VERSION;
  const std::string doc =
      "calibrate(camera_poses, odometry, **options) -> dict\n\n"
      "Runs `odomcal calibrate` and returns its result JSON as a dict\n"
      "(docs/result_schema.md). Check result['status'] == 'success'.\n\n"
      "camera_poses: world_from_cam, a TUM file path or an (N, 8) array\n"
      "    [t, tx, ty, tz, qx, qy, qz, qw] (quaternion scalar LAST), or a "
      "list\n"
      "    of them, one per SfM segment with its own scale.\n"
      "odometry: origin_from_odom, a file path (CSV t,x,y,yaw or TUM) or an\n"
      "    (M, 4) array [t, x, y, yaw] (m, rad) or (M, 8) TUM array.\n"
      "Times: column 0 in camera_time_unit / odometry_time_unit (default s),\n"
      "    as float64, rounded to integer nanoseconds.\n"
      "Raises TypeError for an unknown keyword or a wrong argument type and\n"
      "ValueError for bad values, files or arrays.\n\n"
      "options (the calibrate command's flags, with their defaults):\n" +
      odomcal::KeywordHelp();
  module.def("calibrate",
             &odomcal::Calibrate,
             py::arg("camera_poses"),
             py::arg("odometry"),
             doc.c_str());
}
