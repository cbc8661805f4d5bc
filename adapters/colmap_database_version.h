// Which COLMAP wrote a project database (database.db), told from its schema.
//
// COLMAP creates its tables with CREATE TABLE IF NOT EXISTS and never drops a
// column, so a database shows the layout of the newest COLMAP that opened it:
//   3.8, 3.9   images has prior_qw..prior_tz (the position priors)
//   3.10       images loses them; pose_priors(image_id, position,
//              coordinate_system)
//   3.11       pose_priors gains position_covariance
//   3.12, 3.13 rigs, rig_sensors, frames, frame_data
//   4.x        pose_priors(pose_prior_id, corr_data_id, corr_sensor_id,
//              corr_sensor_type, position, position_covariance, gravity,
//              coordinate_system)
// and PRAGMA user_version holds 3800 (3.8), 3900 (3.9 to 3.13) or
// major * 10^6 + minor * 10^4 + patch * 100 (4.x; 4.1.1 is 4010100).
// (COLMAP's database.cc / database_sqlite.cc at each release tag.) The
// cameras and images columns odomcal reads (colmap_database.h) are the same
// in all of them.
#pragma once

#include <cstdint>
#include <string>

namespace odomcal {

// Where a database keeps position priors.
enum class ColmapPriorLayout {
  kNone,                      // nowhere odomcal knows
  kImagesPriorColumns,        // images.prior_tx/ty/tz (3.8, 3.9)
  kPosePriorsByImage,         // pose_priors(image_id, position, ...) (3.10)
  kPosePriorsWithCovariance,  // ... and position_covariance (3.11 - 3.13)
  kPosePriorsBySensor,        // pose_priors(pose_prior_id, corr_data_id, ...)
                              // (4.x)
};

struct ColmapDatabaseVersion {
  int64_t user_version = 0;  // PRAGMA user_version
  // "3.8", "3.9", "3.8 or 3.9", "3.10", "3.11", "3.12 or 3.13", "4.1.1", or
  // "unknown" when the schema matches none of them.
  std::string label;
  bool has_cameras_and_images = false;  // the tables odomcal reads
  bool has_rigs_and_frames = false;     // 3.12+
  ColmapPriorLayout prior_layout = ColmapPriorLayout::kNone;
};

// Opens the database read-only (as colmap_database.h does) and reads its
// schema. Throws FormatError naming the path when it is missing or not an
// SQLite database.
ColmapDatabaseVersion ReadColmapDatabaseVersion(
    const std::string& database_path);

// "COLMAP 3.10, user_version 3900" or "an unknown COLMAP layout,
// user_version 0", for messages.
std::string DescribeColmapDatabaseVersion(const ColmapDatabaseVersion& version);

}  // namespace odomcal
