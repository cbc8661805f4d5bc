// Image ids renumbered by name (colmap_database_order.h) in databases of
// COLMAP 3.8's layout and of 4.0's (frames, frame_data, pose_priors by
// sensor), with the tables written as those versions create them.
#include "odomcal/adapters/colmap_database_order.h"

#include "odomcal/adapters/colmap_database.h"
#include "odomcal/adapters/format_error.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

constexpr const char* kCommon =
    "CREATE TABLE cameras (camera_id INTEGER PRIMARY KEY AUTOINCREMENT NOT "
    "NULL, model INTEGER NOT NULL, width INTEGER NOT NULL, height INTEGER NOT "
    "NULL, params BLOB, prior_focal_length INTEGER NOT NULL);"
    "CREATE TABLE images (image_id INTEGER PRIMARY KEY AUTOINCREMENT NOT "
    "NULL, name TEXT NOT NULL UNIQUE, camera_id INTEGER NOT NULL, CONSTRAINT "
    "image_id_check CHECK(image_id >= 0 and image_id < 2147483647));"
    "CREATE TABLE keypoints (image_id INTEGER PRIMARY KEY NOT NULL, rows "
    "INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB);"
    "CREATE TABLE descriptors (image_id INTEGER PRIMARY KEY NOT NULL, rows "
    "INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB);"
    "CREATE TABLE matches (pair_id INTEGER PRIMARY KEY NOT NULL, rows "
    "INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB);"
    "CREATE TABLE two_view_geometries (pair_id INTEGER PRIMARY KEY NOT NULL, "
    "rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, config INTEGER "
    "NOT NULL, F BLOB, E BLOB, H BLOB, qvec BLOB, tvec BLOB);"
    "INSERT INTO cameras VALUES (1, 1, 320, 240, NULL, 1);";
// COLMAP 4.0's tables beyond those (database_sqlite.cc at 4.0.0).
constexpr const char* kFrames4 =
    "CREATE TABLE rigs (rig_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, "
    "ref_sensor_id INTEGER NOT NULL, ref_sensor_type INTEGER NOT NULL);"
    "CREATE TABLE rig_sensors (rig_id INTEGER NOT NULL, sensor_id INTEGER "
    "NOT NULL, sensor_type INTEGER NOT NULL, sensor_from_rig BLOB);"
    "CREATE TABLE frames (frame_id INTEGER PRIMARY KEY AUTOINCREMENT NOT "
    "NULL, rig_id INTEGER NOT NULL);"
    "CREATE TABLE frame_data (frame_id INTEGER NOT NULL, data_id INTEGER NOT "
    "NULL, sensor_id INTEGER NOT NULL, sensor_type INTEGER NOT NULL);"
    "CREATE UNIQUE INDEX frame_sensor_assignment ON frame_data(data_id, "
    "sensor_type);"
    "CREATE TABLE pose_priors (pose_prior_id INTEGER PRIMARY KEY NOT NULL, "
    "corr_data_id INTEGER NOT NULL, corr_sensor_id INTEGER NOT NULL, "
    "corr_sensor_type INTEGER NOT NULL, position BLOB, position_covariance "
    "BLOB, gravity BLOB, coordinate_system INTEGER NOT NULL);"
    "INSERT INTO rigs VALUES (1, 1, 0);"
    "PRAGMA user_version = 4000000;";

class RenumberTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ =
        fs::temp_directory_path() /
        ("odomcal_order_" +
         std::string(
             ::testing::UnitTest::GetInstance()->current_test_info()->name()) +
         ".db");
    fs::remove(path_);
  }
  void TearDown() override { fs::remove(path_); }

  void Exec(const std::string& sql) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path_.string().c_str(), &db), SQLITE_OK);
    char* error = nullptr;
    EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error),
              SQLITE_OK)
        << (error ? error : "");
    sqlite3_free(error);
    sqlite3_close(db);
  }

  // "value" of column `sql` selects, keyed by its first column.
  std::map<std::string, std::string> Rows(const std::string& sql) {
    std::map<std::string, std::string> rows;
    sqlite3* db = nullptr;
    sqlite3_open(path_.string().c_str(), &db);
    sqlite3_stmt* statement = nullptr;
    sqlite3_prepare_v2(db, sql.c_str(), -1, &statement, nullptr);
    while (sqlite3_step(statement) == SQLITE_ROW) {
      rows[reinterpret_cast<const char*>(sqlite3_column_text(statement, 0))] =
          reinterpret_cast<const char*>(sqlite3_column_text(statement, 1));
    }
    sqlite3_finalize(statement);
    sqlite3_close(db);
    return rows;
  }

  // Images c.png, a.png, b.png got ids 1, 2, 3 (extraction order), each
  // with keypoints and descriptors holding its name.
  void AddImagesOutOfOrder() {
    Exec(
        "INSERT INTO images (image_id, name, camera_id) VALUES (1, 'c.png', "
        "1), (2, 'a.png', 1), (3, 'b.png', 1);"
        "INSERT INTO keypoints VALUES (1, 0, 6, 'c'), (2, 0, 6, 'a'), (3, 0, "
        "6, 'b');"
        "INSERT INTO descriptors VALUES (1, 0, 128, 'c'), (2, 0, 128, 'a'), "
        "(3, 0, 128, 'b');");
  }

  fs::path path_;
};

TEST_F(RenumberTest, GivesImagesIdsInNameOrderWithTheirFeatures) {
  Exec(kCommon);
  AddImagesOutOfOrder();
  EXPECT_TRUE(RenumberColmapImagesByName(path_.string()));
  const std::vector<ColmapDatabaseImage> images =
      ReadColmapDatabaseImages(path_.string());
  ASSERT_EQ(images.size(), 3u);
  EXPECT_EQ(images[0].name, "a.png");
  EXPECT_EQ(images[0].image_id, 1u);
  EXPECT_EQ(images[2].name, "c.png");
  EXPECT_EQ(images[2].image_id, 3u);
  const std::map<std::string, std::string> expected = {
      {"1", "a"}, {"2", "b"}, {"3", "c"}};
  EXPECT_EQ(Rows("SELECT image_id, data FROM keypoints"), expected);
  EXPECT_EQ(Rows("SELECT image_id, data FROM descriptors"), expected);
  // Renumbered already: nothing more to do.
  EXPECT_FALSE(RenumberColmapImagesByName(path_.string()));
}

TEST_F(RenumberTest, RenumbersFramesAndPosePriorsOfCOLMAP4) {
  Exec(std::string(kCommon) + kFrames4);
  AddImagesOutOfOrder();
  // Frames 1, 2, 3 hold images 2 (a), 3 (b), 1 (c); a prior on image 1 (c)
  // and one on another sensor type that must stay.
  Exec(
      "INSERT INTO frames VALUES (1, 1), (2, 1), (3, 1);"
      "INSERT INTO frame_data VALUES (1, 2, 1, 0), (2, 3, 1, 0), (3, 1, 1, "
      "0), (3, 1, 7, 1);"
      "INSERT INTO pose_priors VALUES (1, 1, 1, 0, 'c', NULL, NULL, 1), (2, "
      "1, 7, 1, 'imu', NULL, NULL, 1);");
  EXPECT_TRUE(RenumberColmapImagesByName(path_.string()));
  // a = 1, b = 2, c = 3; frames follow their images: a's frame is 1.
  EXPECT_EQ(
      Rows("SELECT data_id, frame_id FROM frame_data WHERE "
           "sensor_type = 0"),
      (std::map<std::string, std::string>{{"1", "1"}, {"2", "2"}, {"3", "3"}}));
  EXPECT_EQ(Rows("SELECT data_id, frame_id FROM frame_data WHERE "
                 "sensor_type = 1"),
            (std::map<std::string, std::string>{{"1", "3"}}));
  EXPECT_EQ(Rows("SELECT position, corr_data_id FROM pose_priors"),
            (std::map<std::string, std::string>{{"c", "3"}, {"imu", "1"}}));
  EXPECT_EQ(Rows("SELECT frame_id, rig_id FROM frames").size(), 3u);
}

TEST_F(RenumberTest, RefusesADatabaseWithMatches) {
  Exec(kCommon);
  AddImagesOutOfOrder();
  Exec("INSERT INTO matches VALUES (2147483649, 0, 2, NULL);");
  try {
    RenumberColmapImagesByName(path_.string());
    FAIL() << "no error";
  } catch (const FormatError& error) {
    EXPECT_EQ(std::string(error.what()),
              path_.string() +
                  ": cannot renumber its images: its matches table is not "
                  "empty");
  }
  EXPECT_EQ(ReadColmapDatabaseImages(path_.string())[0].name, "c.png");
}

}  // namespace
}  // namespace odomcal
