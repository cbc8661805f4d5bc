// Odometry-aware frame selection before SfM: keeps an image only once the
// robot has moved enough since the last kept one, so frames taken while the
// robot stands still (no baseline, wasted matching time) and near-duplicates
// are dropped before COLMAP runs. Images outside the odometry (no time, or
// outside its span, or in a gap) cannot be calibrated and are dropped too.
#pragma once

#include "odomcal/adapters/trajectory.h"

#include <cstdint>
#include <string>
#include <vector>

namespace odomcal {

struct FrameSelectionOptions {
  double min_translation_m = 0.05;  // keep once moved this far...
  double min_rotation_deg = 3.0;    // ...or turned this much
  // As AssociationOptions' (0: automatic, from the odometry's sampling).
  double max_odometry_gap_s = 0.0;
  int64_t camera_time_offset_ns = 0;  // odometry time = image time + offset
  void Check() const;  // throws std::invalid_argument naming the field
};

struct TimedImage {
  std::string name;
  int64_t stamp_ns = 0;
};

struct FrameSelection {
  std::vector<TimedImage> kept;  // in time order
  int num_images = 0;
  int num_outside_odometry = 0;
  int num_dropped_still_or_close = 0;
};

// `images` in any order; the result is sorted by time.
FrameSelection SelectFrames(std::vector<TimedImage> images,
                            const Trajectory& odometry,
                            const FrameSelectionOptions& options);

}  // namespace odomcal
