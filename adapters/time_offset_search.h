// Coarse search for the clock offset between a camera and the wheel odometry
// (odometry_time = camera_time + offset, as in association.h).
//
// Both sensors see the same rotation: the rotation angle of a camera motion
// equals that of the odometry motion over the same interval, whatever the
// extrinsic. For every interval between consecutive camera poses the camera's
// rotation angle is compared with the odometry's over the interval shifted by
// a candidate offset (odometry interpolated, so the resolution is finer than
// its sample period); the offset maximising their correlation is the peak.
// The joint refinement (solver/systematics_refine.h) then finds the offset
// precisely; this search only has to land in its basin.
#pragma once

#include "odomcal/adapters/trajectory.h"

#include <cstdint>
#include <string>
#include <vector>

namespace odomcal {

struct TimeOffsetSearchOptions {
  int64_t center_ns = 0;  // the given offset
  double range_s = 1.0;   // search center +- range_s
  double max_odometry_gap_s = 0.25;
  // Not resolved when the correlation at the peak is below this, or when
  // the correlation stays within peak_drop of the peak further than
  // max_peak_half_width_s from it (a flat peak: smooth motion).
  double min_peak_correlation = 0.5;
  double peak_drop = 0.1;
  double max_peak_half_width_s = 0.3;
};

struct TimeOffsetSearch {
  bool resolved = false;
  std::string reason;   // why not resolved (empty when resolved)
  int64_t peak_ns = 0;  // offset at the correlation peak
  double peak_correlation = 0.0;
  double peak_half_width_s = 0.0;  // where the correlation drops by peak_drop
  int num_intervals = 0;           // camera intervals compared at the peak
  double step_s = 0.0;             // grid step of the search
};

// Throws std::invalid_argument for a non-positive range or gap.
TimeOffsetSearch SearchTimeOffset(const std::vector<Trajectory>& cameras,
                                  const Trajectory& odometry,
                                  const TimeOffsetSearchOptions& options);

}  // namespace odomcal
