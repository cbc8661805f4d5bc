// Do the camera poses drift, or does each pose carry its own error?
//
// Visual odometry composes every pose from the previous one, so its errors
// accumulate: the error of the motion from frame k to frame k + m grows with
// m (variance ~ m). A bundle-adjusted model (COLMAP) puts every pose in one
// frame with an error of its own: the motion's error is the difference of
// two pose errors, whatever the span (variance ~ constant). Which frames make
// the best motion pairs depends on it (docs/method.md, "Which frames make the
// pairs"): consecutive frames carry the information of drifting poses, while
// the short steps of globally consistent poses bias the scale.
//
// The test needs no odometry and no extrinsic. Under planar motion every
// camera rotation increment turns about one axis a (the odometry's z in the
// camera frame), and every camera translation increment, in the first
// camera's frame, is perpendicular to it. What leaves that plane is error:
// the rotation vector's components across a and the translation's component
// along a. Their mean squares over the pairs (k, k + span) are compared with
// those over (k, k + 1):
//   ratio = mean square at `span` / mean square at 1,
// about 1 for per-pose errors and about `span` for drift. With one step's
// drift variance d and a per-pose variance p (per motion: 2 p + m d) the
// ratio reaches (span + 1) / 2 exactly when d = 2 p, where one step's drift
// equals the pair's per-pose error: above that, for both the rotation and
// the translation, the poses count as drifting. Terrain that is not flat
// tilts the camera for real and reads as drift (the planarity check warns of
// it separately).
#pragma once

#include "odomcal/adapters/trajectory.h"

#include <vector>

namespace odomcal {

struct CameraPoseDriftOptions {
  int span = 8;            // frames; >= 2
  int min_num_pairs = 30;  // per span, over all segments, to decide
  void Check() const;      // throws std::invalid_argument naming the field
};

struct CameraPoseDriftTest {
  // Enough pairs, planar motion (the rotation across the plane at most 5 %
  // of the long span's mean square) and errors that leave the plane at all
  // (exact poses do not), to tell. When not decided, drifting is false.
  bool decided = false;
  bool drifting = false;
  int span = 0;
  int num_pairs = 0;  // pairs at the long span, over all segments
  // Mean squares across the plane at `span` over those at one frame.
  double rotation_ratio = 0.0;
  double translation_ratio = 0.0;
  double threshold = 0.0;  // (span + 1) / 2
};

// Camera segments as for AssociateCameraWithOdometry (each in its own world
// frame; poses in time order). Throws std::invalid_argument from
// options.Check().
CameraPoseDriftTest TestCameraPoseDrift(
    const std::vector<Trajectory>& camera_segments,
    const CameraPoseDriftOptions& options);

}  // namespace odomcal
