// odomcal as a library for COLMAP users (CMake target odomcal::plugin):
// calibrate the camera-to-odometry extrinsic odom_from_cam and the metric
// scale of a COLMAP reconstruction against wheel odometry.
//
//   (a) An existing COLMAP project: CalibrateColmapProject(inputs) reads the
//       model (a sparse folder or the mapper's root with sub-models 0, 1,
//       ...), the optional database, the odometry and the image times, and
//       returns the calibration (check.result), the sub-models in metres in
//       the odometry's origin frame (metric_models) and the diagnostics
//       (association, stretches left out, scale changes, warnings).
//   (b) An image folder with its odometry: ReconstructAndCalibrate(options,
//       progress) runs COLMAP in options.workspace_path (what `odomcal run`
//       does: frame selection, features, odometry-guided matching, mapper
//       runs chosen by the odometry, calibration) and returns the same
//       calibration plus every mapper attempt.
//
// Nothing is printed and nothing is written outside the workspace of (b); (a)
// writes nothing. Errors are exceptions with one-line messages:
// FormatError (adapters/format_error.h) for unreadable inputs,
// std::invalid_argument for bad options, OutputError for a workspace that
// cannot be used, ColmapError when COLMAP fails. A calibration the data do
// not determine is not an error: check.result.status says why.
//
// The files of `odomcal colmap` (calibration.json, report.html, the model in
// metres) are written by odomcal::reports (colmap_calibration_outputs.h).
#pragma once

#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/plugin/colmap/reconstruction_pipeline.h"
