// The command line's flags: registers the rows of the option tables
// (option_table.h; cli_flags.h, project_flags.h, run_flags.h) as CLI11
// flags bound to the options structs, plus the flags only the command line
// has (how the input files are read) and the output-folder rules.
#pragma once

#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/plugin/colmap/reconstruction_pipeline.h"
#include "odomcal/plugin/options/cli_flags.h"
#include "odomcal/plugin/options/option_table.h"
#include "odomcal/plugin/options/project_flags.h"
#include "odomcal/plugin/options/run_flags.h"
#include "odomcal/plugin/output/output_folder.h"
#include "odomcal/plugin/output/output_guard.h"

#include <CLI/CLI.hpp>

#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace odomcal {

// The CLI11 validator of `check` (none for FlagCheck::Kind::kNone).
CLI::Validator FlagValidator(const FlagCheck& check);

// Registers `row` on `app`, bound to `options` (whose current values are
// the defaults shown).
template <typename Options>
CLI::Option* AddFlag(const OptionRow<Options>& row,
                     CLI::App* app,
                     Options* options) {
  const std::string flag = "--" + row.name;
  CLI::Option* option = nullptr;
  std::visit(
      [&](const auto& value) {
        using Value = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<Value, OptionText<Options>>) {
          if (row.repeatable) {
            // One value per occurrence: "--flag a --flag b".
            option =
                app->add_option(flag)
                    ->description(row.help)
                    ->type_name("TEXT")
                    ->expected(1)
                    ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
                    ->each([options, set = value.set](const std::string& text) {
                      set(options, text);
                    });
            return;
          }
          option = app->add_option_function<std::string>(
              flag,
              [options, set = value.set](const std::string& text) {
                set(options, text);
              },
              row.help);
          if (!value.choices.empty()) {
            option->check(CLI::IsMember(value.choices));
          }
          if (!value.type_name.empty()) option->type_name(value.type_name);
          if (row.show_default) option->default_str(value.get(*options));
        } else if constexpr (std::is_same_v<Value, OptionSwitch<Options>>) {
          option = app->add_flag_callback(
              flag, [options, set = value.set]() { set(options); }, row.help);
        } else {
          option = app->add_option(flag, value(*options), row.help);
          if (row.show_default) option->capture_default_str();
        }
      },
      row.value);
  if (row.check.kind != FlagCheck::Kind::kNone) {
    option->check(FlagValidator(row.check));
  }
  if (row.required) option->required();
  return option;
}

// Registers every flag of `table`, in table order.
template <typename Options>
void AddFlags(const OptionTable<Options>& table,
              CLI::App* app,
              Options* options) {
  for (const OptionRow<Options>& row : table) AddFlag(row, app, options);
}

// How the input files are read: --odometry_format, --camera_time_unit,
// --odometry_time_unit. Not echoed: the report echoes in `inputs` the units
// and format it is given in ReportContext (for `odomcal colmap` without
// --image_timestamps the camera times come "from image file names").
const OptionTable<CalibrateInputs>& InputFormatFlags();

// Registers InputFormatFlags(), AssociationFlags() and
// CalibrationOptionFlags(), in the order of docs/cli.md, bound to `inputs`:
// after parsing, `inputs` holds every value given.
void AddCalibrationFlags(CLI::App* app, CalibrateInputs* inputs);

struct ProjectFlags {
  CalibrateInputs calibrate;  // the calibration flags
  // --fixed_translation_z_m, whose presence turns --floor_plane estimate
  // into check: a given z overrides the floor's.
  const CLI::Option* fixed_translation_z = nullptr;
};

// ProjectInputFlags(), StretchFlags() and the calibration flags.
void AddProjectFlags(CLI::App* app,
                     ColmapCalibrationInputs* inputs,
                     ProjectFlags* flags);

// Copies the calibration flags into `inputs`; a given
// --fixed_translation_z_m makes the floor plane a check.
void FinishProjectFlags(const ProjectFlags& flags,
                        ColmapCalibrationInputs* inputs);

// Registers RunFolderFlags() and RunFlags(), bound to `settings` (not its
// `project`: the project flags are AddProjectFlags').
void AddRunFlags(CLI::App* app, ReconstructionOptions* settings);

// Checks the output folder `output` against `inputs` (output_guard.h), then
// creates it if needed and claims `entries` in it (output_folder.h), before
// any work. Throws OutputError.
void PrepareOutputFolder(const FlaggedPath& output,
                         const std::vector<FlaggedPath>& inputs,
                         const std::vector<std::string>& entries,
                         ExistingOutputs existing);

}  // namespace odomcal
