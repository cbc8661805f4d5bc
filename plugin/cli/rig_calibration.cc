#include "odomcal/plugin/cli/rig_calibration.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/input_plausibility.h"
#include "odomcal/solver/format_number.h"
#include "odomcal/solver/joint_extrinsic.h"

#include <map>
#include <set>
#include <stdexcept>

namespace odomcal {
namespace {

bool IsCameraName(const std::string& name) {
  if (name.empty() || name.size() > 100) return false;
  for (const char c : name) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') ||
                    (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

}  // namespace

void CheckCameraName(const std::string& name, const std::string& where) {
  if (name.empty()) {
    throw std::invalid_argument(where + ": the camera name is empty");
  }
  if (!IsCameraName(name)) {
    throw std::invalid_argument(
        where + ": a camera name is 1-100 characters of A-Z a-z 0-9 _ - .");
  }
}

std::vector<NamedCameraPaths> ParseNamedCameras(
    const std::vector<std::string>& values) {
  std::vector<NamedCameraPaths> cameras;
  std::map<std::string, size_t> index;
  std::set<std::string> paths;
  for (const std::string& value : values) {
    const size_t equals = value.find('=');
    if (equals == std::string::npos) {
      throw std::invalid_argument("--camera '" + value +
                                  "': expected NAME=PATH");
    }
    const std::string name = value.substr(0, equals);
    const std::string path = value.substr(equals + 1);
    if (name.empty()) {
      throw std::invalid_argument("--camera '" + value +
                                  "': the camera name before '=' is empty");
    }
    if (!IsCameraName(name)) {
      throw std::invalid_argument(
          "--camera '" + value +
          "': a camera name is 1-100 characters of A-Z a-z 0-9 _ - .");
    }
    if (path.empty()) {
      throw std::invalid_argument("--camera '" + value +
                                  "': the path after '=' is empty");
    }
    if (!paths.insert(path).second) {
      throw std::invalid_argument("--camera '" + value + "': the file " + path +
                                  " is given twice");
    }
    const auto found = index.find(name);
    if (found == index.end()) {
      index[name] = cameras.size();
      cameras.push_back({name, {path}});
    } else {
      cameras[found->second].paths.push_back(path);
    }
  }
  return cameras;
}

int ReferenceCameraIndex(const std::vector<NamedCameraPaths>& cameras,
                         const std::string& reference) {
  if (reference.empty()) return 0;
  std::string names;
  for (size_t k = 0; k < cameras.size(); ++k) {
    if (cameras[k].name == reference) return static_cast<int>(k);
    names += (k == 0 ? "" : ", ") + cameras[k].name;
  }
  throw std::invalid_argument("--reference_camera '" + reference +
                              "' names no camera given with --camera (" +
                              names + ")");
}

std::string RigCameraRun::Status() const {
  if (input_error.empty()) return ToString(run.result.status);
  return failure_status.empty() ? "input_error" : failure_status;
}

std::string RigCameraRun::Reason() const {
  return input_error.empty() ? run.result.message : input_error;
}

int RigCalibrationRun::NumCalibrated() const {
  int count = 0;
  for (const RigCameraRun& camera : cameras) count += camera.Calibrated();
  return count;
}

std::vector<std::string> RigCalibrationRun::Warnings() const {
  std::vector<std::string> warnings;
  for (const RigCameraRun& camera : cameras) {
    if (camera.Calibrated()) continue;
    warnings.push_back("camera " + camera.name + " not calibrated (" +
                       camera.Status() + "): " + camera.Reason());
  }
  warnings.insert(warnings.end(), findings.begin(), findings.end());
  return warnings;
}

RigCalibrationRun CalibrateRig(const std::vector<NamedCamera>& cameras,
                               const Trajectory& odometry,
                               const CalibrateInputs& inputs,
                               int reference,
                               const std::string& command) {
  inputs.association.Check();
  inputs.calibration.Check();
  inputs.robot_frames.Check();
  if (reference < 0 || reference >= static_cast<int>(cameras.size())) {
    throw std::invalid_argument("reference camera index out of range");
  }
  // The odometry is every camera's: its errors stop the run.
  CheckOdometrySpeed(odometry);
  RigCalibrationRun rig;
  rig.reference = reference;
  for (const NamedCamera& camera : cameras) {
    RigCameraRun camera_run;
    camera_run.name = camera.name;
    try {
      camera_run.run =
          CalibrateTrajectories(camera.segments, odometry, inputs, command);
    } catch (const FormatError& error) {
      // This camera's poses do not fit the odometry (time stamps, rotation
      // units): the camera is named with the reason, the others go on.
      camera_run.input_error = error.what();
      camera_run.run.result.message = error.what();
      camera_run.run.context.command = command;
      for (const Trajectory& segment : camera.segments) {
        camera_run.run.context.camera_paths.push_back(segment.source);
      }
      camera_run.run.context.odometry_path = odometry.source;
    }
    camera_run.extrinsic = ExtrinsicOf(camera_run.run.result);
    rig.cameras.push_back(std::move(camera_run));
  }
  PairCalibratedCameras(&rig);
  return rig;
}

void PairCalibratedCameras(RigCalibrationRun* rig) {
  rig->pairs.clear();
  const std::vector<RigCameraRun>& cameras = rig->cameras;
  const RigJointAdjustment& joint = rig->joint;
  for (size_t a = 0; a < cameras.size(); ++a) {
    for (size_t b = a + 1; b < cameras.size(); ++b) {
      if (!cameras[a].Calibrated() || !cameras[b].Calibrated()) continue;
      RigCameraPair pair;
      pair.camera_a = static_cast<int>(a);
      pair.camera_b = static_cast<int>(b);
      const int mount_a = joint.MountOf(pair.camera_a);
      const int mount_b = joint.MountOf(pair.camera_b);
      Eigen::Matrix<double, 6, 6> cross = Eigen::Matrix<double, 6, 6>::Zero();
      if (joint.Adopted() && mount_a >= 0 && mount_b >= 0) {
        cross.topLeftCorner<5, 5>() =
            joint.result.mounts_covariance.block<5, 5>(
                Eigen::Index{5} * mount_a, Eigen::Index{5} * mount_b);
        pair.adjusted_together = true;
      }
      pair.transform =
          CameraPairOf(*cameras[a].extrinsic, *cameras[b].extrinsic, cross);
      rig->pairs.push_back(pair);
    }
  }
}

void AdoptRigJointAdjustment(const RigJointAdjustment& joint,
                             const CalibrationOptions& limits,
                             RigCalibrationRun* rig) {
  rig->joint = joint;
  const bool check = joint.use == JointAdjustmentUse::kCheck;
  if (!check && joint.ran && !joint.result.IsSuccess()) {
    rig->findings.push_back("the rig's joint adjustment failed (" +
                            std::string(ToString(joint.result.status)) +
                            "): " + joint.result.message +
                            "; each camera's own result stands");
  } else if (!check && !joint.ran && !joint.skipped.empty()) {
    rig->findings.push_back("the rig's joint adjustment not run: " +
                            joint.skipped);
  }
  if (check && joint.Succeeded() && !joint.disagreements.empty()) {
    for (const RigDisagreement& d : joint.disagreements) {
      const ExtrinsicDisagreement& q = d.quantity;
      const bool angle = q.quantity.find("translation") == std::string::npos;
      rig->findings.push_back(
          "rig joint adjustment check: camera " +
          rig->cameras.at(d.camera).name + "'s " + q.quantity +
          " differs from its own estimate by " +
          (angle ? FormatPrintf("%.3f deg", q.difference)
                 : FormatPrintf("%.1f mm", q.difference * 1e3)) +
          " (" + FormatPrintf("%.1f", q.Sigmas()) +
          " sigma of the difference)");
    }
    const std::string before =
        FormatPrintf("%.1f", joint.max_disagreement_sigmas);
    const std::string after =
        FormatPrintf("%.1f", joint.max_disagreement_sigmas_jackknifed);
    rig->findings.push_back(
        joint.adopted
            ? "rig joint adjustment check: the images of all cameras "
              "contradict the cameras' own estimates (" +
                  before + " sigma of the difference apart, more than " +
                  FormatPrintf("%.0f", kJointContradictionSigmas) + "; " +
                  after +
                  " after the adjustment's jackknife): the cameras adjusted "
                  "together are reported"
            : "rig joint adjustment check: the adjustment's own "
              "uncertainty, widened by its jackknife over stretches of the "
              "drive, covers the difference (" +
                  after + " sigma of it, " + before +
                  " before) and is wider than the cameras' own: each "
                  "camera's own estimate stands");
  }
  if (joint.Adopted()) {
    for (size_t mount = 0; mount < joint.cameras.size(); ++mount) {
      RigCameraRun& camera = rig->cameras.at(joint.cameras[mount]);
      JointAdjustmentResult one;
      one.odom_from_cam =
          joint.result.MountOdomFromCam(static_cast<int>(mount));
      one.covariance = joint.result.MountCovariance(static_cast<int>(mount));
      CalibrationResult& result = camera.run.result;
      AdoptJointExtrinsic(one, &result);
      RefuseLooseAdoptedExtrinsic(limits, &result);
      camera.extrinsic = ExtrinsicOf(result);
    }
  }
  PairCalibratedCameras(rig);
}

}  // namespace odomcal
