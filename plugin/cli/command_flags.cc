#include "odomcal/plugin/cli/command_flags.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/plugin/cli/command_line.h"

namespace odomcal {
namespace {

using Inputs = CalibrateInputs;

const std::vector<std::string> kTimeUnits = {"s", "ms", "us", "ns"};

}  // namespace

CLI::Validator FlagValidator(const FlagCheck& check) {
  switch (check.kind) {
    case FlagCheck::Kind::kNone:
      break;
    case FlagCheck::Kind::kAtLeast:
      return AtLeast(check.min);
    case FlagCheck::Kind::kInRange:
      return InRange(check.min, check.max);
    case FlagCheck::Kind::kExistingFile:
      return CLI::ExistingFile;
    case FlagCheck::Kind::kExistingDirectory:
      return CLI::ExistingDirectory;
    case FlagCheck::Kind::kCustom:
      return CLI::Validator(
          [custom = check.custom](std::string& text) { return custom(text); },
          "");
  }
  return CLI::Validator();
}

const OptionTable<CalibrateInputs>& InputFormatFlags() {
  static const OptionTable<Inputs> table = [] {
    OptionTable<Inputs> rows = {
        ChoiceRow<Inputs>(
            "odometry_format",
            "odometry file format",
            {"auto", "tum", "csv"},
            [](const Inputs& i) {
              return OdometryFormatName(i.odometry_format);
            },
            [](Inputs* i, const std::string& name) {
              i->odometry_format = ParseOdometryFormat(name);
            }),
        ChoiceRow<Inputs>(
            "camera_time_unit",
            "unit of the camera timestamps",
            kTimeUnits,
            [](const Inputs& i) { return TimeUnitName(i.camera_time_unit); },
            [](Inputs* i, const std::string& name) {
              i->camera_time_unit = ParseTimeUnit(name);
            }),
        // Given on the command line, a CSV header naming another unit is an
        // error; the default gives way to the header.
        ChoiceRow<Inputs>(
            "odometry_time_unit",
            "unit of the odometry timestamps (a CSV header's time_ms etc. "
            "sets it per file)",
            kTimeUnits,
            [](const Inputs& i) { return TimeUnitName(i.odometry_time_unit); },
            [](Inputs* i, const std::string& name) {
              i->odometry_time_unit = ParseTimeUnit(name);
              i->odometry_time_unit_given = true;
            }),
    };
    for (OptionRow<Inputs>& row : rows) row.echo = nullptr;
    return rows;
  }();
  return table;
}

void AddCalibrationFlags(CLI::App* app, CalibrateInputs* inputs) {
  AddFlags(InputFormatFlags(), app, inputs);
  AddFlags(AssociationFlags(), app, &inputs->association);
  AddFlags(CalibrationOptionFlags(), app, &inputs->calibration);
  AddFlags(SystematicsFlags(), app, &inputs->systematics);
  AddFlags(RobotFrameFlags(), app, &inputs->robot_frames);
}

void AddProjectFlags(CLI::App* app,
                     ColmapCalibrationInputs* inputs,
                     ProjectFlags* flags) {
  AddFlags(ProjectInputFlags(), app, inputs);
  AddFlags(StretchFlags(), app, &inputs->stretch);
  AddFlags(FloorPlaneFlags(), app, &inputs->floor);
  AddFlags(JointAdjustmentFlags(), app, &inputs->joint_adjustment);
  AddCalibrationFlags(app, &flags->calibrate);
  flags->fixed_translation_z = app->get_option("--fixed_translation_z_m");
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
  inputs->robot_frames = calibrate.robot_frames;
  if (flags.fixed_translation_z != nullptr &&
      flags.fixed_translation_z->count() > 0 &&
      inputs->floor.use == FloorPlaneUse::kEstimateZ) {
    inputs->floor.use = FloorPlaneUse::kCheck;
  }
}

void AddRunFlags(CLI::App* app, ReconstructionOptions* settings) {
  AddFlags(RunFolderFlags(), app, settings);
  AddFlags(RunFlags(), app, settings);
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
