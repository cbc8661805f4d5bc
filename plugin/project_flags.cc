#include "odomcal/plugin/project_flags.h"

#include <filesystem>

#include "odomcal/plugin/output_file.h"

namespace odomcal {

namespace fs = std::filesystem;

void AddProjectFlags(CLI::App* app,
                     ColmapCalibrationInputs* inputs,
                     ProjectFlags* flags) {
  app->add_option("--odometry", inputs->odometry_path,
                  "wheel odometry: CSV 'timestamp,x,y,yaw' (m, rad) or TUM "
                  "origin_from_odom")
      ->required()
      ->check(CLI::ExistingFile);
  app->add_option("--image_timestamps", inputs->image_timestamps_path,
                  "CSV 'image_name,timestamp' (unit: --camera_time_unit); "
                  "without it, times come from numeric image file names")
      ->check(CLI::ExistingFile);
  app->add_option("--file_name_time_unit", flags->file_name_time_unit,
                  "unit of numeric image file names; auto: integer stems are "
                  "ns, stems with a decimal point are s")
      ->check(CLI::IsMember({"auto", "s", "ms", "us", "ns"}))
      ->capture_default_str();
  app->add_option("--min_inconsistent_run_pairs", inputs->stretch.min_run_pairs,
                  "consecutive motion pairs contradicting the odometry that "
                  "make a stretch to cut out or split off")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  AddCalibrationFlags(app, &flags->calibrate, &flags->calibration);
}

void FinishProjectFlags(const ProjectFlags& flags, ColmapCalibrationInputs* inputs) {
  CalibrateInputs calibrate = flags.calibrate;
  FinishCalibrationFlags(flags.calibration, &calibrate);
  inputs->odometry_format = calibrate.odometry_format;
  inputs->odometry_time_unit = calibrate.odometry_time_unit;
  inputs->image_time_unit = calibrate.camera_time_unit;
  inputs->association = calibrate.association;
  inputs->calibration = calibrate.calibration;
  if (flags.file_name_time_unit != "auto") {
    inputs->file_name_time_unit = ParseTimeUnit(flags.file_name_time_unit);
  }
}

void PrepareOutputFolder(const std::string& output_dir,
                         bool overwrite,
                         const std::vector<std::string>& protected_paths) {
  std::error_code error;
  const fs::path output = fs::weakly_canonical(fs::absolute(output_dir), error);
  for (const std::string& input : protected_paths) {
    if (input.empty()) continue;
    const fs::path root = fs::weakly_canonical(fs::absolute(input), error);
    const auto mismatch =
        std::mismatch(root.begin(), root.end(), output.begin(), output.end());
    if (mismatch.first == root.end()) {
      throw OutputError(output_dir + ": is inside the input " + input +
                        "; odomcal never writes into an input project");
    }
  }
  if (fs::exists(output_dir, error)) {
    if (!fs::is_directory(output_dir, error)) {
      throw OutputError(output_dir + ": exists and is not a folder");
    }
    if (!fs::is_empty(output_dir, error) && !overwrite) {
      throw OutputError(output_dir +
                        ": is not empty (pass --overwrite to replace odomcal's "
                        "files in it)");
    }
    return;
  }
  fs::create_directories(output_dir, error);
  if (error) {
    throw OutputError(output_dir + ": cannot create (" + error.message() + ")");
  }
}

}  // namespace odomcal
