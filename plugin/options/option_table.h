// The single source of truth for the flags of an options struct: one table
// per struct, one row per flag. A row says the flag's name, its help text,
// where its value goes (a field, whose value is the default shown by --help,
// or a text parsed into the struct), its check, and the key under which the
// result JSON echoes the value. This header needs no CLI11: the library
// (option tables in cli_flags.h, project_flags.h, run_flags.h, target
// odomcal::plugin) echoes the options from the tables (CalibrationFlagsEcho,
// ProjectFlagsEcho, RunFlagsEcho), which the report writers use by default;
// the command line registers its CLI11 flags from the same rows
// (command_flags.h, AddFlags). tests/flag_table_test.cc checks docs/cli.md
// and the echo against the CLI.
//
// Field names are the flag names without "--" (CalibrationOptions::Check
// names fields, and the CLI rewrites them into flags), so a row's name is
// the field's, the flag's and, but for --no_refine (echoed as "refine"), the
// echo's key.
#pragma once

#include "odomcal/solver/format_number.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace odomcal {

// A check of a flag's value. The command line turns it into a CLI11
// validator whose message names the limit ("--num_threads must be >= 1,
// got 0", command_line.h's AtLeast and InRange).
struct FlagCheck {
  enum class Kind {
    kNone,
    kAtLeast,
    kInRange,
    kExistingFile,
    kExistingDirectory,
    kCustom,
  };
  Kind kind = Kind::kNone;
  double min = 0.0;
  double max = 0.0;
  // kCustom: "" when `text` is a valid value, else what is wrong with it
  // ("must be a number, got 'x'").
  std::function<std::string(const std::string& text)> custom;

  static FlagCheck None() { return {}; }
  static FlagCheck AtLeast(double min) {
    FlagCheck check;
    check.kind = Kind::kAtLeast;
    check.min = min;
    return check;
  }
  static FlagCheck InRange(double min, double max) {
    FlagCheck check;
    check.kind = Kind::kInRange;
    check.min = min;
    check.max = max;
    return check;
  }
  static FlagCheck ExistingFile() { return {Kind::kExistingFile, 0, 0, {}}; }
  static FlagCheck ExistingDirectory() {
    return {Kind::kExistingDirectory, 0, 0, {}};
  }
  static FlagCheck Custom(
      std::function<std::string(const std::string& text)> custom) {
    return {Kind::kCustom, 0, 0, std::move(custom)};
  }
};

// Where a flag's value goes. A field of the struct (a number or a string),
// bound directly: its current value is the default shown...
template <typename Options, typename T>
using OptionField = std::function<T&(Options&)>;
// ...or a text that `set` stores in the struct in another form (a unit, an
// enum, seconds as nanoseconds); `get` names the current value (the
// default shown). `choices`, when not empty, are the valid texts;
// `type_name` is --help's type ("" for TEXT).
template <typename Options>
struct OptionText {
  std::vector<std::string> choices;
  std::function<std::string(const Options&)> get;
  std::function<void(Options*, const std::string&)> set;
  std::string type_name;
};
// ...or a flag without a value: `set` runs when it is given.
template <typename Options>
struct OptionSwitch {
  std::function<void(Options*)> set;
};

template <typename Options>
using OptionValue = std::variant<OptionField<Options, double>,
                                 OptionField<Options, int>,
                                 OptionField<Options, int64_t>,
                                 OptionField<Options, uint64_t>,
                                 OptionField<Options, std::string>,
                                 OptionText<Options>,
                                 OptionSwitch<Options>>;

template <typename Options>
struct OptionRow {
  std::string name;         // the flag without "--"
  std::string help;         // --help text
  std::string echo_key;     // key in the echo object
  std::string echo_object;  // "": the echo object itself, else a member
  OptionValue<Options> value;
  FlagCheck check;
  bool required = false;
  bool repeatable = false;   // given any number of times (OptionText)
  bool show_default = true;  // --help shows the current value
  // The value echoed in the result JSON; empty for rows that are not
  // echoed or whose value the report echoes from elsewhere.
  std::function<nlohmann::json(const Options& options)> echo;
};

template <typename Options>
using OptionTable = std::vector<OptionRow<Options>>;

// Writes every row's echo into `echo` (an object) under the row's key.
template <typename Options>
void EchoOptions(const OptionTable<Options>& table,
                 const Options& options,
                 nlohmann::json* echo) {
  for (const OptionRow<Options>& row : table) {
    if (!row.echo) continue;
    nlohmann::json& object =
        row.echo_object.empty() ? *echo : (*echo)[row.echo_object];
    object[row.echo_key] = row.echo(options);
  }
}

// Adds `more`'s "inputs" and "options" members to `echo`'s (both echoes as
// made by the *FlagsEcho functions).
inline void MergeFlagEcho(const nlohmann::json& more, nlohmann::json* echo) {
  for (const char* part : {"inputs", "options"}) {
    if (!more.contains(part)) continue;
    nlohmann::json& into = (*echo)[part];
    if (into.is_null()) into = nlohmann::json::object();
    into.update(more.at(part));
  }
}

// A number or string field. `field` maps an options struct to the field,
// const or not, e.g.
//   [](auto& o) -> auto& { return o.noise.odom_yaw_sigma_deg; }
template <typename Options, typename Field>
OptionRow<Options> NumberRow(const std::string& name,
                             const std::string& help,
                             Field field,
                             const FlagCheck& check = {}) {
  using T = std::remove_reference_t<decltype(field(std::declval<Options&>()))>;
  OptionRow<Options> row;
  row.name = name;
  row.help = help;
  row.echo_key = name;
  row.value = OptionField<Options, T>(
      [field](Options& options) -> T& { return field(options); });
  row.check = check;
  row.echo = [field](const Options& options) {
    return nlohmann::json(field(options));
  };
  return row;
}

// One of `choices`, held in the options struct as another type: `get`
// names the current value (the default shown and the echo), `set` stores a
// name that passed the check.
template <typename Options>
OptionRow<Options> ChoiceRow(
    const std::string& name,
    const std::string& help,
    std::vector<std::string> choices,
    std::function<std::string(const Options&)> get,
    std::function<void(Options*, const std::string&)> set) {
  OptionRow<Options> row;
  row.name = name;
  row.help = help;
  row.echo_key = name;
  row.value = OptionText<Options>{std::move(choices), get, std::move(set), ""};
  row.echo = [get](const Options& options) {
    return nlohmann::json(get(options));
  };
  return row;
}

// A flag given any number of times: `add` stores each value (in the order
// given), `echo` echoes them all.
template <typename Options>
OptionRow<Options> RepeatedRow(
    const std::string& name,
    const std::string& help,
    std::function<void(Options*, const std::string&)> add,
    std::function<nlohmann::json(const Options&)> echo) {
  OptionRow<Options> row;
  row.name = name;
  row.help = help;
  row.echo_key = name;
  row.value = OptionText<Options>{
      {}, [](const Options&) { return std::string(); }, std::move(add), ""};
  row.repeatable = true;
  row.show_default = false;
  row.echo = std::move(echo);
  return row;
}

// A flag without a value that sets a bool field to `value_when_given`; the
// echo is the field under `echo_key` (e.g. --no_refine echoes "refine").
template <typename Options, typename Field>
OptionRow<Options> SwitchRow(const std::string& name,
                             const std::string& help,
                             const std::string& echo_key,
                             Field field,
                             bool value_when_given) {
  OptionRow<Options> row;
  row.name = name;
  row.help = help;
  row.echo_key = echo_key;
  row.value = OptionSwitch<Options>{
      [field, value_when_given](Options* o) { field(*o) = value_when_given; }};
  row.echo = [field](const Options& options) {
    return nlohmann::json(field(options));
  };
  return row;
}

// The numbers an AutoOrNumberRow takes besides "auto": finite and above
// `min`, or at it too when `min_allowed`.
struct AutoOrNumberLimit {
  double min = 0.0;
  bool min_allowed = true;
};

// What is wrong with `text` as "auto" or a number within `limit` ("" when
// nothing): "must be auto or a number, got 'x'", "must be >= 0, got -3",
// "must be finite and > 0, got -1".
inline std::string AutoOrNumberError(const std::string& text,
                                     AutoOrNumberLimit limit) {
  if (text == "auto") return "";
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) {
    return "must be auto or a number, got '" + text + "'";
  }
  const bool within =
      limit.min_allowed ? value >= limit.min : value > limit.min;
  if (!std::isfinite(value) || !within) {
    return std::string("must be ") +
           (limit.min_allowed ? ">= " : "finite and > ") +
           FormatNumber(limit.min) + ", got " + FormatNumber(value);
  }
  return "";
}

// A number field that also takes "auto", stored as `automatic` (a value no
// valid number takes). --help's default and the echo say "auto" for it,
// else the number (a report may echo the value used instead).
template <typename Options, typename Field>
OptionRow<Options> AutoOrNumberRow(const std::string& name,
                                   const std::string& help,
                                   Field field,
                                   double automatic,
                                   AutoOrNumberLimit limit) {
  OptionRow<Options> row;
  row.name = name;
  row.help = help;
  row.echo_key = name;
  row.value = OptionText<Options>{
      {},
      [field, automatic](const Options& options) {
        const double value = field(options);
        return value == automatic ? std::string("auto") : FormatNumber(value);
      },
      [field, automatic](Options* options, const std::string& text) {
        field(*options) =
            text == "auto" ? automatic : std::strtod(text.c_str(), nullptr);
      },
      "FLOAT"};  // or auto
  row.check = FlagCheck::Custom([limit](const std::string& text) {
    return AutoOrNumberError(text, limit);
  });
  row.echo = [field, automatic](const Options& options) {
    const double value = field(options);
    return value == automatic ? nlohmann::json("auto") : nlohmann::json(value);
  };
  return row;
}

// `row`, echoed in the member `object` of the echo object.
template <typename Options>
OptionRow<Options> EchoedIn(const std::string& object, OptionRow<Options> row) {
  row.echo_object = object;
  return row;
}

}  // namespace odomcal
