// Writes position priors into a COLMAP database that odomcal itself created
// (the workspace of `odomcal run`; never a user's project), so that COLMAP's
// spatial_matcher pairs images that are near each other along the odometry.
//
// The priors go where the database's COLMAP reads them
// (colmap_database_version.h):
//   3.8, 3.9     UPDATE images SET prior_tx, prior_ty, prior_tz
//   3.10         pose_priors(image_id, position, coordinate_system)
//   3.11 - 3.13  ... and position_covariance (unknown: 9 NaN)
//   4.x          pose_priors(pose_prior_id (new), corr_data_id = image_id,
//                corr_sensor_id = camera_id, corr_sensor_type = 0 (camera),
//                position, position_covariance (9 NaN), coordinate_system,
//                gravity (3 NaN: unknown))
// position is 3 little-endian float64 (x, y, z), the covariance 9 (column
// major), coordinate_system 1 (CARTESIAN). An image's earlier prior is
// replaced.
#pragma once

#include <Eigen/Core>

#include <map>
#include <string>

namespace odomcal {

// Sets the prior position of every image named in `positions` (metres);
// returns how many images got one (names the database lacks are skipped).
// Throws FormatError naming the database when it cannot be opened or
// written, and, in one line naming the database and its version, when its
// layout has no place for priors.
int WriteColmapDatabasePositionPriors(
    const std::string& database_path,
    const std::map<std::string, Eigen::Vector3d>& positions);

}  // namespace odomcal
