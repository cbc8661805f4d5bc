#include "odomcal/adapters/colmap_database_priors.h"

#include "odomcal/adapters/format_error.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// The cameras and images tables of COLMAP 3.8 (prior columns included).
constexpr const char* kImages38 =
    "CREATE TABLE cameras (camera_id INTEGER PRIMARY KEY, model INTEGER);"
    "CREATE TABLE images (image_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, "
    "name TEXT NOT NULL UNIQUE, camera_id INTEGER NOT NULL, prior_qw REAL, "
    "prior_qx REAL, prior_qy REAL, prior_qz REAL, prior_tx REAL, prior_ty "
    "REAL, prior_tz REAL);"
    "INSERT INTO images (image_id, name, camera_id) VALUES (5, 'a/1.png', 1), "
    "(2, 'a/2.png', 1);";

// One file per test: ctest runs the tests of this binary in parallel.
std::string MakeDatabase(const std::string& schema) {
  const fs::path path =
      fs::path(::testing::TempDir()) /
      (std::string("priors_") +
       ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".db");
  // TEST_TMPDIR need not exist yet (the first test to run creates it).
  fs::create_directories(path.parent_path());
  fs::remove(path);
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(db, schema.c_str(), nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  return path.string();
}

TEST(WriteColmapDatabasePositionPriors, SetsPriorsByImageName) {
  const std::string path = MakeDatabase(kImages38);
  const int updated = WriteColmapDatabasePositionPriors(
      path,
      {{"a/2.png", Eigen::Vector3d(1.5, -2.0, 0.0)},
       {"missing.png", Eigen::Vector3d(9, 9, 9)}});
  EXPECT_EQ(updated, 1);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* statement = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db,
                               "SELECT image_id, prior_tx, prior_ty, prior_tz "
                               "FROM images WHERE name = 'a/2.png'",
                               -1,
                               &statement,
                               nullptr),
            SQLITE_OK);
  ASSERT_EQ(sqlite3_step(statement), SQLITE_ROW);
  EXPECT_EQ(sqlite3_column_int(statement, 0), 2);
  EXPECT_DOUBLE_EQ(sqlite3_column_double(statement, 1), 1.5);
  EXPECT_DOUBLE_EQ(sqlite3_column_double(statement, 2), -2.0);
  EXPECT_DOUBLE_EQ(sqlite3_column_double(statement, 3), 0.0);
  sqlite3_finalize(statement);
  sqlite3_close(db);
}

TEST(WriteColmapDatabasePositionPriors, RefusesOtherSchemas) {
  const std::string path =
      MakeDatabase("CREATE TABLE images (image_id INTEGER, name TEXT);");
  EXPECT_THROW(WriteColmapDatabasePositionPriors(path, {{"x", {0, 0, 0}}}),
               FormatError);
  EXPECT_THROW(WriteColmapDatabasePositionPriors(
                   (fs::path(::testing::TempDir()) / "no" / "db").string(), {}),
               FormatError);
}

}  // namespace
}  // namespace odomcal
