// ParseFlags lets CLI11 collect unknown arguments (allow_extras) instead of
// throwing on them, because CLI11 checks required flags first: a misspelt
// required flag would otherwise read as a missing one. After parsing (or a
// parse error), the first unknown flag, else the first stray argument, is
// the error; CLI11's own messages are reworded where they name no flag
// ("Could not convert: ...") or print C++ limits.
#include "odomcal/plugin/cli/command_line.h"

#include "odomcal/plugin/colmap/colmap_runner.h"
#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <stdexcept>

namespace odomcal {
namespace {

// Lower case, '-' as '_', without leading dashes: "--Model-Path" ->
// "model_path".
std::string Normalized(const std::string& flag) {
  std::string name =
      flag.substr(std::min(flag.find_first_not_of('-'), flag.size()));
  for (char& c : name) {
    c = c == '-'
            ? '_'
            : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return name;
}

// Optimal string alignment distance: Levenshtein plus adjacent swaps.
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<size_t>> d(a.size() + 1,
                                     std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] =
          std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[a.size()][b.size()];
}

bool StartsWith(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

// "-5", "-.5": a (negative) number given where no flag takes it.
bool LooksLikeNumber(const std::string& argument) {
  const size_t start = argument.find_first_not_of('-');
  return start != std::string::npos && start <= 1 &&
         (std::isdigit(static_cast<unsigned char>(argument[start])) ||
          argument[start] == '.');
}

// The error for what CLI11 left over, or "" when nothing was.
std::string LeftOverError(const CLI::App& app) {
  const std::vector<std::string> left_over = app.remaining();
  for (const std::string& argument : left_over) {
    if (argument.size() < 2 || argument[0] != '-' ||
        LooksLikeNumber(argument)) {
      continue;  // a stray value, reported below unless a flag is unknown
    }
    const std::string flag = argument.substr(0, argument.find('='));
    const std::string nearest = NearestFlag(flag, LongFlags(app));
    return "unknown flag " + flag +
           (nearest.empty() ? "" : " (did you mean " + nearest + "?)");
  }
  if (!left_over.empty()) {
    return "unexpected argument '" + left_over.front() +
           "' (every value follows its --flag)";
  }
  return "";
}

// CLI11's "Could not convert: --trials = many" names the flag but not what
// it takes.
std::string ConversionMessage(const CLI::App& app,
                              const CLI::ConversionError& error) {
  std::string what = error.what();  // returned by move where unchanged
  const std::string prefix = "Could not convert: ";
  const size_t equals = what.find(" = ");
  if (!StartsWith(what, prefix) || equals == std::string::npos) return what;
  const std::string flag = what.substr(prefix.size(), equals - prefix.size());
  const std::string value = what.substr(equals + 3);
  std::string expected = "a number";
  try {
    const std::string type =
        app.get_option(flag)->get_type_name();  // e.g. "INT:min 1"
    const std::string base = type.substr(0, type.find(':'));
    if (base == "INT") expected = "an integer";
    if (base == "UINT") expected = "an integer >= 0";
  } catch (const CLI::OptionNotFound&) {
  }
  return flag + " must be " + expected + ", got '" + value + "'";
}

// CLI11's "--gap: 1 required FLOAT missing" when a flag ends the command
// line.
std::string MismatchMessage(const CLI::ArgumentMismatch& error) {
  std::string what = error.what();  // returned by move where unchanged
  const size_t colon = what.find(": ");
  if (StartsWith(what, "--") && colon != std::string::npos &&
      what.find(" required ") != std::string::npos && what.size() >= 8 &&
      what.compare(what.size() - 8, 8, " missing") == 0) {
    return what.substr(0, colon) + " needs a value";
  }
  return what;
}

// CLI11 writes a ValidationError as "--flag: <message>"; ours read
// "--flag must be ...".
std::string ValidationMessage(const CLI::ValidationError& error) {
  std::string what = error.what();
  const size_t colon = what.find(": must ");
  if (StartsWith(what, "--") && colon != std::string::npos &&
      what.find(' ') > colon) {
    what.erase(colon, 1);
  }
  return what;
}

bool IsNameCharacter(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' ||
         c == '.' || c == '/' || c == '[';
}

// "max_odometry_gap_s must be ..." -> "--max_odometry_gap_s must be ...":
// the library's options name their fields, which are the flags' names.
// Whole words only, and only names with a '_' ("odometry" is also a word of
// prose); not inside paths or dotted names.
std::string WithFlagNames(const CLI::App& app, std::string message) {
  for (const std::string& flag : LongFlags(app)) {
    const std::string name = flag.substr(2);
    if (name.find('_') == std::string::npos) continue;
    for (size_t at = message.find(name); at != std::string::npos;
         at = message.find(name, at + name.size())) {
      const size_t end = at + name.size();
      if ((at > 0 && IsNameCharacter(message[at - 1])) ||
          (end < message.size() && IsNameCharacter(message[end]) &&
           message[end] != '.')) {
        continue;
      }
      message.insert(at, "--");
      at += 2;
    }
  }
  return message;
}

// "1000000", not FormatNumber's "1e+06", for whole limits.
std::string FormatLimit(double limit) {
  if (limit == std::floor(limit) && std::abs(limit) < 1e15) {
    return std::to_string(static_cast<long long>(limit));
  }
  return FormatNumber(limit);
}

// Parses a flag's text as a finite number for the range checks; CLI11
// converts it to the flag's type later.
std::string RangeError(const std::string& text,
                       double min,
                       double max,
                       const std::string& limits) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) {
    return "must be a number, got '" + text + "'";
  }
  if (!std::isfinite(value)) {
    return "must be a finite number " + limits + ", got " + FormatNumber(value);
  }
  if (!(value >= min && value <= max)) {
    return "must be " + limits + ", got " + FormatNumber(value);
  }
  return "";
}

}  // namespace

std::vector<std::string> LongFlags(const CLI::App& app) {
  std::vector<std::string> flags;
  for (const CLI::Option* option : app.get_options()) {
    for (const std::string& name : option->get_lnames()) {
      flags.push_back("--" + name);
    }
  }
  return flags;
}

std::string NearestFlag(const std::string& typed,
                        const std::vector<std::string>& flags) {
  const std::string wanted = Normalized(typed);
  if (wanted.empty()) return "";
  std::string nearest;
  size_t nearest_distance = std::string::npos;
  for (const std::string& flag : flags) {
    const std::string name = Normalized(flag);
    if (name == wanted) return flag;
    const size_t distance = EditDistance(wanted, name);
    const size_t shorter = std::min(wanted.size(), name.size());
    const bool close = 3 * distance <= std::max(wanted.size(), name.size());
    const bool extends =
        shorter >= 4 && (StartsWith(wanted, name) || StartsWith(name, wanted));
    if ((close || extends) && distance < nearest_distance) {
      nearest = flag;
      nearest_distance = distance;
    }
  }
  return nearest;
}

CLI::Validator AtLeast(double min) {
  const std::string limit = FormatLimit(min);
  return CLI::Validator(
      [min, limit](std::string& text) {
        return RangeError(
            text, min, std::numeric_limits<double>::max(), ">= " + limit);
      },
      "min " + limit);  // --help: "--num_threads INT:min 1=2"
}

CLI::Validator InRange(double min, double max) {
  const std::string limits =
      "[" + FormatLimit(min) + ", " + FormatLimit(max) + "]";
  return CLI::Validator(
      [min, max, limits](std::string& text) {
        return RangeError(text, min, max, "in " + limits);
      },
      limits);  // --help: "--threads INT:[1, 256]=2"
}

std::string FlagError(CLI::App* app, int argc, const char* const* argv) {
  app->allow_extras();
  std::string error;
  try {
    app->parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    throw;
  } catch (const CLI::ConversionError& parse_error) {
    error = ConversionMessage(*app, parse_error);
  } catch (const CLI::ArgumentMismatch& parse_error) {
    error = MismatchMessage(parse_error);
  } catch (const CLI::ValidationError& parse_error) {
    error = ValidationMessage(parse_error);
  } catch (const CLI::ParseError& parse_error) {
    error = parse_error.what();
  }
  // Also after a parse error: CLI11 collects unknown arguments before it
  // checks values and required flags.
  const std::string left_over = LeftOverError(*app);
  return left_over.empty() ? error : left_over;
}

std::optional<int> ParseFlags(CLI::App* app, int argc, char** argv) {
  std::string error;
  try {
    error = FlagError(app, argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app->help();
    return kExitSuccess;
  }
  if (error.empty()) return std::nullopt;
  std::cerr << app->get_name() << ": error: " << error << "\n";
  return kExitBadInput;
}

int RunReportingErrors(const CLI::App& app, const std::function<int()>& body) {
  const std::string& command = app.get_name();
  try {
    return body();
  } catch (const ColmapError& error) {
    std::cout << std::flush;
    std::cerr << command << ": error: " << error.what() << "\n";
    return kExitColmapFailed;
  } catch (const std::invalid_argument& error) {
    std::cout << std::flush;
    std::cerr << command << ": error: " << WithFlagNames(app, error.what())
              << "\n";
  } catch (const std::runtime_error& error) {
    // FormatError, OutputError and rendering I/O errors.
    std::cout << std::flush;
    std::cerr << command << ": error: " << error.what() << "\n";
  }
  return kExitBadInput;
}

}  // namespace odomcal
