// Writes position priors into a COLMAP database that odomcal itself created
// (the workspace of `odomcal run`; never a user's project), so that COLMAP's
// spatial_matcher pairs images that are near each other along the odometry.
//
// COLMAP 3.8's schema keeps priors in images.prior_tx/prior_ty/prior_tz
// (COLMAP 3.10 moved them to a pose_priors table; that schema is refused
// with a clear error).
#pragma once

#include <Eigen/Core>

#include <map>
#include <string>

namespace odomcal {

// Sets the prior position of every image named in `positions` (metres);
// returns how many rows were updated. Throws FormatError naming the database
// when it cannot be opened or lacks the 3.8 prior columns.
int WriteColmapDatabasePositionPriors(
    const std::string& database_path,
    const std::map<std::string, Eigen::Vector3d>& positions);

}  // namespace odomcal
