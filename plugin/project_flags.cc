#include "odomcal/plugin/project_flags.h"

#include "odomcal/plugin/command_line.h"

namespace odomcal {
namespace {

using Project = ColmapCalibrationInputs;

// A path flag: no default, checked to exist (`check`); echoed as given,
// null when not given.
OptionRow<Project> PathRow(std::string name,
                           std::string help,
                           std::string Project::*field,
                           bool required,
                           const CLI::Validator& check) {
  OptionRow<Project> row;
  row.name = name;
  row.help = help;
  row.echo_key = name;
  row.add = [name, help, field, required, check](CLI::App* app,
                                                 Project* inputs) {
    CLI::Option* option = app->add_option("--" + name, inputs->*field, help);
    if (required) option->required();
    return option->check(check);
  };
  row.echo = [field](const Project& inputs) {
    const std::string& path = inputs.*field;
    return path.empty() ? nlohmann::json(nullptr) : nlohmann::json(path);
  };
  return row;
}

}  // namespace

const OptionTable<ColmapCalibrationInputs>& ColmapModelFlags() {
  static const OptionTable<Project> table = {
      PathRow("model_path",
              "COLMAP sparse model folder, or the mapper's output folder with "
              "sub-models 0, 1, ...",
              &Project::model_path,
              true,
              CLI::ExistingDirectory),
      PathRow("database_path",
              "the project's database.db (read-only; counts unregistered "
              "images)",
              &Project::database_path,
              false,
              CLI::ExistingFile),
  };
  return table;
}

const OptionTable<ColmapCalibrationInputs>& ProjectInputFlags() {
  static const OptionTable<Project> table = {
      PathRow("odometry",
              "wheel odometry: CSV 'timestamp,x,y,yaw' (m, rad) or TUM "
              "origin_from_odom",
              &Project::odometry_path,
              true,
              CLI::ExistingFile),
      PathRow("image_timestamps",
              "CSV 'image_name,timestamp' (unit: --camera_time_unit); "
              "without it, times come from numeric image file names",
              &Project::image_timestamps_path,
              false,
              CLI::ExistingFile),
      ChoiceRow<Project>(
          "file_name_time_unit",
          "unit of numeric image file names; auto: integer stems are ns, "
          "stems with a decimal point are s",
          {"auto", "s", "ms", "us", "ns"},
          [](const Project& inputs) -> std::string {
            return inputs.file_name_time_unit
                       ? TimeUnitName(*inputs.file_name_time_unit)
                       : "auto";
          },
          [](Project* inputs, const std::string& name) {
            inputs->file_name_time_unit.reset();
            if (name != "auto")
              inputs->file_name_time_unit = ParseTimeUnit(name);
          }),
  };
  return table;
}

const OptionTable<StretchOptions>& StretchFlags() {
  static const OptionTable<StretchOptions> table = {
      NumberRow<StretchOptions>(
          "min_inconsistent_run_pairs",
          "consecutive motion pairs contradicting the odometry that make a "
          "stretch to cut out or split off",
          [](auto& o) -> auto& { return o.min_run_pairs; },
          AtLeast(1)),
  };
  return table;
}

void AddProjectFlags(CLI::App* app,
                     ColmapCalibrationInputs* inputs,
                     ProjectFlags* flags) {
  AddFlags(ProjectInputFlags(), app, inputs);
  AddFlags(StretchFlags(), app, &inputs->stretch);
  AddCalibrationFlags(app, &flags->calibrate);
}

void FinishProjectFlags(const ProjectFlags& flags,
                        ColmapCalibrationInputs* inputs) {
  const CalibrateInputs& calibrate = flags.calibrate;
  inputs->odometry_format = calibrate.odometry_format;
  inputs->odometry_time_unit = calibrate.odometry_time_unit;
  inputs->odometry_time_unit_given = calibrate.odometry_time_unit_given;
  inputs->image_time_unit = calibrate.camera_time_unit;
  inputs->association = calibrate.association;
  inputs->calibration = calibrate.calibration;
  inputs->systematics = calibrate.systematics;
}

nlohmann::json ProjectFlagsEcho(const ColmapCalibrationInputs& inputs) {
  nlohmann::json echo = CalibrationFlagsEcho(
      inputs.association, inputs.calibration, inputs.systematics);
  EchoOptions(ColmapModelFlags(), inputs, &echo["inputs"]);
  EchoOptions(ProjectInputFlags(), inputs, &echo["inputs"]);
  EchoOptions(StretchFlags(), inputs.stretch, &echo["options"]);
  return echo;
}

void PrepareOutputFolder(const FlaggedPath& output,
                         const std::vector<FlaggedPath>& inputs,
                         const std::vector<std::string>& entries,
                         ExistingOutputs existing) {
  GuardedPaths paths;
  paths.inputs = inputs;
  paths.output_folders = {output};
  CheckOutputsApartFromInputs(paths);
  ClaimOutputFolder(output.path, entries, existing);
}

}  // namespace odomcal
