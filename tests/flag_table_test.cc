// Every flag of the commands, three ways (plugin/options/option_table.h):
// listed by `odomcal help <command>`, documented in docs/cli.md with the same
// default, and echoed in the result JSON's `inputs`/`options` with the value
// given on the command line; and vice versa, every documented flag and every
// echoed key is a flag of the command.

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/test_support.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/tests/odomcal_process.h"
#include "odomcal/tests/scratch_folder_test.h"
#include "odomcal/tests/test_files.h"

#include <sys/stat.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A flag as `odomcal help` prints it.
struct HelpFlag {
  bool takes_value = false;
  bool required = false;
  std::string default_value;  // "" when none is shown
};

std::string Trimmed(const std::string& text) {
  const size_t begin = text.find_first_not_of(' ');
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(' ') - begin + 1);
}

// "--name" -> how it is listed, from `odomcal help <command>` (lines
// "  --name TYPE:CHECK=default  help"); --help left out.
std::map<std::string, HelpFlag> HelpFlags(const std::string& command) {
  const CommandResult help = RunOdomcal({"help", command});
  EXPECT_EQ(help.exit_code, 0) << help.err;
  std::map<std::string, HelpFlag> flags;
  std::vector<std::string> lines;
  std::istringstream text(help.out);
  for (std::string line; std::getline(text, line);) lines.push_back(line);
  // CLI11 pads a flag's listing to 30 columns and starts its help there; a
  // listing of 30 or more has its help on the next line, indented 30.
  constexpr size_t kColumn = 30;
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string& line = lines[i];
    if (line.rfind("  --", 0) != 0) continue;  // not a flag ("-h,--help")
    const bool help_on_next_line =
        i + 1 < lines.size() &&
        lines[i + 1].rfind(std::string(kColumn, ' '), 0) == 0;
    const std::string listing =
        Trimmed(help_on_next_line ? line : line.substr(0, kColumn));
    const size_t space = listing.find(' ');
    const std::string name = listing.substr(0, space);
    HelpFlag flag;
    if (space != std::string::npos) {
      const std::string type = listing.substr(space + 1);
      flag.takes_value = true;
      flag.required = type.find("REQUIRED") != std::string::npos;
      const size_t equals = type.rfind('=');
      if (equals != std::string::npos) {
        flag.default_value = type.substr(equals + 1);
      }
    }
    flags[name] = flag;
  }
  EXPECT_FALSE(flags.empty()) << help.out;
  return flags;
}

// docs/cli.md's flag tables: "## " section heading -> "--name" -> the
// default column (backticks removed).
std::map<std::string, std::map<std::string, std::string>> DocumentedFlags() {
  std::map<std::string, std::map<std::string, std::string>> sections;
  std::istringstream lines(ReadFile(ODOMCAL_CLI_DOC_PATH));
  std::string section;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("## ", 0) == 0) {
      section = line.substr(3);
      continue;
    }
    if (line.rfind("| `--", 0) != 0) continue;
    std::vector<std::string> cells;
    std::string cell;
    for (size_t i = 1; i < line.size(); ++i) {
      if (line[i] == '|' && line[i - 1] != '\\') {
        cells.push_back(Trimmed(cell));
        cell.clear();
      } else if (line[i] != '`') {
        cell += line[i];
      }
    }
    if (cells.size() < 3) {
      ADD_FAILURE() << "not a flag row: " << line;
      continue;
    }
    EXPECT_EQ(sections[section].count(cells[0]), 0u)
        << cells[0] << " documented twice in section " << section;
    sections[section][cells[0]] = cells[1];
  }
  return sections;
}

constexpr char kCalibrationSection[] =
    "Calibration flags (every command that calibrates)";
constexpr char kProjectSection[] = "Project flags (`colmap` and `run`)";
constexpr char kBagSection[] = "Bag flags (`inspect`, `extract` and `run`)";

// The docs/cli.md sections that together list a command's flags.
std::vector<std::string> SectionsOf(const std::string& command) {
  const std::string own = "`odomcal " + command + "`";
  if (command == "calibrate" || command == "demo") {
    return {kCalibrationSection, own};
  }
  if (command == "colmap") return {kCalibrationSection, kProjectSection, own};
  if (command == "run") {
    return {kCalibrationSection, kProjectSection, kBagSection, own};
  }
  if (command == "inspect" || command == "extract") return {kBagSection};
  return {own};
}

TEST(FlagTable,
     EveryFlagIsDocumentedWithItsDefaultAndEveryDocumentedFlagExists) {
  const auto documented = DocumentedFlags();
  const std::vector<std::string> commands = {
      "calibrate", "colmap", "run", "demo", "render", "simulate"};
  std::set<std::string> sections_of_commands = {kBagSection};
  for (const std::string& command : commands) {
    for (const std::string& section : SectionsOf(command)) {
      sections_of_commands.insert(section);
    }
  }
  for (const auto& [section, rows] : documented) {
    EXPECT_TRUE(sections_of_commands.count(section))
        << "flags documented in section ## " << section
        << ", which is no command's: " << rows.begin()->first;
  }
  for (const std::string& command : commands) {
    SCOPED_TRACE(command);
    const std::map<std::string, HelpFlag> flags = HelpFlags(command);
    std::map<std::string, std::string> docs;
    for (const std::string& section : SectionsOf(command)) {
      ASSERT_TRUE(documented.count(section)) << "no section ## " << section;
      for (const auto& [flag, default_value] : documented.at(section)) {
        EXPECT_EQ(docs.count(flag), 0u) << flag << " documented twice";
        docs[flag] = default_value;
      }
    }
    for (const auto& [flag, listed] : flags) {
      if (flag == "--help") continue;
      if (!docs.count(flag)) {
        ADD_FAILURE() << flag << " is not documented in docs/cli.md";
        continue;
      }
      const std::string& doc = docs.at(flag);
      if (listed.required) {
        EXPECT_EQ(doc, "required") << flag;
      } else if (!listed.takes_value) {
        EXPECT_EQ(doc, "off") << flag;
      } else if (!listed.default_value.empty()) {
        EXPECT_EQ(doc, listed.default_value) << flag;
      } else {
        EXPECT_FALSE(doc.empty()) << flag << ": say what no value means";
      }
    }
    for (const auto& [flag, doc] : docs) {
      EXPECT_TRUE(flags.count(flag)) << flag << " is documented but odomcal "
                                     << command << " has no such flag";
    }
  }
}

// Flags that say where and whether to write the outputs, not what is
// computed: not echoed.
const std::set<std::string> kNotEchoed = {"--help",
                                          "--output",
                                          "--output_path",
                                          "--workspace_path",
                                          "--overwrite",
                                          "--quiet"};
// Echo keys that are no flag's of `command`: `colmap` and `run` echo the
// sub-models they read as camera_poses, and `run` the model and database of
// its workspace that it calibrates as `colmap` would.
std::set<std::string> EchoOnlyKeys(const std::string& command) {
  std::set<std::string> keys = {"command",
                                "camera_pose_convention",
                                "camera_poses",
                                "max_odometry_gap_automatic"};
  if (command == "run") keys.insert({"model_path", "database_path"});
  return keys;
}

// "--name" -> the echo key the flag's value is under.
std::string EchoKey(const std::string& flag) {
  if (flag == "--no_refine") return "refine";
  if (flag == "--camera") return "cameras";
  return flag.substr(2);
}

// The echo's keys (`inputs`, `options`, and the objects in them) with their
// values.
std::map<std::string, json> EchoedValues(const json& result) {
  std::map<std::string, json> values;
  for (const char* part : {"inputs", "options"}) {
    for (const auto& [key, value] : result.at(part).items()) {
      if (value.is_object()) {
        for (const auto& [inner, inner_value] : value.items()) {
          EXPECT_EQ(values.count(inner), 0u) << inner << " echoed twice";
          values[inner] = inner_value;
        }
      } else {
        EXPECT_EQ(values.count(key), 0u) << key << " echoed twice";
        values[key] = value;
      }
    }
  }
  return values;
}

// A value of a flag and the echo it must give.
struct FlagValue {
  std::string argument;  // "" for a flag without value
  json echo;
};

// Every flag of `command` is given with `values` (a non-default value each,
// but for kNotEchoed and `not_given`); the result JSON echoes each value, and
// each echoed key is a flag. `other_form`: flags of the command's other form
// (calibrate's --camera_poses or --camera), neither given nor echoed.
void ExpectEchoOfEveryFlag(const std::string& command,
                           const std::map<std::string, FlagValue>& values,
                           const std::set<std::string>& not_given,
                           const json& result,
                           const std::set<std::string>& other_form = {}) {
  SCOPED_TRACE(command);
  const std::map<std::string, HelpFlag> flags = HelpFlags(command);
  const std::map<std::string, json> echoed = EchoedValues(result);
  for (const auto& [flag, listed] : flags) {
    if (kNotEchoed.count(flag) || other_form.count(flag)) continue;
    const std::string key = EchoKey(flag);
    if (!echoed.count(key)) {
      ADD_FAILURE() << flag << " is not echoed (no key " << key << ")";
      continue;
    }
    if (not_given.count(flag)) continue;
    if (!values.count(flag)) {
      ADD_FAILURE() << flag << ": the test gives it no value";
      continue;
    }
    const json& expected = values.at(flag).echo;
    const json& echo = echoed.at(key);
    if (expected.is_number_float()) {
      EXPECT_NEAR(echo.get<double>(), expected.get<double>(), 1e-12) << flag;
    } else {
      EXPECT_EQ(echo, expected) << flag;
    }
    if (listed.takes_value && !listed.default_value.empty()) {
      EXPECT_NE(values.at(flag).argument, listed.default_value)
          << flag << ": give a value other than the default";
    }
  }
  for (const auto& [key, value] : echoed) {
    if (EchoOnlyKeys(command).count(key)) continue;
    const std::string flag = key == "refine"    ? "--no_refine"
                             : key == "cameras" ? "--camera"
                                                : "--" + key;
    EXPECT_TRUE(flags.count(flag))
        << "echo key " << key << " is no flag of odomcal " << command;
  }
}

// "1700000000.020000000" -> the same time as an integer in a unit with
// `digits` decimals of a second ("1700000000020" for ms).
std::string TimeInUnit(const std::string& seconds, size_t digits) {
  const size_t point = seconds.find('.');
  return seconds.substr(0, point) + seconds.substr(point + 1, digits);
}

// Rewrites the first field of every data line (comma or blank separated).
void RewriteTimes(const fs::path& path, size_t digits, char separator) {
  std::istringstream lines(ReadFile(path));
  std::string out;
  for (std::string line; std::getline(lines, line);) {
    const size_t end = line.find(separator);
    if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0])) &&
        end != std::string::npos) {
      line = TimeInUnit(line.substr(0, end), digits) + line.substr(end);
    }
    out += line + "\n";
  }
  WriteFile(path, out);
}

// WriteDrive's odometry is a pose log, with which --wheel_ticks_per_m is
// refused: its echo is checked with a tick log in
// InputUnits.WheelTicksCalibrateWithTicksPerMetre.
const std::set<std::string> kNoTickLog = {"--wheel_ticks_per_m"};

class FlagEcho : public ScratchFolderTest {
 protected:
  static constexpr int kImages = 50;

  FlagEcho() : ScratchFolderTest("odomcal_flag_echo_") {}

  static std::string ImageName(int index) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06d.png", index);
    return name;
  }

  // A 60 s simulated drive: odometry.csv (times in us), camera.tum (ms),
  // images/ with kImages files every 1 s and image_timestamps.csv (ms).
  SimulatedDrive WriteDrive(bool straight) const {
    DriveSimulatorOptions options;
    options.seed = 3;
    options.straight_only = straight;
    const SimulatedDrive drive = SimulateDrive(options);
    WriteOdometryCsv(drive.odometry, Path("odometry.csv"));
    RewriteTimes(Path("odometry.csv"), 6, ',');
    WriteTumTrajectory(drive.camera, Path("camera.tum"));
    RewriteTimes(Path("camera.tum"), 3, ' ');
    fs::create_directories(dir_ / "images");
    std::string stamps;
    for (int i = 0; i < kImages; ++i) {
      WriteFile(dir_ / "images" / ImageName(i), "x");
      stamps +=
          ImageName(i) + "," +
          TimeInUnit(
              FormatTimestampSeconds(drive.camera.poses[10 * i + 10].stamp_ns),
              3) +
          "\n";
    }
    WriteFile(Path("image_timestamps.csv"), stamps);
    return drive;
  }

  // model/ (the drive's camera poses of every image) and db/database.db
  // (COLMAP's cameras and images tables; its folder is an input too).
  void WriteProject(const SimulatedDrive& drive) const {
    ColmapModel model;
    model.cameras[1] = MakeColmapCamera(
        1, ColmapCameraModel::kPinhole, 320, 240, {260, 260, 160, 120});
    for (int i = 0; i < kImages; ++i) {
      ColmapImage image;
      image.image_id = static_cast<uint32_t>(i + 1);
      image.camera_id = 1;
      image.name = ImageName(i);
      image.cam_from_world =
          Inverse(drive.camera.poses[10 * i + 10].world_from_sensor);
      model.images[image.image_id] = image;
    }
    fs::create_directories(dir_ / "model");
    WriteColmapModel(model, Path("model"), ColmapFormat::kBinary);
    fs::create_directories(dir_ / "db");
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(Path("db/database.db").c_str(), &db), SQLITE_OK);
    std::string sql =
        "CREATE TABLE cameras (camera_id INTEGER PRIMARY KEY NOT NULL, model "
        "INTEGER NOT NULL, width INTEGER NOT NULL, height INTEGER NOT NULL, "
        "params BLOB, prior_focal_length INTEGER NOT NULL);"
        "CREATE TABLE images (image_id INTEGER PRIMARY KEY NOT NULL, name "
        "TEXT NOT NULL UNIQUE, camera_id INTEGER NOT NULL);"
        "INSERT INTO cameras VALUES (1, 1, 320, 240, NULL, 1);";
    for (int i = 0; i < kImages; ++i) {
      sql += "INSERT INTO images VALUES (" + std::to_string(i + 1) + ", '" +
             ImageName(i) + "', 1);";
    }
    EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr),
              SQLITE_OK)
        << sqlite3_errmsg(db);
    sqlite3_close(db);
  }

  // Non-default values of the calibration flags (docs/cli.md, "Calibration
  // flags"), for the files WriteDrive writes; but for --wheel_ticks_per_m
  // (kNoTickLog), which needs a wheel-tick log.
  static std::map<std::string, FlagValue> CalibrationValues() {
    return {
        {"--odometry_format", {"csv", "csv"}},
        {"--camera_time_unit", {"ms", "ms"}},
        {"--odometry_time_unit", {"us", "us"}},
        {"--camera_time_offset_s", {"0.0005", 0.0005}},
        {"--max_odometry_gap_s", {"0.3", 0.3}},
        {"--keyframe_min_rotation_deg", {"4", 4.0}},
        {"--keyframe_min_translation_m", {"0.08", 0.08}},
        {"--method", {"als", "als"}},
        {"--alsp_projection", {"length_preserving", "length_preserving"}},
        {"--no_refine", {"", false}},
        {"--fixed_translation_z_m", {"0.25", 0.25}},
        {"--translation_z_prior_sigma_m", {"0.5", 0.5}},
        {"--ransac", {"off", false}},
        {"--ransac_max_rotation_error_deg", {"1.5", 1.5}},
        {"--ransac_max_translation_error_m", {"0.03", 0.03}},
        {"--ransac_max_translation_error_rel", {"0.06", 0.06}},
        {"--ransac_min_inlier_ratio", {"0.4", 0.4}},
        {"--ransac_seed", {"7", 7}},
        {"--robust_loss", {"huber", "huber"}},
        {"--robust_loss_scale", {"2.5", 2.5}},
        {"--odom_yaw_sigma_deg", {"0.3", 0.3}},
        {"--odom_yaw_sigma_rel", {"0.02", 0.02}},
        {"--odom_tilt_sigma_deg", {"0.01", 0.01}},
        {"--odom_translation_sigma_m", {"0.003", 0.003}},
        {"--odom_translation_sigma_rel", {"0.02", 0.02}},
        {"--cam_rotation_sigma_deg", {"0.06", 0.06}},
        {"--cam_translation_sigma_rel", {"0.02", 0.02}},
        {"--min_rotation_deg", {"1.5", 1.5}},
        {"--max_rotation_stddev_deg", {"2.5", 2.5}},
        {"--max_translation_stddev_m", {"0.06", 0.06}},
        {"--max_scale_stddev_rel", {"0.06", 0.06}},
        {"--estimate_noise", {"off", false}},
        {"--noise_prior_weight", {"2.5", 2.5}},
        {"--estimate_time_offset", {"off", false}},
        {"--time_offset_search_s", {"0.5", 0.5}},
        {"--estimate_odometry_intrinsics", {"off", false}},
        {"--wheel_track_m", {"0.4", 0.4}},
        {"--base_frame", {"base_footprint", "base_footprint"}},
        {"--camera_frame", {"front_camera_optical", "front_camera_optical"}},
        {"--camera_body_frame", {"front_camera", "front_camera"}},
    };
  }

  // The project flags of `colmap` and `run`.
  std::map<std::string, FlagValue> ProjectValues() const {
    std::map<std::string, FlagValue> values = CalibrationValues();
    values["--odometry"] = {Path("odometry.csv"), Path("odometry.csv")};
    values["--image_timestamps"] = {Path("image_timestamps.csv"),
                                    Path("image_timestamps.csv")};
    values["--file_name_time_unit"] = {"ms", "ms"};
    values["--min_inconsistent_run_pairs"] = {"4", 4};
    values["--floor_plane"] = {"off", "off"};
    values["--odometry_height_m"] = {"0.05", 0.05};
    values["--floor_max_path_distance_m"] = {"2.5", 2.5};
    values["--floor_inlier_distance_m"] = {"0.03", 0.03};
    values["--floor_max_slope_deg"] = {"0.7", 0.7};
    values["--joint_adjustment"] = {"on", "on"};
    values["--joint_intrinsics"] = {"refined", "refined"};
    values["--joint_max_reprojection_sigmas"] = {"4", 4};
    values["--joint_jackknife_blocks"] = {"5", 5};
    return values;
  }

  static std::vector<std::string> Arguments(
      const std::string& command,
      const std::map<std::string, FlagValue>& values) {
    std::vector<std::string> arguments = {command};
    for (const auto& [flag, value] : values) {
      arguments.push_back(flag);
      if (!value.argument.empty()) arguments.push_back(value.argument);
    }
    return arguments;
  }
};

TEST_F(FlagEcho, CalibrateEchoesEveryFlag) {
  WriteDrive(/*straight=*/false);
  std::map<std::string, FlagValue> values = CalibrationValues();
  values["--camera_poses"] = {Path("camera.tum"),
                              json::array({Path("camera.tum")})};
  values["--odometry"] = {Path("odometry.csv"), Path("odometry.csv")};
  std::vector<std::string> arguments = Arguments("calibrate", values);
  arguments.insert(arguments.end(), {"--output", Path("result.json")});
  const CommandResult run = RunOdomcal(arguments);
  ASSERT_TRUE(fs::exists(Path("result.json"))) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "success") << run.out;
  ExpectEchoOfEveryFlag("calibrate",
                        values,
                        kNoTickLog,
                        result,
                        {"--camera", "--reference_camera"});

  // The same with the trajectory as a named camera of a rig.
  values.erase("--camera_poses");
  values["--camera"] = {
      "main=" + Path("camera.tum"),
      json::array({{{"name", "main"},
                    {"camera_poses", json::array({Path("camera.tum")})}}})};
  values["--reference_camera"] = {"main", "main"};
  arguments = Arguments("calibrate", values);
  arguments.insert(arguments.end(),
                   {"--output", Path("rig.json"), "--overwrite"});
  const CommandResult rig_run = RunOdomcal(arguments);
  ASSERT_TRUE(fs::exists(Path("rig.json"))) << rig_run.out << rig_run.err;
  const json rig = json::parse(ReadFile(Path("rig.json")));
  EXPECT_EQ(rig["status"], "success") << rig_run.out;
  ExpectEchoOfEveryFlag(
      "calibrate", values, kNoTickLog, rig, {"--camera_poses"});
}

TEST_F(FlagEcho, ColmapEchoesEveryFlag) {
  WriteProject(WriteDrive(/*straight=*/false));
  std::map<std::string, FlagValue> values = ProjectValues();
  values["--model_path"] = {Path("model"), Path("model")};
  values["--database_path"] = {Path("db/database.db"), Path("db/database.db")};
  std::vector<std::string> arguments = Arguments("colmap", values);
  arguments.insert(arguments.end(), {"--output_path", Path("out")});
  const CommandResult run = RunOdomcal(arguments);
  const fs::path path = dir_ / "out" / "calibration.json";
  ASSERT_TRUE(fs::exists(path)) << run.out << run.err;
  const json result = json::parse(ReadFile(path));
  EXPECT_EQ(result["status"], "success") << run.out;
  // A project of one camera refuses --reference_camera (ColmapRigCli.*
  // checks its echo on a rig).
  ExpectEchoOfEveryFlag(
      "colmap", values, kNoTickLog, result, {"--reference_camera"});
}

// `odomcal run` on a straight drive: refused before COLMAP (exit 3) with
// calibration.json, which echoes the flags. --force would run COLMAP, so it
// is the one flag not given (its default is echoed).
TEST_F(FlagEcho, RunEchoesEveryFlag) {
  WriteDrive(/*straight=*/true);
  const fs::path colmap = dir_ / "colmap";
  WriteFile(colmap, "#!/bin/sh\nexit 1\n");
  ::chmod(colmap.c_str(), 0755);
  std::map<std::string, FlagValue> values = ProjectValues();
  values["--image_path"] = {Path("images"), Path("images")};
  values["--camera_model"] = {"SIMPLE_PINHOLE", "SIMPLE_PINHOLE"};
  values["--camera_params"] = {"260,160,120", "260,160,120"};
  values["--matcher"] = {"sequential", "sequential"};
  values["--spatial_neighbors"] = {"9", 9};
  values["--sequential_overlap"] = {"11", 11};
  values["--max_num_features"] = {"1024", 1024};
  values["--num_threads"] = {"1", 1};
  values["--frame_min_translation_m"] = {"0.04", 0.04};
  values["--frame_min_rotation_deg"] = {"2.5", 2.5};
  values["--mapper_attempts"] = {"2", 2};
  values["--rematch"] = {"off", false};
  values["--chunk_images"] = {"150", 150};
  values["--colmap_path"] = {colmap.string(), colmap.string()};
  values["--mapper"] = {"global", "global"};
  values["--glomap_path"] = {Path("glomap"), Path("glomap")};
  std::vector<std::string> arguments = Arguments("run", values);
  arguments.insert(arguments.end(), {"--workspace_path", Path("ws")});
  const CommandResult run = RunOdomcal(arguments);
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  const fs::path path = dir_ / "ws" / "calibration.json";
  ASSERT_TRUE(fs::exists(path)) << run.out << run.err;
  const json result = json::parse(ReadFile(path));
  // A bag replaces --image_path, --odometry and --image_timestamps: its
  // flags are echoed with their defaults (run --bag: RenderedEndToEnd).
  ExpectEchoOfEveryFlag("run",
                        values,
                        {"--force",
                         "--wheel_ticks_per_m",
                         "--bag",
                         "--image_topic",
                         "--odometry_topic",
                         "--joint_states_topic",
                         "--camera_info_topic",
                         "--bag_time",
                         "--wheel_radius_m",
                         "--left_wheel_joint",
                         "--right_wheel_joint",
                         "--rig"},
                        result,
                        // With --rig only (RigRun.*).
                        {"--reference_camera"});
  EXPECT_TRUE(result["inputs"]["bag"].is_null());
  EXPECT_EQ(result["inputs"]["rig"], false);
  EXPECT_EQ(result["options"]["bag"]["bag_time"], "header");
  EXPECT_EQ(result["options"]["run"]["force"], false);
}

}  // namespace
}  // namespace odomcal
