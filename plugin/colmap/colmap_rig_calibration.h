// A COLMAP project with several cameras of one robot (colmap_cameras.h):
// every camera calibrated against the one odometry from its own images
// (CalibrateColmapProject with the camera's camera_ids), each with its own
// clock offset, floor height and metric model; then, where two cameras'
// images share a sub-model, their metric scales compared: one model has one
// scale, so two cameras that disagree on it cannot both be right. Then the
// calibrated cameras are adjusted together (rig_joint_adjustment.h): as a
// check of their own estimates (`--joint_adjustment check`, the default) or
// reported (`on`).
#pragma once

#include "odomcal/adapters/colmap_cameras.h"
#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/plugin/colmap/rig_joint_adjustment.h"

#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct ColmapRigCameraRun {
  ColmapProjectCamera camera;
  ColmapCalibrationInputs inputs;  // the project's, with camera_ids set
  // The calibration; absent when this camera's images do not fit the
  // odometry (input_error says why: no time stamp inside it, ...).
  std::optional<ColmapCalibrationRun> run;
  std::string input_error;
  std::string failure_status;  // "colmap_failed"; empty: "input_error"
};

// The metric scale of one sub-model as two cameras calibrated it.
struct SharedSubModelScale {
  int camera_a = 0;  // indices into ColmapRigRun::cameras
  int camera_b = 0;
  std::string sub_model;
  double scale_a = 0.0;  // metres per model unit
  double scale_b = 0.0;
  // (scale_b / scale_a - 1) over its standard deviation (the two relative
  // sigmas in quadrature); +-inf when neither scale has a sigma.
  double sigmas = 0.0;
  bool Disagrees() const;  // beyond 3 sigma
};

struct ColmapRigRun {
  ColmapCameraGrouping grouping = ColmapCameraGrouping::kBySubFolder;
  std::vector<ColmapRigCameraRun> cameras;
  int reference = 0;
  // Every sub-model two calibrated cameras both hold as one segment.
  std::vector<SharedSubModelScale> shared_scales;
  // Every calibrated camera adjusted together (`--joint_adjustment check`
  // or `on`; not run under `off`: ran false, skipped empty).
  RigJointAdjustment joint;
};

// Under `--joint_adjustment check` or `on` (inputs.joint_adjustment.use),
// adjusts the rig's calibrated cameras together into rig->joint.
void AdjustColmapRigJointly(const ColmapCalibrationInputs& inputs,
                            const CalibrationProgress& progress,
                            ColmapRigRun* rig);

// Calibrates every camera of `cameras` (FindColmapProjectCameras) with
// `inputs`' options. `reference` indexes `cameras.cameras`. Throws
// std::invalid_argument for bad options and a reference out of range, and
// FormatError for errors of the project or the odometry (not of one
// camera's images).
ColmapRigRun CalibrateColmapRig(const ColmapCalibrationInputs& inputs,
                                const ColmapProjectCameras& cameras,
                                int reference,
                                const CalibrationProgress& progress = {});

// The index of the camera named `name` (0, the first, when empty). Throws
// std::invalid_argument naming --reference_camera when none is.
int ColmapReferenceCamera(const ColmapProjectCameras& cameras,
                          const std::string& name);

// "cameras front and rear disagree on the scale of sub-model 0 by 4.1 %
// (6.2 sigma): ..." per disagreement.
std::vector<std::string> SharedScaleWarnings(const ColmapRigRun& rig);

}  // namespace odomcal
