// Read-only access to the verified image pairs of a COLMAP database: the
// `two_view_geometries` table (pair_id, rows, config, E), written by COLMAP's
// matchers after geometric verification. The columns read have the same
// names and meaning from COLMAP 3.8 to 4.1.
//
// pair_id encodes the two image ids as image_id1 * 2147483647 + image_id2
// with image_id1 < image_id2 (COLMAP's kMaxNumImages, every version). `rows`
// is the number of inlier matches. E is stored row-major (COLMAP transposes
// Eigen's column-major matrices before writing) as 9 little-endian float64,
// such that x2^T E x1 = 0 for normalized image points of image_id1 (x1) and
// image_id2 (x2); an empty or all-zero blob means COLMAP estimated none
// (e.g. an uncalibrated pair).
//
// The database is opened as colmap_database.h opens it (read-only,
// immutable): the file stays byte-identical. Errors throw FormatError naming
// the database path.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

// COLMAP's TwoViewGeometry::ConfigurationType, as stored in `config`.
enum class TwoViewConfig {
  kUndefined = 0,
  kDegenerate = 1,
  kCalibrated = 2,
  kUncalibrated = 3,
  kPlanar = 4,
  kPanoramic = 5,
  kPlanarOrPanoramic = 6,
  kWatermark = 7,
  kMultiple = 8,
};

struct ColmapVerifiedPair {
  uint32_t image_id1 = 0;  // < image_id2
  uint32_t image_id2 = 0;
  int num_inliers = 0;  // the table's `rows`
  int config = 0;       // TwoViewConfig's value; other values kept as read
  // x2^T E x1 = 0; absent when the blob is empty or all zeros.
  std::optional<Eigen::Matrix3d> essential;
};

// COLMAP's pair id of two image ids (either order).
uint64_t ColmapPairId(uint32_t image_id1, uint32_t image_id2);

// Every row of two_view_geometries with at least `min_inliers` inliers,
// sorted by (image_id1, image_id2). Throws FormatError naming the path.
std::vector<ColmapVerifiedPair> ReadColmapVerifiedPairs(
    const std::string& database_path, int min_inliers = 1);

}  // namespace odomcal
