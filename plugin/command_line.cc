#include "odomcal/plugin/command_line.h"

#include "odomcal/plugin/colmap_runner.h"

#include <iostream>
#include <stdexcept>

namespace odomcal {

std::optional<int> ParseFlags(CLI::App* app, int argc, char** argv) {
  try {
    app->parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app->help();
    return kExitSuccess;
  } catch (const CLI::ParseError& error) {
    std::cerr << app->get_name() << ": error: " << error.what() << "\n";
    return kExitBadInput;
  }
  return std::nullopt;
}

int RunReportingErrors(const std::string& command, const std::function<int()>& body) {
  try {
    return body();
  } catch (const ColmapError& error) {
    std::cout << std::flush;
    std::cerr << command << ": error: " << error.what() << "\n";
    return kExitColmapFailed;
  } catch (const std::invalid_argument& error) {
    std::cout << std::flush;
    std::cerr << command << ": error: " << error.what() << "\n";
  } catch (const std::runtime_error& error) {
    // FormatError, OutputError and rendering I/O errors.
    std::cout << std::flush;
    std::cerr << command << ": error: " << error.what() << "\n";
  }
  return kExitBadInput;
}

}  // namespace odomcal
