// The command line itself: unknown flags with the nearest valid one, stray
// arguments, `odomcal help <command>`, and option values refused with
// messages that name the flag and print numbers readably (docs/robustness.md,
// "Command line"). The CLI tests run the built odomcal with fork/exec.

#include "odomcal/plugin/cli/command_line.h"

#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/cli/command_flags.h"
#include "odomcal/tests/odomcal_process.h"

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

constexpr char kCalibrateError[] = "odomcal calibrate: error: ";
constexpr char kColmapError[] = "odomcal colmap: error: ";

class CommandLine : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           (std::string("odomcal_command_line_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "model");
    // Existing but empty inputs: every flag value is checked before they are
    // read, and a run that gets that far stops at "no data lines".
    WriteFile(dir_ / "camera.tum", "");
    WriteFile(dir_ / "odometry.csv", "");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Path(const std::string& name) const {
    return (dir_ / name).string();
  }

  std::vector<std::string> Calibrate(
      const std::vector<std::string>& extra = {}) const {
    std::vector<std::string> arguments = {"calibrate",
                                          "--camera_poses",
                                          Path("camera.tum"),
                                          "--odometry",
                                          Path("odometry.csv"),
                                          "--output",
                                          Path("result.json")};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return arguments;
  }

  // `odomcal run` on a folder without images: its flags are checked first.
  std::vector<std::string> Run(
      const std::vector<std::string>& extra = {}) const {
    std::vector<std::string> arguments = {"run",
                                          "--image_path",
                                          Path("model"),
                                          "--workspace_path",
                                          Path("ws"),
                                          "--odometry",
                                          Path("odometry.csv")};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return arguments;
  }

  std::vector<std::string> Colmap(
      const std::vector<std::string>& extra = {}) const {
    std::vector<std::string> arguments = {"colmap",
                                          "--model_path",
                                          Path("model"),
                                          "--odometry",
                                          Path("odometry.csv"),
                                          "--output_path",
                                          Path("out")};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return arguments;
  }

  fs::path dir_;
};

TEST(NearestFlag, ForgivesDashesForUnderscoresAndCase) {
  const std::vector<std::string> flags = {
      "--model_path", "--database_path", "--output_path"};
  EXPECT_EQ(NearestFlag("--model-path", flags), "--model_path");
  EXPECT_EQ(NearestFlag("--Database-Path", flags), "--database_path");
  EXPECT_EQ(NearestFlag("-output_path", flags), "--output_path");
}

TEST(NearestFlag, PicksTheClosestByEditDistance) {
  const std::vector<std::string> flags = {"--odom_yaw_sigma_deg",
                                          "--odom_yaw_sigma_rel",
                                          "--odom_tilt_sigma_deg",
                                          "--ransac_seed"};
  EXPECT_EQ(NearestFlag("--odom_yaw_sigma_dge", flags),
            "--odom_yaw_sigma_deg");  // swap
  EXPECT_EQ(NearestFlag("--odom_yaw_sigma_re", flags),
            "--odom_yaw_sigma_rel");  // deletion
  EXPECT_EQ(NearestFlag("--odom_tilt_sigma_de", flags),
            "--odom_tilt_sigma_deg");
  EXPECT_EQ(NearestFlag("--ransac_sed", flags), "--ransac_seed");
}

TEST(NearestFlag, SuggestsTheFlagThatATypedFlagExtendsOrAbbreviates) {
  const std::vector<std::string> flags = {
      "--camera_poses", "--odometry", "--output", "--overwrite"};
  EXPECT_EQ(NearestFlag("--output_path", flags), "--output");
  EXPECT_EQ(NearestFlag("--odometry_csv", flags), "--odometry");
  EXPECT_EQ(NearestFlag("--camera", flags), "--camera_poses");
}

TEST(NearestFlag, SuggestsNothingWhenNothingIsClose) {
  const std::vector<std::string> flags = {
      "--camera_poses", "--odometry", "--output", "--no_refine"};
  EXPECT_EQ(NearestFlag("--xyzzy", flags), "");
  EXPECT_EQ(NearestFlag("--no_such_flag", flags), "");
  EXPECT_EQ(NearestFlag("--", flags), "");
  EXPECT_EQ(NearestFlag("--o", flags), "");  // too short to be a prefix
  EXPECT_EQ(NearestFlag("--output", {}), "");
}

TEST(NearestFlag, LongFlagsListsEveryFlagOfAnApp) {
  CLI::App app;
  std::string value;
  app.add_option("--first", value);
  app.add_flag("--second");
  EXPECT_EQ(LongFlags(app),
            (std::vector<std::string>{"--help", "--first", "--second"}));
}

TEST_F(CommandLine, UnknownFlagNamesTheNearestFlagBeforeMissingOnes) {
  // --output is missing too: the misspelt flag is the error worth reporting.
  ExpectBadInput(RunOdomcal({"calibrate",
                             "--output_path",
                             Path("r.json"),
                             "--camera_poses",
                             Path("camera.tum"),
                             "--odometry",
                             Path("odometry.csv")}),
                 std::string(kCalibrateError) +
                     "unknown flag --output_path (did you mean --output?)");
  ExpectBadInput(RunOdomcal({"colmap", "--model-path", Path("model")}),
                 std::string(kColmapError) +
                     "unknown flag --model-path (did you mean --model_path?)");
  // Before a bad value of a known flag, too.
  ExpectBadInput(
      RunOdomcal(
          Calibrate({"--max_odometry_gap_s", "abc", "--ransac-seed", "3"})),
      std::string(kCalibrateError) +
          "unknown flag --ransac-seed (did you mean --ransac_seed?)");
  ExpectBadInput(RunOdomcal(Calibrate({"--no_refine=yes", "--Quiet"})),
                 std::string(kCalibrateError) +
                     "unknown flag --Quiet (did you mean --quiet?)");
}

TEST_F(CommandLine, UnknownFlagWithNothingCloseHasNoSuggestion) {
  ExpectBadInput(RunOdomcal(Calibrate({"--xyzzy"})),
                 std::string(kCalibrateError) + "unknown flag --xyzzy");
  ExpectBadInput(RunOdomcal(Calibrate({"--no_such_flag=3"})),
                 std::string(kCalibrateError) + "unknown flag --no_such_flag");
}

TEST_F(CommandLine, StrayArgumentIsNamed) {
  ExpectBadInput(
      RunOdomcal(Calibrate({"stray"})),
      std::string(kCalibrateError) +
          "unexpected argument 'stray' (every value follows its --flag)");
  // A second value for a flag that takes one.
  ExpectBadInput(
      RunOdomcal(Calibrate({"--min_rotation_deg", "1", "2"})),
      std::string(kCalibrateError) +
          "unexpected argument '2' (every value follows its --flag)");
}

TEST_F(CommandLine, FlagWithoutValue) {
  ExpectBadInput(
      RunOdomcal(Calibrate({"--max_odometry_gap_s"})),
      std::string(kCalibrateError) + "--max_odometry_gap_s needs a value");
}

TEST_F(CommandLine, HelpOfACommandIsItsHelpFlag) {
  const CommandResult help = RunOdomcal({"help", "calibrate"});
  const CommandResult flag = RunOdomcal({"calibrate", "--help"});
  EXPECT_EQ(help.exit_code, 0) << help.err;
  EXPECT_EQ(help.err, "");
  EXPECT_EQ(help.out, flag.out);
  EXPECT_EQ(flag.exit_code, 0);
  EXPECT_NE(help.out.find("--camera_poses"), std::string::npos) << help.out;
  EXPECT_EQ(help.out.find("commands:"), std::string::npos) << help.out;
  for (const char* command : {"colmap", "run", "demo", "render", "simulate"}) {
    SCOPED_TRACE(command);
    const CommandResult run = RunOdomcal({"help", command});
    EXPECT_EQ(run.exit_code, 0);
    EXPECT_EQ(run.out, RunOdomcal({command, "--help"}).out);
  }
  const CommandResult usage = RunOdomcal({"help"});
  EXPECT_EQ(usage.exit_code, 0);
  EXPECT_NE(usage.out.find("commands:"), std::string::npos) << usage.out;
}

TEST_F(CommandLine, HelpOfAnUnknownCommandNamesTheCommands) {
  ExpectBadInput(
      RunOdomcal({"help", "calibration"}),
      "odomcal help: error: unknown command 'calibration' "
      "(commands: calibrate, "
      "colmap, run, inspect, extract, demo, render, simulate, version)");
  ExpectBadInput(
      RunOdomcal({"help", "calibrate", "colmap"}),
      "odomcal help: error: unexpected argument 'colmap' (usage: odomcal help "
      "<command>)");
}

TEST_F(CommandLine, OptionErrorsNameTheFlag) {
  ExpectBadInput(RunOdomcal(Calibrate({"--max_odometry_gap_s", "-1"})),
                 std::string(kCalibrateError) +
                     "--max_odometry_gap_s must be finite and > 0, got -1");
  ExpectBadInput(RunOdomcal(Calibrate({"--max_odometry_gap_s", "1s"})),
                 std::string(kCalibrateError) +
                     "--max_odometry_gap_s must be auto or a number, got '1s'");
  ExpectBadInput(
      RunOdomcal(Calibrate({"--keyframe_min_translation_m", "-0.25"})),
      std::string(kCalibrateError) +
          "--keyframe_min_translation_m must be >= 0, got -0.25");
  ExpectBadInput(RunOdomcal(Calibrate({"--odom_yaw_sigma_deg", "-1"})),
                 std::string(kCalibrateError) +
                     "--odom_yaw_sigma_deg must be finite and >= 0, got -1");
  ExpectBadInput(RunOdomcal(Calibrate({"--cam_rotation_sigma_deg", "0"})),
                 std::string(kCalibrateError) +
                     "--cam_rotation_sigma_deg must be finite and > 0, got 0");
  ExpectBadInput(
      RunOdomcal(Calibrate(
          {"--odom_yaw_sigma_deg", "0", "--odom_yaw_sigma_rel", "0"})),
      std::string(kCalibrateError) +
          "--odom_yaw_sigma_deg and --odom_yaw_sigma_rel are both 0 (the "
          "odometry "
          "yaw would be exact)");
  ExpectBadInput(RunOdomcal(Calibrate({"--ransac_min_inlier_ratio", "1.5"})),
                 std::string(kCalibrateError) +
                     "--ransac_min_inlier_ratio must be in [0, 1], got 1.5");
  ExpectBadInput(RunOdomcal(Calibrate({"--fixed_translation_z_m", "nan"})),
                 std::string(kCalibrateError) +
                     "--fixed_translation_z_m must be finite, got nan");
  ExpectBadInput(RunOdomcal(Calibrate({"--camera_time_offset_s", "1e400"})),
                 std::string(kCalibrateError) +
                     "--camera_time_offset_s must be finite and within [-1e9, "
                     "1e9], got inf");
  ExpectBadInput(RunOdomcal(Colmap({"--min_inconsistent_run_pairs", "0"})),
                 std::string(kColmapError) +
                     "--min_inconsistent_run_pairs must be >= 1, got 0");
  ExpectBadInput(RunOdomcal(Colmap({"--max_odometry_gap_s", "0"})),
                 std::string(kColmapError) +
                     "--max_odometry_gap_s must be finite and > 0, got 0");
  ExpectBadInput(RunOdomcal(Colmap({"--floor_plane", "yes"})),
                 std::string(kColmapError) +
                     "--floor_plane: yes not in {estimate,check,off}");
  ExpectBadInput(RunOdomcal(Colmap({"--odometry_height_m", "nan"})),
                 std::string(kColmapError) +
                     "--odometry_height_m must be finite, got nan");
  ExpectBadInput(RunOdomcal(Colmap({"--floor_max_path_distance_m", "0"})),
                 std::string(kColmapError) +
                     "--floor_max_path_distance_m must be positive, got 0");
  ExpectBadInput(RunOdomcal(Colmap({"--floor_max_slope_deg", "20"})),
                 std::string(kColmapError) +
                     "--floor_max_slope_deg must be in (0, 10), got 20");
}

TEST_F(CommandLine, ValuesOfTheWrongTypeNameTheFlag) {
  ExpectBadInput(RunOdomcal(Calibrate({"--min_rotation_deg", "abc"})),
                 std::string(kCalibrateError) +
                     "--min_rotation_deg must be a number, got 'abc'");
  ExpectBadInput(
      RunOdomcal(Calibrate({"--ransac_seed", "-1"})),
      std::string(kCalibrateError) + "--ransac_seed must be >= 0, got -1");
  ExpectBadInput(RunOdomcal(Calibrate({"--ransac_seed", "1.5"})),
                 std::string(kCalibrateError) +
                     "--ransac_seed must be an integer >= 0, got '1.5'");
  ExpectBadInput(
      RunOdomcal(Colmap({"--min_inconsistent_run_pairs", "2.5"})),
      std::string(kColmapError) +
          "--min_inconsistent_run_pairs must be an integer, got '2.5'");
}

TEST_F(CommandLine, RangeChecksOfOtherCommandsPrintTheirLimits) {
  ExpectBadInput(RunOdomcal(Run({"--num_threads", "0"})),
                 "odomcal run: error: --num_threads must be >= 1, got 0");
  ExpectBadInput(
      RunOdomcal(Run({"--mapper_attempts", "21"})),
      "odomcal run: error: --mapper_attempts must be in [1, 20], got 21");
  ExpectBadInput(
      RunOdomcal(Run({"--frame_min_rotation_deg", "-3"})),
      "odomcal run: error: --frame_min_rotation_deg must be >= 0, got -3");
  // The "auto or a number" rows share one parse (AutoOrNumberRow).
  ExpectBadInput(
      RunOdomcal(Run({"--frame_min_translation_m", "far"})),
      "odomcal run: error: --frame_min_translation_m must be auto or a "
      "number, got 'far'");
  ExpectBadInput(
      RunOdomcal(Run({"--chunk_images", "20"})),
      "odomcal run: error: --chunk_images must be 0 or >= 24, got 20");
  ExpectBadInput(
      RunOdomcal({"demo", "--simulated", "--duration_s", "1"}),
      "odomcal demo: error: --duration_s must be in [5, 3600], got 1");
  ExpectBadInput(
      RunOdomcal({"simulate", "--output_path", Path("sim"), "--threads", "0"}),
      "odomcal simulate: error: --threads must be in [1, 256], got 0");
  ExpectBadInput(RunOdomcal({"simulate",
                             "--output_path",
                             Path("sim"),
                             "--landmark_max_depth_m",
                             "0.4"}),
                 "odomcal simulate: error: --landmark_max_depth_m must be in "
                 "[1, 100], got 0.4");
  EXPECT_FALSE(fs::exists(Path("ws")));
  EXPECT_FALSE(fs::exists(Path("sim")));
}

// The printed table and the CSV say which batch the B methods used: the
// paper's keeps every motion, the default rounds may leave some out.
TEST_F(CommandLine, SimulateNamesTheBatchRefinement) {
  for (const std::string batch : {"paper", "inlier_rounds"}) {
    SCOPED_TRACE(batch);
    const std::string folder = Path("sim_" + batch);
    const CommandResult result = RunOdomcal({"simulate",
                                             "--output_path",
                                             folder,
                                             "--camera_noise",
                                             "parametric",
                                             "--sweep",
                                             "num_motions",
                                             "--trials",
                                             "3",
                                             "--batch_refinement",
                                             batch});
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(result.out.find("3 trials per point, B methods: " + batch),
              std::string::npos)
        << result.out;
    std::ifstream csv(folder + "/num_motions.csv");
    std::string line;
    ASSERT_TRUE(std::getline(csv, line));
    EXPECT_EQ(line.substr(line.rfind(',') + 1), "motions_used");
    int num_batch_rows = 0;
    while (std::getline(csv, line)) {
      const std::string used = line.substr(line.rfind(',') + 1);
      if (line.find("-B,") == std::string::npos) {
        EXPECT_EQ(used, "") << line;  // closed forms: no refinement
        continue;
      }
      ++num_batch_rows;
      const double fraction = std::stod(used);
      if (batch == "paper") {
        EXPECT_EQ(fraction, 1.0) << line;
      } else {
        EXPECT_GT(fraction, 0.5) << line;
        EXPECT_LE(fraction, 1.0) << line;
      }
    }
    EXPECT_EQ(num_batch_rows, 5 * 4);  // 5 motion counts, 4 B methods
  }
}

// `odomcal calibrate <arguments>` in this process (RunCalibrate, as main()
// calls it), with its stdout and stderr captured: ~250 runs would take a
// minute as processes, which load Ceres and OpenCV.
CommandResult RunCalibrateInProcess(std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), "calibrate");
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  std::ostringstream out, err;
  std::streambuf* const cout_buffer = std::cout.rdbuf(out.rdbuf());
  std::streambuf* const cerr_buffer = std::cerr.rdbuf(err.rdbuf());
  CommandResult result;
  result.exit_code =
      RunCalibrate(static_cast<int>(arguments.size()), argv.data());
  std::cout.rdbuf(cout_buffer);
  std::cerr.rdbuf(cerr_buffer);
  result.out = out.str();
  result.err = err.str();
  return result;
}

// Every numeric flag of calibrate, every kind of bad value: one line that
// names the flag (or, for a value the flag accepts, the empty input file),
// with no C++ field path and no 20-digit number.
TEST_F(CommandLine, NoMessageLeaksCppNamesOrHugeNumbers) {
  CLI::App app;
  CalibrateInputs inputs;
  AddCalibrationFlags(&app, &inputs);
  const std::regex huge_number("[0-9]{20}");
  const std::string empty_input =
      std::string(kCalibrateError) + Path("camera.tum") +
      ": no data lines (0 lines, all blank or '#' comments)\n";
  int num_flags = 0;
  for (const CLI::Option* option : app.get_options()) {
    const std::string type = option->get_type_name();
    if (type.rfind("FLOAT", 0) != 0 && type.rfind("INT", 0) != 0 &&
        type.rfind("UINT", 0) != 0) {
      continue;
    }
    ++num_flags;
    const std::string flag = "--" + option->get_lnames().front();
    for (const char* value : {"-1",
                              "0",
                              "1.5",
                              "-0.5",
                              "nan",
                              "inf",
                              "-inf",
                              "1e400",
                              "-1e400",
                              "abc",
                              "1e30",
                              ""}) {
      SCOPED_TRACE(flag + " " + value);
      std::vector<std::string> arguments = Calibrate({flag, value});
      arguments.erase(arguments.begin());
      const CommandResult run = RunCalibrateInProcess(arguments);
      EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
      EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
      EXPECT_EQ(run.err.rfind(kCalibrateError, 0), 0u) << run.err;
      if (run.err != empty_input) {
        EXPECT_EQ(run.err.rfind(std::string(kCalibrateError) + flag + " ", 0),
                  0u)
            << run.err;
      }
      EXPECT_EQ(run.err.find("Options."), std::string::npos) << run.err;
      EXPECT_EQ(run.err.find("noise."), std::string::npos) << run.err;
      EXPECT_FALSE(std::regex_search(run.err, huge_number)) << run.err;
    }
  }
  EXPECT_EQ(num_flags, 27);
}

}  // namespace
}  // namespace odomcal
