// A multi-camera rig on the rendered robot (rendered_rig.h): named cameras,
// each with its mount, its own frame rate, phase and clock, its intrinsics
// and whether a lens cap covers it. The cameras are not synchronised: each
// takes its frames at its own times
//   capture_k = lead_time_s + phase_s + k / rate_hz   (path time, s)
// while they fall inside the reference camera's frames; cameras with the
// same rate and phase share their capture times (a synchronised pair). The
// first camera is the reference: its phase is 0, its first frame starts the
// images, and its frames are the single-camera dataset's (the drive's length
// is its number of images at its rate).
//
// Built-in layouts (RigLayouts(), MakeRigLayout):
//   stereo     two forward cameras 12 cm apart (left, right), synchronised at
//              the preset's camera rate
//   surround3  front_left (yaw +30 deg, 5 Hz), rear (yaw 180 deg, 4 Hz,
//              phase 0.07 s) and right (yaw -90 deg, 5 Hz, phase 0.1 s): next
//              to no overlap between the views, and no two captures at the
//              same instant
//   surround4  front, left, rear and right (yaw 0, 90, 180, -90 deg) at the
//              preset's camera rate, phases 0, 0.07, 0.14 and 0.21 s
#pragma once

#include "odomcal/datasets/rendering/camera_model.h"
#include "odomcal/solver/rigid3.h"

#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct RigCamera {
  // The folder of its images (images/<name>/): 1-100 characters of A-Z a-z
  // 0-9 _ - ., not starting with '.'.
  std::string name;
  Rigid3d odom_from_cam;
  // The preset's camera and camera rate when not given.
  std::optional<CameraIntrinsics> intrinsics;
  std::optional<double> rate_hz;
  double phase_s = 0.0;  // its first frame after the reference camera's first
  // Its clock runs late by this on top of the preset's camera_time_offset_s:
  // recorded stamp = capture + preset offset + time_offset_s + jitter.
  double time_offset_s = 0.0;
  // A lens cap: every image uniformly dark, nothing for COLMAP to match.
  bool capped = false;
  void Check() const;  // throws std::invalid_argument naming the field
};

struct RigLayout {
  std::string name = "custom";     // echoed in ground_truth.json
  std::vector<RigCamera> cameras;  // at least one; the first is the reference
  // Each camera's Check(), distinct names, a reference phase of 0; throws
  // std::invalid_argument naming the field.
  void Check() const;
  // The camera called `name`; throws std::invalid_argument listing the
  // cameras when there is none.
  RigCamera& Camera(const std::string& name);
};

struct RigLayoutInfo {
  std::string name;
  std::string summary;  // one line
};

std::vector<RigLayoutInfo> RigLayouts();

// Throws std::invalid_argument listing the valid names for an unknown one.
RigLayout MakeRigLayout(const std::string& name);

}  // namespace odomcal
