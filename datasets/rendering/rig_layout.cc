// Rig layouts: the checks of a layout and the built-in rigs. The built-in
// mounts keep every camera within 0.26 m of the robot's centre, so that the
// path planner's robot clearance (0.5-0.6 m in the room presets) keeps each
// one at least 0.24 m from the walls and boxes, as it does the reference
// camera.

#include "odomcal/datasets/rendering/rig_layout.h"

#include "odomcal/datasets/simulation/camera_mount.h"

#include <cmath>
#include <set>
#include <stdexcept>

namespace odomcal {
namespace {

bool IsRigCameraName(const std::string& name) {
  if (name.empty() || name.size() > 100 || name[0] == '.') return false;
  for (const char c : name) {
    const bool allowed = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') ||
                         (c >= '0' && c <= '9') || c == '_' || c == '-' ||
                         c == '.';
    if (!allowed) return false;
  }
  return true;
}

RigCamera MountedCamera(const std::string& name,
                        double yaw_deg,
                        double pitch_down_deg,
                        const Eigen::Vector3d& translation_m) {
  RigCamera camera;
  camera.name = name;
  camera.odom_from_cam =
      MakeCameraMount(yaw_deg, pitch_down_deg, 0.0, translation_m);
  return camera;
}

}  // namespace

void RigCamera::Check() const {
  if (!IsRigCameraName(name)) {
    throw std::invalid_argument(
        "RigCamera.name '" + name +
        "': 1-100 characters of A-Z a-z 0-9 _ - ., not starting with '.'");
  }
  const std::string where = "RigCamera '" + name + "'.";
  if (!odom_from_cam.translation.allFinite() ||
      !odom_from_cam.rotation.coeffs().allFinite() ||
      std::abs(odom_from_cam.rotation.norm() - 1.0) > 1e-9) {
    throw std::invalid_argument(
        where + "odom_from_cam: finite, with a unit quaternion");
  }
  if (intrinsics) intrinsics->Check();
  if (rate_hz && !(std::isfinite(*rate_hz) && *rate_hz > 0.0)) {
    throw std::invalid_argument(where + "rate_hz must be > 0");
  }
  if (!(std::isfinite(phase_s) && phase_s >= 0.0)) {
    throw std::invalid_argument(where + "phase_s must be >= 0");
  }
  if (!std::isfinite(time_offset_s)) {
    throw std::invalid_argument(where + "time_offset_s must be finite");
  }
}

void RigLayout::Check() const {
  if (cameras.empty()) {
    throw std::invalid_argument("RigLayout.cameras: at least one camera");
  }
  std::set<std::string> names;
  for (const RigCamera& camera : cameras) {
    camera.Check();
    if (!names.insert(camera.name).second) {
      throw std::invalid_argument("RigLayout.cameras: '" + camera.name +
                                  "' named twice");
    }
  }
  if (cameras.front().phase_s != 0.0) {
    throw std::invalid_argument("RigLayout.cameras: the reference camera '" +
                                cameras.front().name +
                                "' starts the images: its phase_s must be 0");
  }
}

RigCamera& RigLayout::Camera(const std::string& name) {
  std::string names;
  for (RigCamera& camera : cameras) {
    if (camera.name == name) return camera;
    names += (names.empty() ? "" : ", ") + camera.name;
  }
  throw std::invalid_argument("rig '" + this->name + "' has no camera '" +
                              name + "' (its cameras: " + names + ")");
}

std::vector<RigLayoutInfo> RigLayouts() {
  return {
      {"stereo",
       "two forward cameras 12 cm apart (left, right), synchronised at the "
       "preset's camera rate"},
      {"surround3",
       "front_left (yaw +30 deg, 5 Hz), rear (180 deg, 4 Hz) and right (-90 "
       "deg, 5 Hz), unsynchronised: other phases, next to no overlap"},
      {"surround4",
       "front, left, rear and right (yaw 0, 90, 180, -90 deg) at the "
       "preset's camera rate, unsynchronised: phases 0, 0.07, 0.14, 0.21 s"},
  };
}

RigLayout MakeRigLayout(const std::string& name) {
  RigLayout rig;
  rig.name = name;
  if (name == "stereo") {
    // The single camera's forward mount (dataset_presets.cc), split into a
    // pair 12 cm apart about the robot's centre line.
    rig.cameras = {
        MountedCamera("left", 0.0, 0.0, Eigen::Vector3d(0.25, 0.06, 0.40)),
        MountedCamera("right", 0.0, 0.0, Eigen::Vector3d(0.25, -0.06, 0.40))};
  } else if (name == "surround3") {
    // 63 deg wide views (the presets' lenses) centred at +30, 180 and -90
    // deg. Phases off the 0.05 s grid on which 4 Hz and 5 Hz frames could
    // meet: no two cameras capture at the same instant, so their image names
    // (the stamps) differ and COLMAP groups no two into one frame.
    rig.cameras = {
        MountedCamera(
            "front_left", 30.0, 0.0, Eigen::Vector3d(0.22, 0.10, 0.40)),
        MountedCamera("rear", 180.0, 5.0, Eigen::Vector3d(-0.25, 0.0, 0.45)),
        MountedCamera("right", -90.0, 0.0, Eigen::Vector3d(0.0, -0.20, 0.40))};
    rig.cameras[0].rate_hz = 5.0;
    rig.cameras[1].rate_hz = 4.0;
    rig.cameras[1].phase_s = 0.07;
    rig.cameras[2].rate_hz = 5.0;
    rig.cameras[2].phase_s = 0.1;
  } else if (name == "surround4") {
    // The four sides of the robot (CamOdoCal's surround set), each at the
    // preset's rate with a phase of its own: four views that hardly overlap.
    rig.cameras = {
        MountedCamera("front", 0.0, 0.0, Eigen::Vector3d(0.25, 0.0, 0.40)),
        MountedCamera("left", 90.0, 0.0, Eigen::Vector3d(0.0, 0.20, 0.40)),
        MountedCamera("rear", 180.0, 5.0, Eigen::Vector3d(-0.25, 0.0, 0.45)),
        MountedCamera("right", -90.0, 0.0, Eigen::Vector3d(0.0, -0.20, 0.40))};
    rig.cameras[1].phase_s = 0.07;
    rig.cameras[2].phase_s = 0.14;
    rig.cameras[3].phase_s = 0.21;
  } else {
    std::string names;
    for (const RigLayoutInfo& info : RigLayouts()) {
      names += (names.empty() ? "" : ", ") + info.name;
    }
    throw std::invalid_argument("unknown rig '" + name + "' (valid: " + names +
                                ")");
  }
  return rig;
}

}  // namespace odomcal
