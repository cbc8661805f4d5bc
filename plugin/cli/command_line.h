// What every odomcal command does the same way: parse its flags with CLI11
// and turn the errors of bad input into one line on stderr and exit code 2.
// The line names flags and values as the user typed them, never C++ fields:
//   odomcal calibrate: error: unknown flag --output_path (did you mean
//   --output?) odomcal calibrate: error: --max_odometry_gap_s must be finite
//   and > 0, got -1
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

// Exit codes of every odomcal command.
constexpr int kExitSuccess = 0;
constexpr int kExitInternalError = 1;
constexpr int kExitBadInput = 2;       // arguments, files, outputs
constexpr int kExitNotCalibrated = 3;  // the data do not determine it
constexpr int kExitColmapFailed = 4;  // COLMAP missing, failed or gave no model

// Parses argv. Returns nothing when the command should go on, otherwise its
// exit code: 0 after printing --help, kExitBadInput after one line
// "odomcal <command>: error: <what>" for a flag error. An unknown flag or a
// stray argument is reported first (before a missing required flag, which
// may just be the misspelt one), with the nearest valid flag.
std::optional<int> ParseFlags(CLI::App* app, int argc, char** argv);

// ParseFlags without printing: the error line's <what> (e.g. "unknown flag
// --output_path (did you mean --output?)"), or "" when argv parsed. --help
// throws CLI::CallForHelp. For callers that report errors their own way
// (the Python module raises them).
std::string FlagError(CLI::App* app, int argc, const char* const* argv);

// Runs `body` and returns its exit code; FormatError, OutputError,
// std::invalid_argument and other std::runtime_errors (the library's ways of
// rejecting input) become one line "odomcal <command>: error: <what>" and
// kExitBadInput; a ColmapError the same line and kExitColmapFailed. In the
// messages of std::invalid_argument (options' Check()), option names that
// are flags of `app` are written as flags: "max_odometry_gap_s must be ..."
// becomes "--max_odometry_gap_s must be ...".
int RunReportingErrors(const CLI::App& app, const std::function<int()>& body);

// The flag among `flags` (each "--name") that the user most likely meant by
// `typed` (an unknown flag as typed, e.g. "--model-path" or "-output"), or ""
// when none is close. '-' for '_' and letter case are forgiven outright;
// otherwise the nearest by edit distance (insertions, deletions,
// substitutions, transpositions) within a third of the name's length, or a
// flag that `typed` extends or abbreviates ("--output_path" -> "--output").
std::string NearestFlag(const std::string& typed,
                        const std::vector<std::string>& flags);

// Every long flag of `app` ("--name"), --help included, in declaration order.
std::vector<std::string> LongFlags(const CLI::App& app);

// CLI11 checks of numeric flags whose messages print readable limits
// ("--num_threads must be >= 1, got 0") instead of CLI::PositiveNumber's
// 309-digit maximum. The value must also be a finite number.
CLI::Validator AtLeast(double min);
CLI::Validator InRange(double min, double max);

}  // namespace odomcal
