// odomcal command-line tool: a table of subcommands, each with its own flags
// (`odomcal <command> --help`). Exit codes: 0 success, 1 internal error,
// 2 bad arguments or files, 3 the data do not determine the calibration,
// 4 COLMAP missing, failed or gave no model (`run`, `demo`).

#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include "odomcal/plugin/calibrate_command.h"
#include "odomcal/plugin/colmap_command.h"
#include "odomcal/plugin/demo_command.h"
#include "odomcal/plugin/run_command.h"
#include "odomcal/plugin/render_command.h"
#include "odomcal/plugin/simulate_command.h"

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
    {"demo",
     "simulated drive -> files -> calibration, compared with ground truth",
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
         "usage: odomcal <command> [flags]   (odomcal <command> --help)\n"
         "commands:\n";
  for (const Command& command : kCommands) {
    out << "  " << command.name << std::string(12 - std::strlen(command.name), ' ')
        << command.summary << "\n";
  }
  out << "  version     print the version\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    PrintUsage(std::cerr);
    return odomcal::kExitBadInput;
  }
  const std::string name = argv[1];
  if (name == "help" || name == "--help" || name == "-h") {
    PrintUsage(std::cout);
    return odomcal::kExitSuccess;
  }
  if (name == "version" || name == "--version") {
    std::cout << "odomcal " << ODOMCAL_VERSION << "\n";
    return odomcal::kExitSuccess;
  }
  for (const Command& command : kCommands) {
    if (name == command.name) {
      try {
        // The subcommand sees itself as argv[0].
        return command.run(argc - 1, argv + 1);
      } catch (const std::exception& error) {
        std::cerr << "odomcal " << name << ": internal error: " << error.what()
                  << "\n";
        return odomcal::kExitInternalError;
      }
    }
  }
  std::cerr << "odomcal: error: unknown command '" << name
            << "' (odomcal help lists them)\n";
  return odomcal::kExitBadInput;
}
