// odomcal command-line tool: a table of subcommands, each with its own flags
// (`odomcal <command> --help`). Exit codes: 0 success, 1 internal error,
// 2 bad arguments or files, 3 the data do not determine the calibration,
// 4 COLMAP missing, failed or gave no model (`run`, `demo`).

#include "odomcal/plugin/cli/bag_commands.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/cli/colmap_command.h"
#include "odomcal/plugin/cli/demo_command.h"
#include "odomcal/plugin/cli/render_command.h"
#include "odomcal/plugin/cli/run_command.h"
#include "odomcal/plugin/cli/simulate_command.h"

#include <cstring>
#include <exception>
#include <iostream>
#include <string>

namespace {

struct Command {
  const char* name;
  const char* summary;
  int (*run)(int argc, char** argv);
};

const Command kCommands[] = {
    {"calibrate",
     "extrinsic + metric scale from a camera trajectory and wheel odometry",
     &odomcal::RunCalibrate},
    {"colmap",
     "calibrate an existing COLMAP project against wheel odometry",
     &odomcal::RunColmap},
    {"run",
     "image folder + odometry -> COLMAP -> calibration and metric model",
     &odomcal::RunRun},
    {"inspect",
     "list a robot bag's topics and what run --bag would take from it",
     &odomcal::RunInspect},
    {"extract",
     "write a robot bag's images, odometry and camera as input files",
     &odomcal::RunExtract},
    {"demo",
     "rendered scene -> COLMAP -> calibration, compared with ground truth",
     &odomcal::RunDemo},
    {"render",
     "write a rendered synthetic dataset (images, odometry, ground truth)",
     &odomcal::RunRender},
    {"simulate",
     "Monte Carlo evaluation of the paper (Fig. 2 sweeps, Table I)",
     &odomcal::RunSimulate},
};

void PrintUsage(std::ostream& out) {
  out << "odomcal " << ODOMCAL_VERSION
      << ": camera-to-wheel-odometry extrinsic calibration\n"
         "usage: odomcal <command> [flags]   (odomcal help <command>)\n"
         "commands:\n";
  for (const Command& command : kCommands) {
    out << "  " << command.name
        << std::string(12 - std::strlen(command.name), ' ') << command.summary
        << "\n";
  }
  out << "  version     print the version\n";
}

const Command* FindCommand(const std::string& name) {
  for (const Command& command : kCommands) {
    if (name == command.name) return &command;
  }
  return nullptr;
}

std::string CommandNames() {
  std::string names;
  for (const Command& command : kCommands)
    names += std::string(command.name) + ", ";
  return names + "version";
}

int RunCommand(const Command& command, int argc, char** argv) {
  try {
    // The subcommand sees itself as argv[0].
    return command.run(argc, argv);
  } catch (const std::exception& error) {
    std::cerr << "odomcal " << command.name
              << ": internal error: " << error.what() << "\n";
    return odomcal::kExitInternalError;
  }
}

// `odomcal help` lists the commands, `odomcal help <command>` is
// `odomcal <command> --help`.
int RunHelp(int argc, char** argv) {
  if (argc == 1) {
    PrintUsage(std::cout);
    return odomcal::kExitSuccess;
  }
  const std::string name = argv[1];
  if (argc > 2) {
    std::cerr << "odomcal help: error: unexpected argument '" << argv[2]
              << "' (usage: odomcal help <command>)\n";
    return odomcal::kExitBadInput;
  }
  if (name == "version") {
    std::cout << "usage: odomcal version\nprints the version of odomcal\n";
    return odomcal::kExitSuccess;
  }
  const Command* command = FindCommand(name);
  if (command == nullptr) {
    std::cerr << "odomcal help: error: unknown command '" << name
              << "' (commands: " << CommandNames() << ")\n";
    return odomcal::kExitBadInput;
  }
  char help_flag[] = "--help";
  char* help_argv[] = {argv[1], help_flag, nullptr};
  return RunCommand(*command, 2, help_argv);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    PrintUsage(std::cerr);
    return odomcal::kExitBadInput;
  }
  const std::string name = argv[1];
  if (name == "help" || name == "--help" || name == "-h") {
    return RunHelp(argc - 1, argv + 1);
  }
  if (name == "version" || name == "--version") {
    std::cout << "odomcal " << ODOMCAL_VERSION << "\n";
    return odomcal::kExitSuccess;
  }
  if (const Command* command = FindCommand(name)) {
    return RunCommand(*command, argc - 1, argv + 1);
  }
  std::cerr << "odomcal: error: unknown command '" << name
            << "' (odomcal help lists them)\n";
  return odomcal::kExitBadInput;
}
