#include "odomcal/plugin/project_flags.h"

namespace odomcal {

void AddProjectFlags(CLI::App* app,
                     ColmapCalibrationInputs* inputs,
                     ProjectFlags* flags) {
  app->add_option("--odometry",
                  inputs->odometry_path,
                  "wheel odometry: CSV 'timestamp,x,y,yaw' (m, rad) or TUM "
                  "origin_from_odom")
      ->required()
      ->check(CLI::ExistingFile);
  app->add_option("--image_timestamps",
                  inputs->image_timestamps_path,
                  "CSV 'image_name,timestamp' (unit: --camera_time_unit); "
                  "without it, times come from numeric image file names")
      ->check(CLI::ExistingFile);
  app->add_option("--file_name_time_unit",
                  flags->file_name_time_unit,
                  "unit of numeric image file names; auto: integer stems are "
                  "ns, stems with a decimal point are s")
      ->check(CLI::IsMember({"auto", "s", "ms", "us", "ns"}))
      ->capture_default_str();
  app->add_option("--min_inconsistent_run_pairs",
                  inputs->stretch.min_run_pairs,
                  "consecutive motion pairs contradicting the odometry that "
                  "make a stretch to cut out or split off")
      ->check(AtLeast(1))
      ->capture_default_str();
  AddCalibrationFlags(app, &flags->calibrate, &flags->calibration);
}

void FinishProjectFlags(const ProjectFlags& flags,
                        ColmapCalibrationInputs* inputs) {
  CalibrateInputs calibrate = flags.calibrate;
  FinishCalibrationFlags(flags.calibration, &calibrate);
  inputs->odometry_format = calibrate.odometry_format;
  inputs->odometry_time_unit = calibrate.odometry_time_unit;
  inputs->odometry_time_unit_given = calibrate.odometry_time_unit_given;
  inputs->image_time_unit = calibrate.camera_time_unit;
  inputs->association = calibrate.association;
  inputs->calibration = calibrate.calibration;
  if (flags.file_name_time_unit != "auto") {
    inputs->file_name_time_unit = ParseTimeUnit(flags.file_name_time_unit);
  }
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
