// The single source of truth for the flags of an options struct: one table
// per struct, one row per flag. A row says the flag's name, its help text, its
// check, the field it sets (whose value is the default shown by --help) and
// the key under which the result JSON echoes the value. The CLI registers its
// flags from these tables (cli_flags.cc, project_flags.cc, run_flags.cc) and
// makes the echo of the values from them (CalibrationFlagsEcho,
// ProjectFlagsEcho, RunFlagsEcho), which it hands the report writers in
// ReportContext::flag_echo (calibration_report.h): the reports and the
// library know nothing of flags. tests/flag_table_test.cc checks docs/cli.md
// and the echo against the CLI.
//
// Field names are the flag names without "--" (CalibrationOptions::Check
// names fields, and the CLI rewrites them into flags), so a row's name is
// the field's, the flag's and, but for --no_refine (echoed as "refine"), the
// echo's key.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace odomcal {

template <typename Options>
struct OptionRow {
  std::string name;         // the flag without "--"
  std::string help;         // --help text
  std::string echo_key;     // key in the echo object
  std::string echo_object;  // "": the echo object itself, else a member
  // Registers the flag on `app`, bound to the field of `options`, whose
  // current value is shown as the default.
  std::function<CLI::Option*(CLI::App* app, Options* options)> add;
  // The value echoed in the result JSON; empty for rows whose value the
  // report echoes from elsewhere (see the table's comment).
  std::function<nlohmann::json(const Options& options)> echo;
};

template <typename Options>
using OptionTable = std::vector<OptionRow<Options>>;

// Registers every flag of `table`, in table order.
template <typename Options>
void AddFlags(const OptionTable<Options>& table,
              CLI::App* app,
              Options* options) {
  for (const OptionRow<Options>& row : table) row.add(app, options);
}

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

// A number (or other type CLI11 converts) bound to a field. `field` maps an
// options struct to the field, const or not, e.g.
//   [](auto& o) -> auto& { return o.noise.odom_yaw_sigma_deg; }
template <typename Options, typename Field>
OptionRow<Options> NumberRow(std::string name,
                             std::string help,
                             Field field,
                             std::optional<CLI::Validator> check = {}) {
  OptionRow<Options> row;
  row.name = name;
  row.help = help;
  row.echo_key = name;
  row.add = [name, help, field, check](CLI::App* app, Options* options) {
    CLI::Option* option = app->add_option("--" + name, field(*options), help);
    if (check) option->check(*check);
    return option->capture_default_str();
  };
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
    std::string name,
    std::string help,
    std::vector<std::string> choices,
    std::function<std::string(const Options&)> get,
    std::function<void(Options*, const std::string&)> set) {
  OptionRow<Options> row;
  row.name = name;
  row.help = help;
  row.echo_key = name;
  row.add = [name, help, choices, get, set](CLI::App* app, Options* options) {
    return app
        ->add_option_function<std::string>(
            "--" + name,
            [options, set](const std::string& value) { set(options, value); },
            help)
        ->check(CLI::IsMember(choices))
        ->default_str(get(*options));
  };
  row.echo = [get](const Options& options) {
    return nlohmann::json(get(options));
  };
  return row;
}

// A flag without a value that sets a bool field to `value_when_given`; the
// echo is the field under `echo_key` (e.g. --no_refine echoes "refine").
template <typename Options, typename Field>
OptionRow<Options> SwitchRow(std::string name,
                             std::string help,
                             std::string echo_key,
                             Field field,
                             bool value_when_given) {
  OptionRow<Options> row;
  row.name = name;
  row.help = help;
  row.echo_key = echo_key;
  row.add = [name, help, field, value_when_given](CLI::App* app,
                                                  Options* options) {
    return app->add_flag_callback(
        "--" + name,
        [options, field, value_when_given]() {
          field(*options) = value_when_given;
        },
        help);
  };
  row.echo = [field](const Options& options) {
    return nlohmann::json(field(options));
  };
  return row;
}

// `row`, echoed in the member `object` of the echo object.
template <typename Options>
OptionRow<Options> EchoedIn(std::string object, OptionRow<Options> row) {
  row.echo_object = std::move(object);
  return row;
}

}  // namespace odomcal
