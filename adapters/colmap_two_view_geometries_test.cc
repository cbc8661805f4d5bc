// The verified pairs of a COLMAP 3.8 database (colmap_two_view_geometries.h).
#include "odomcal/adapters/colmap_two_view_geometries.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <filesystem>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// E of camera 2 = R * camera 1 + t, for a unit baseline t: [t]x R.
Eigen::Matrix3d Essential(const Eigen::Vector3d& t, double yaw_rad) {
  Eigen::Matrix3d skew;
  const Eigen::Vector3d u = t.normalized();
  skew << 0, -u.z(), u.y(), u.z(), 0, -u.x(), -u.y(), u.x(), 0;
  return skew * Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitY())
                    .toRotationMatrix();
}

// A database with the two_view_geometries table of COLMAP 3.8 (database.cc
// at tag 3.8), E written row-major as COLMAP writes it.
TEST(ReadColmapVerifiedPairs, DecodesPairIdsInliersAndTheEssentialMatrix) {
  const fs::path path =
      fs::temp_directory_path() / "odomcal_two_view_geometries.db";
  fs::remove(path);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.string().c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "CREATE TABLE two_view_geometries (pair_id INTEGER "
                         "PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols "
                         "INTEGER NOT NULL, data BLOB, config INTEGER NOT "
                         "NULL, F BLOB, E BLOB, H BLOB, qvec BLOB, tvec "
                         "BLOB);",
                         nullptr,
                         nullptr,
                         nullptr),
            SQLITE_OK);
  const Eigen::Matrix3d essential = Essential({0.6, 0.0, 0.8}, 0.1);
  auto insert = [&](uint64_t pair_id, int rows, int config, bool with_e) {
    sqlite3_stmt* statement = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db,
                                 "INSERT INTO two_view_geometries VALUES(?, "
                                 "?, 2, NULL, ?, NULL, ?, NULL, NULL, NULL)",
                                 -1,
                                 &statement,
                                 nullptr),
              SQLITE_OK);
    sqlite3_bind_int64(statement, 1, static_cast<sqlite3_int64>(pair_id));
    sqlite3_bind_int(statement, 2, rows);
    sqlite3_bind_int(statement, 3, config);
    double row_major[9];
    for (int k = 0; k < 9; ++k) row_major[k] = essential(k / 3, k % 3);
    if (with_e) {
      sqlite3_bind_blob(
          statement, 4, row_major, sizeof(row_major), SQLITE_TRANSIENT);
    } else {
      sqlite3_bind_zeroblob(statement, 4, 0);
    }
    ASSERT_EQ(sqlite3_step(statement), SQLITE_DONE);
    sqlite3_finalize(statement);
  };
  insert(ColmapPairId(7, 3), 150, 2, true);
  insert(ColmapPairId(1, 2), 12, 3, false);
  insert(ColmapPairId(1, 4), 0, 1, false);
  sqlite3_close(db);

  const std::vector<ColmapVerifiedPair> pairs =
      ReadColmapVerifiedPairs(path.string());
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].image_id1, 1u);
  EXPECT_EQ(pairs[0].image_id2, 2u);
  EXPECT_FALSE(pairs[0].essential);
  EXPECT_EQ(pairs[1].image_id1, 3u);
  EXPECT_EQ(pairs[1].image_id2, 7u);
  EXPECT_EQ(pairs[1].num_inliers, 150);
  EXPECT_EQ(pairs[1].config, 2);
  ASSERT_TRUE(pairs[1].essential);
  EXPECT_TRUE(pairs[1].essential->isApprox(essential, 1e-15));
  // The left null vector of E is the baseline in the second camera: read
  // transposed, it would be another direction.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(*pairs[1].essential,
                                              Eigen::ComputeFullU);
  EXPECT_NEAR(std::abs(svd.matrixU().col(2).z()), 0.8, 1e-12);
  EXPECT_EQ(ReadColmapVerifiedPairs(path.string(), 100).size(), 1u);
  EXPECT_EQ(ColmapPairId(3, 7), uint64_t{3} * 2147483647 + 7);
  fs::remove(path);
}

}  // namespace
}  // namespace odomcal
