// What every odomcal command does the same way: parse its flags with CLI11
// and turn the errors of bad input into one line on stderr and exit code 2.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace odomcal {

// Exit codes of every odomcal command.
constexpr int kExitSuccess = 0;
constexpr int kExitInternalError = 1;
constexpr int kExitBadInput = 2;       // arguments, files, outputs
constexpr int kExitNotCalibrated = 3;  // the data do not determine it
constexpr int kExitColmapFailed = 4;  // COLMAP missing, failed or gave no model

// Parses argv. Returns nothing when the command should go on, otherwise its
// exit code: 0 after printing --help, kExitBadInput after one line
// "odomcal <command>: error: <what>" for a flag error.
std::optional<int> ParseFlags(CLI::App* app, int argc, char** argv);

// Runs `body` and returns its exit code; FormatError, OutputError,
// std::invalid_argument and other std::runtime_errors (the library's ways of
// rejecting input) become one line "odomcal <command>: error: <what>" and
// kExitBadInput; a ColmapError the same line and kExitColmapFailed.
int RunReportingErrors(const std::string& command, const std::function<int()>& body);

}  // namespace odomcal
