// Noise of a drive as the calibration's noise model (NoiseModel) describes
// it, for tests and studies that compare a verdict made under that model
// (adapters/excitation_precheck.h) with the calibration's on noisy data.
#pragma once

#include "odomcal/adapters/trajectory.h"
#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/rigid3.h"

#include <cstdint>
#include <vector>

namespace odomcal {

// A planar odometry log with, over each interval between consecutive image
// times, the noise `noise` gives a pair of that motion, times `factor`: yaw
// odom_yaw_sigma_deg + odom_yaw_sigma_rel |yaw|, x and y each
// odom_translation_sigma_m + odom_translation_sigma_rel |t| (in the frame
// at the interval's start). Spread linearly over the interval, so the log
// stays continuous; samples before the first image time keep their pose.
// `image_stamps_ns` on the odometry clock, ascending. Deterministic for a
// seed.
Trajectory WithModelOdometryNoise(const Trajectory& odometry,
                                  const std::vector<int64_t>& image_stamps_ns,
                                  const NoiseModel& noise,
                                  double factor,
                                  uint64_t seed);

// A reconstruction's world_from_cam at the images: the true odometry at
// each capture time (odometry clock) times odom_from_cam, in units of
// metres_per_unit, stamped with the recorded times, with independent noise
// per pose such that two consecutive poses differ by `noise`'s camera noise
// times `factor`: cam_rotation_sigma_deg / sqrt(2) per axis, and
// cam_translation_sigma_rel / sqrt(2) of the median distance between
// consecutive images per axis. Throws std::invalid_argument when a capture
// time is outside the odometry or the two lists differ in length.
Trajectory ModelNoisyReconstruction(const Trajectory& true_odometry,
                                    const std::vector<int64_t>& capture_ns,
                                    const std::vector<int64_t>& stamps_ns,
                                    const Rigid3d& odom_from_cam,
                                    double metres_per_unit,
                                    const NoiseModel& noise,
                                    double factor,
                                    uint64_t seed);

}  // namespace odomcal
