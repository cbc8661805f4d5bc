// Calibration flags shared by the commands that calibrate (calibrate, colmap,
// run, demo). Flag names are public interface: keep them stable (docs/cli.md).
#pragma once

#include "odomcal/plugin/calibrate_command.h"

#include <CLI/CLI.hpp>

#include <string>

namespace odomcal {

// Text flags held until they are converted into CalibrateInputs.
struct CalibrationFlags {
  std::string method = "alsp";
  std::string alsp_projection = "orthogonal";
  std::string ransac = "on";
  std::string robust_loss = "none";
  std::string odometry_format = "auto";
  std::string camera_time_unit = "s";
  std::string odometry_time_unit = "s";
  // --odometry_time_unit given on the command line: then an odometry CSV
  // header that names another time unit is an error.
  bool odometry_time_unit_given = false;
  double camera_time_offset_s = 0.0;
  bool no_refine = false;
};

void AddCalibrationFlags(CLI::App* app,
                         CalibrateInputs* inputs,
                         CalibrationFlags* flags);

// Converts the text flags; throws std::invalid_argument naming the flag.
void FinishCalibrationFlags(const CalibrationFlags& flags,
                            CalibrateInputs* inputs);

}  // namespace odomcal
