// A folded stretch of a sub-model posed again from the odometry.
//
// COLMAP folds a drive where the robot turns close to a wall: a view of a
// single plane fits two poses almost equally well, and the incremental
// mapper's registration and bundle adjustment stay in the wrong one (on the
// rendered 1 000-image drive the motions from 256 s on point 130-177 deg
// away from the truth; docs/benchmarks.md). No random seed and no smaller
// model escapes it, because every run starts that stretch from the images
// before it. The odometry, with the extrinsic and scale calibrated on the
// rest of the drive, says where those cameras were: started there, COLMAP's
// triangulation and bundle adjustment reach the right minimum (0.01-0.04 deg
// and under 1 deg of direction per motion against the truth, where the fold
// was 1-3 deg and reversed).
//
// The poses only choose the minimum: the bundle adjustment that follows
// (colmap bundle_adjuster) knows nothing of the odometry, so the calibration
// afterwards tests the stretch against the odometry as before.
#pragma once

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/colmap_segments.h"
#include "odomcal/adapters/trajectory.h"
#include "odomcal/solver/rigid3.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct ReposedModel {
  // The sub-model with every image from the anchor on placed by the
  // odometry (cam_from_world in the sub-model's frame and units), the
  // images without an odometry pose left out, and no 3D points (every
  // points2D entry unlinked): the points of the fold are to be
  // triangulated again.
  ColmapModel model;
  std::string anchor_image;  // kept where COLMAP put it
  int num_reposed = 0;
  std::vector<uint32_t> reposed_image_ids;  // in time order
  int num_left_out = 0;  // after the anchor, without an odometry pose
};

struct FoldToRepose {
  // Odometry time (camera time + offset) of the first folded motion pair's
  // first image: the anchor, whose pose and everything before it are kept.
  // Everything after it is posed again, not only the stretch: the images
  // after a fold hang off the folded ones.
  int64_t first_stamp_ns = 0;
  int64_t camera_time_offset_ns = 0;  // odometry_time = camera_time + this
  Rigid3d odom_from_cam;
  double metres_per_unit = 1.0;  // the sub-model's metric scale
  double max_odometry_gap_s = 0.25;
};

// `segment` is `model`'s trajectory as ReadColmapSegments gives it (camera
// times, image ids of `model`); `odometry` in odometry time. Returns
// std::nullopt when no image of `segment` lies at fold.first_stamp_ns
// (within 1 ms), when the anchor has no odometry pose, or when nothing
// after it could be posed. Throws std::invalid_argument for a scale that is
// not positive and finite.
std::optional<ReposedModel> ReposeFoldFromOdometry(const ColmapModel& model,
                                                   const ColmapSegment& segment,
                                                   const Trajectory& odometry,
                                                   const FoldToRepose& fold);

}  // namespace odomcal
