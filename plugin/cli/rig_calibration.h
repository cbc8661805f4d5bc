// Several cameras of one robot, each calibrated against the one odometry:
// every camera's own trajectory (its own time stamps, rate, scale and clock
// offset) through the calibrate pipeline (CalibrateTrajectories), then the
// transform between every two calibrated cameras (solver/camera_pair.h).
// A camera that cannot be calibrated keeps its status and reason; the others
// are calibrated all the same. For `odomcal calibrate --camera` and any
// command that has one trajectory per camera.
#pragma once

#include "odomcal/adapters/trajectory.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/colmap/rig_joint_adjustment.h"
#include "odomcal/solver/camera_pair.h"

#include <optional>
#include <string>
#include <vector>

namespace odomcal {

// One camera: its name and its trajectory, one per SfM segment (each with
// its own scale).
struct NamedCamera {
  std::string name;
  std::vector<Trajectory> segments;
};

// "--camera NAME=PATH" values in order: a repeated name adds a segment to
// that camera. Throws std::invalid_argument naming --camera for a value
// without NAME= or PATH, a name that is not 1-100 characters of A-Z a-z 0-9
// _ - . (it becomes a frame name), or a file given twice.
struct NamedCameraPaths {
  std::string name;
  std::vector<std::string> paths;
};
std::vector<NamedCameraPaths> ParseNamedCameras(
    const std::vector<std::string>& values);

// Throws std::invalid_argument "<where>: a camera name is 1-100 characters
// of A-Z a-z 0-9 _ - ." (or "... is empty") unless `name` is one.
void CheckCameraName(const std::string& name, const std::string& where);

// The index of `reference` among the cameras (0, the first, when empty).
// Throws std::invalid_argument naming --reference_camera when no camera has
// that name.
int ReferenceCameraIndex(const std::vector<NamedCameraPaths>& cameras,
                         const std::string& reference);

struct RigCameraRun {
  std::string name;
  // The pipeline's result and context; for a camera whose input the
  // pipeline refused (e.g. no time stamp inside the odometry), status
  // kNotRun and input_error says why.
  CalibrationRun run;
  std::string input_error;
  // The status of a camera whose pipeline failed: "colmap_failed" (COLMAP
  // gave it no model); empty: "input_error".
  std::string failure_status;
  // The extrinsic with its covariance when the camera was calibrated.
  std::optional<ExtrinsicWithCovariance> extrinsic;

  bool Calibrated() const { return extrinsic.has_value(); }
  // A calibration status name, or failure_status / "input_error".
  std::string Status() const;
  // The result's message, or the input error.
  std::string Reason() const;
};

struct RigCameraPair {
  int camera_a = 0;  // index into RigCalibrationRun::cameras
  int camera_b = 0;
  CameraPairTransform transform;  // camB_from_camA
  // Both cameras from the rig's joint adjustment: the transform's
  // covariance holds their cross terms (else they count as independent).
  bool adjusted_together = false;
};

struct RigCalibrationRun {
  std::vector<RigCameraRun> cameras;
  int reference = 0;
  // Every two calibrated cameras, A before B in the given order.
  std::vector<RigCameraPair> pairs;
  // The rig's own findings (cameras that disagree on a shared scale).
  std::vector<std::string> findings;
  // A COLMAP rig under `--joint_adjustment check` or `on`: the cameras
  // adjusted together (their extrinsics are the adjustment's where it was
  // adopted).
  RigJointAdjustment joint;

  int NumCalibrated() const;
  // "camera rear not calibrated (not_enough_motion): ..." per camera that
  // was not calibrated, then the findings.
  std::vector<std::string> Warnings() const;
};

// Fills rig->pairs from its calibrated cameras (with the cross terms of
// rig->joint for two cameras it adjusted and that were adopted).
void PairCalibratedCameras(RigCalibrationRun* rig);

// Takes `joint` into the rig: where it was adopted (RigJointAdjustment::
// Adopted), each of its cameras' rotation and translation x/y and their
// covariance become the adjustment's (AdoptJointExtrinsic; refused as
// kUnobservable beyond `limits`, RefuseLooseAdoptedExtrinsic); a check
// that contradicted a camera names each quantity in the findings. Under
// `on`, an adjustment that failed or did not run is a finding; under the
// check, it is said in the JSON only (the cameras' own estimates stand, as
// without it). Then pairs the cameras again.
void AdoptRigJointAdjustment(const RigJointAdjustment& joint,
                             const CalibrationOptions& limits,
                             RigCalibrationRun* rig);

// Calibrates every camera against `odometry` with `inputs`' options (its
// paths are not used). Throws std::invalid_argument for bad options and for
// a reference index out of range.
RigCalibrationRun CalibrateRig(const std::vector<NamedCamera>& cameras,
                               const Trajectory& odometry,
                               const CalibrateInputs& inputs,
                               int reference,
                               const std::string& command);

}  // namespace odomcal
