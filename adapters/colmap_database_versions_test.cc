// Databases of every COLMAP layout from 3.8 to 4.0, created with the CREATE
// TABLE statements and PRAGMA user_version of each release (database.cc at
// tags 3.8, 3.9.1, 3.10, 3.11.1, 3.12.0; database_sqlite.cc at 4.0.0): the
// version told from the schema, images and cameras read, and position
// priors written where that version reads them.
#include "odomcal/adapters/colmap_database.h"
#include "odomcal/adapters/colmap_database_priors.h"
#include "odomcal/adapters/colmap_database_version.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

constexpr const char* kCameras =
    "CREATE TABLE IF NOT EXISTS cameras (camera_id INTEGER PRIMARY KEY "
    "AUTOINCREMENT NOT NULL, model INTEGER NOT NULL, width INTEGER NOT NULL, "
    "height INTEGER NOT NULL, params BLOB, prior_focal_length INTEGER NOT "
    "NULL);";
constexpr const char* kImagesWithPriors =
    "CREATE TABLE IF NOT EXISTS images (image_id INTEGER PRIMARY KEY "
    "AUTOINCREMENT NOT NULL, name TEXT NOT NULL UNIQUE, camera_id INTEGER NOT "
    "NULL, prior_qw REAL, prior_qx REAL, prior_qy REAL, prior_qz REAL, "
    "prior_tx REAL, prior_ty REAL, prior_tz REAL, CONSTRAINT image_id_check "
    "CHECK(image_id >= 0 and image_id < 2147483647), FOREIGN KEY(camera_id) "
    "REFERENCES cameras(camera_id));"
    "CREATE UNIQUE INDEX IF NOT EXISTS index_name ON images(name);";
constexpr const char* kImages =
    "CREATE TABLE IF NOT EXISTS images (image_id INTEGER PRIMARY KEY "
    "AUTOINCREMENT NOT NULL, name TEXT NOT NULL UNIQUE, camera_id INTEGER NOT "
    "NULL, CONSTRAINT image_id_check CHECK(image_id >= 0 and image_id < "
    "2147483647), FOREIGN KEY(camera_id) REFERENCES cameras(camera_id));"
    "CREATE UNIQUE INDEX IF NOT EXISTS index_name ON images(name);";
constexpr const char* kFeatures =
    "CREATE TABLE IF NOT EXISTS keypoints (image_id INTEGER PRIMARY KEY NOT "
    "NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, FOREIGN "
    "KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);"
    "CREATE TABLE IF NOT EXISTS matches (pair_id INTEGER PRIMARY KEY NOT "
    "NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB);"
    "CREATE TABLE IF NOT EXISTS two_view_geometries (pair_id INTEGER PRIMARY "
    "KEY NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, "
    "config INTEGER NOT NULL, F BLOB, E BLOB, H BLOB, qvec BLOB, tvec BLOB);";
constexpr const char* kDescriptors3 =
    "CREATE TABLE IF NOT EXISTS descriptors (image_id INTEGER PRIMARY KEY NOT "
    "NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, FOREIGN "
    "KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);";
constexpr const char* kDescriptors4 =
    "CREATE TABLE IF NOT EXISTS descriptors (image_id INTEGER PRIMARY KEY NOT "
    "NULL, type INTEGER NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT "
    "NULL, data BLOB, FOREIGN KEY(image_id) REFERENCES images(image_id) ON "
    "DELETE CASCADE);";
constexpr const char* kPosePriors310 =
    "CREATE TABLE IF NOT EXISTS pose_priors (image_id INTEGER PRIMARY KEY NOT "
    "NULL, position BLOB, coordinate_system INTEGER NOT NULL, FOREIGN "
    "KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);";
constexpr const char* kPosePriors311 =
    "CREATE TABLE IF NOT EXISTS pose_priors (image_id INTEGER PRIMARY KEY NOT "
    "NULL, position BLOB, coordinate_system INTEGER NOT NULL, "
    "position_covariance BLOB, FOREIGN KEY(image_id) REFERENCES "
    "images(image_id) ON DELETE CASCADE);";
constexpr const char* kPosePriors4 =
    "CREATE TABLE IF NOT EXISTS pose_priors (pose_prior_id INTEGER PRIMARY "
    "KEY NOT NULL, corr_data_id INTEGER NOT NULL, corr_sensor_id INTEGER NOT "
    "NULL, corr_sensor_type INTEGER NOT NULL, position BLOB, "
    "position_covariance BLOB, gravity BLOB, coordinate_system INTEGER NOT "
    "NULL);"
    "CREATE UNIQUE INDEX IF NOT EXISTS pose_prior_data_assignment ON "
    "pose_priors(corr_data_id, corr_sensor_id, corr_sensor_type);";
constexpr const char* kRigsAndFrames =
    "CREATE TABLE IF NOT EXISTS rigs (rig_id INTEGER PRIMARY KEY "
    "AUTOINCREMENT NOT NULL, ref_sensor_id INTEGER NOT NULL, ref_sensor_type "
    "INTEGER NOT NULL);"
    "CREATE UNIQUE INDEX IF NOT EXISTS rig_ref_sensor_assignment ON "
    "rigs(ref_sensor_id, ref_sensor_type);"
    "CREATE TABLE IF NOT EXISTS rig_sensors (rig_id INTEGER NOT NULL, "
    "sensor_id INTEGER NOT NULL, sensor_type INTEGER NOT NULL, "
    "sensor_from_rig BLOB, FOREIGN KEY(rig_id) REFERENCES rigs(rig_id) ON "
    "DELETE CASCADE);"
    "CREATE UNIQUE INDEX IF NOT EXISTS rig_sensor_assignment ON "
    "rig_sensors(sensor_id, sensor_type);"
    "CREATE TABLE IF NOT EXISTS frames (frame_id INTEGER PRIMARY KEY "
    "AUTOINCREMENT NOT NULL, rig_id INTEGER NOT NULL, FOREIGN KEY(rig_id) "
    "REFERENCES rigs(rig_id) ON DELETE CASCADE);"
    "CREATE TABLE IF NOT EXISTS frame_data (frame_id INTEGER NOT NULL, "
    "data_id INTEGER NOT NULL, sensor_id INTEGER NOT NULL, sensor_type "
    "INTEGER NOT NULL, FOREIGN KEY(frame_id) REFERENCES frames(frame_id) ON "
    "DELETE CASCADE);"
    "CREATE UNIQUE INDEX IF NOT EXISTS frame_sensor_assignment ON "
    "frame_data(data_id, sensor_type);";

struct Layout {
  const char* version;  // the label expected
  std::string schema;   // CREATE statements and PRAGMA user_version
  int max_model_id;     // the highest camera model id of that version
  ColmapPriorLayout priors;
  bool rigs;
};

std::vector<Layout> Layouts() {
  const std::string s = kCameras;
  return {
      {"3.8",
       s + kImagesWithPriors + kFeatures + kDescriptors3 +
           "PRAGMA user_version = 3800;",
       10,
       ColmapPriorLayout::kImagesPriorColumns,
       false},
      {"3.9",
       s + kImagesWithPriors + kFeatures + kDescriptors3 +
           "PRAGMA user_version = 3900;",
       10,
       ColmapPriorLayout::kImagesPriorColumns,
       false},
      {"3.10",
       s + kImages + kPosePriors310 + kFeatures + kDescriptors3 +
           "PRAGMA user_version = 3900;",
       10,
       ColmapPriorLayout::kPosePriorsByImage,
       false},
      {"3.11",
       s + kImages + kPosePriors311 + kFeatures + kDescriptors3 +
           "PRAGMA user_version = 3900;",
       11,
       ColmapPriorLayout::kPosePriorsWithCovariance,
       false},
      {"3.12 or 3.13",
       std::string(kRigsAndFrames) + s + kImages + kPosePriors311 + kFeatures +
           kDescriptors3 + "PRAGMA user_version = 3900;",
       11,
       ColmapPriorLayout::kPosePriorsWithCovariance,
       true},
      {"4.0.0",
       std::string(kRigsAndFrames) + s + kImages + kPosePriors4 + kFeatures +
           kDescriptors4 + "PRAGMA user_version = 4000000;",
       15,
       ColmapPriorLayout::kPosePriorsBySensor,
       true},
  };
}

std::string ParamsBlob(const std::vector<double>& params) {
  std::string blob;
  for (const double value : params) {
    uint64_t bits = 0;
    std::memcpy(&bits, &value, 8);
    for (int i = 0; i < 8; ++i) {
      blob.push_back(static_cast<char>(bits >> (8 * i)));
    }
  }
  return blob;
}

void Exec(sqlite3* db, const std::string& sql) {
  char* message = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message),
            SQLITE_OK)
      << (message != nullptr ? message : "") << "\n"
      << sql;
  sqlite3_free(message);
}

// A database of `layout` with a PINHOLE camera 1, a camera 2 of the
// version's highest model id, and images 1-3 (image 3 on camera 2).
std::string MakeDatabase(const Layout& layout) {
  const fs::path dir = fs::path(::testing::TempDir()) / "odomcal_db_versions";
  fs::create_directories(dir);
  std::string file = std::string("v") + layout.version + ".db";
  for (char& c : file) c = c == ' ' ? '_' : c;
  const std::string path = (dir / file).string();
  fs::remove(path);
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  Exec(db, layout.schema);
  const int model = layout.max_model_id;
  const int num_params =
      ColmapCameraModelNumParams(*ColmapCameraModelFromId(model));
  sqlite3_stmt* insert = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db,
                               "INSERT INTO cameras VALUES (?1, ?2, 640, 480, "
                               "?3, 1)",
                               -1,
                               &insert,
                               nullptr),
            SQLITE_OK);
  for (const auto& [id, model_id, params] :
       std::vector<std::tuple<int, int, std::vector<double>>>{
           {1, 1, {500, 500, 320, 240}},
           {2, model, std::vector<double>(num_params, 0.25)}}) {
    const std::string blob = ParamsBlob(params);
    sqlite3_reset(insert);
    sqlite3_bind_int(insert, 1, id);
    sqlite3_bind_int(insert, 2, model_id);
    sqlite3_bind_blob(insert, 3, blob.data(), blob.size(), SQLITE_TRANSIENT);
    EXPECT_EQ(sqlite3_step(insert), SQLITE_DONE);
  }
  sqlite3_finalize(insert);
  Exec(db,
       "INSERT INTO images (image_id, name, camera_id) VALUES "
       "(1, 'b.png', 1), (2, 'a.png', 1), (3, 'c/d.png', 2);");
  sqlite3_close(db);
  return path;
}

// The position stored for image `image_id`, wherever the layout keeps it.
std::vector<double> StoredPosition(const std::string& path,
                                   ColmapPriorLayout layout,
                                   int image_id,
                                   int camera_id) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  const std::string id = std::to_string(image_id);
  const std::string sql =
      layout == ColmapPriorLayout::kImagesPriorColumns
          ? "SELECT prior_tx, prior_ty, prior_tz FROM images WHERE image_id "
            "= " +
                id
      : layout == ColmapPriorLayout::kPosePriorsBySensor
          ? "SELECT position, corr_sensor_id, corr_sensor_type, "
            "coordinate_system, length(gravity), length(position_covariance) "
            "FROM pose_priors WHERE corr_data_id = " +
                id
          : "SELECT position, coordinate_system FROM pose_priors WHERE "
            "image_id = " +
                id;
  sqlite3_stmt* statement = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &statement, nullptr),
            SQLITE_OK);
  std::vector<double> values;
  if (sqlite3_step(statement) == SQLITE_ROW) {
    if (layout == ColmapPriorLayout::kImagesPriorColumns) {
      for (int k = 0; k < 3; ++k) {
        values.push_back(sqlite3_column_double(statement, k));
      }
    } else {
      EXPECT_EQ(sqlite3_column_bytes(statement, 0), 24);
      values.resize(3);
      std::memcpy(values.data(), sqlite3_column_blob(statement, 0), 24);
      // corr_sensor_id (4.x) or coordinate_system (CARTESIAN).
      EXPECT_EQ(
          sqlite3_column_int(statement, 1),
          layout == ColmapPriorLayout::kPosePriorsBySensor ? camera_id : 1);
      if (layout == ColmapPriorLayout::kPosePriorsBySensor) {
        EXPECT_EQ(sqlite3_column_int(statement, 2), 0);  // CAMERA
        EXPECT_EQ(sqlite3_column_int(statement, 3), 1);  // CARTESIAN
        EXPECT_EQ(sqlite3_column_int(statement, 4), 24);
        EXPECT_EQ(sqlite3_column_int(statement, 5), 72);
      }
    }
    EXPECT_EQ(sqlite3_step(statement), SQLITE_DONE);  // one prior per image
  }
  sqlite3_finalize(statement);
  sqlite3_close(db);
  return values;
}

TEST(ColmapDatabaseVersions, EveryLayoutIsReadAndTakesPriors) {
  for (const Layout& layout : Layouts()) {
    SCOPED_TRACE(layout.version);
    const std::string path = MakeDatabase(layout);

    const ColmapDatabaseVersion version = ReadColmapDatabaseVersion(path);
    EXPECT_EQ(version.label, layout.version);
    EXPECT_EQ(version.prior_layout, layout.priors);
    EXPECT_EQ(version.has_rigs_and_frames, layout.rigs);
    EXPECT_TRUE(version.has_cameras_and_images);

    const std::vector<ColmapDatabaseImage> images =
        ReadColmapDatabaseImages(path);
    ASSERT_EQ(images.size(), 3u);
    EXPECT_EQ(images[1].name, "a.png");
    EXPECT_EQ(images[2].camera_id, 2u);
    const std::vector<ColmapDatabaseCamera> cameras =
        ReadColmapDatabaseCameras(path);
    ASSERT_EQ(cameras.size(), 2u);
    EXPECT_EQ(static_cast<int>(cameras[1].camera.model), layout.max_model_id);

    // Twice: the second write replaces the first, one prior per image.
    for (const double x : {7.0, 1.5}) {
      EXPECT_EQ(WriteColmapDatabasePositionPriors(
                    path,
                    {{"c/d.png", Eigen::Vector3d(x, -2.0, 0.25)},
                     {"b.png", Eigen::Vector3d(3, 4, 5)},
                     {"missing.png", Eigen::Vector3d(9, 9, 9)}}),
                2);
    }
    EXPECT_EQ(StoredPosition(path, layout.priors, 3, 2),
              (std::vector<double>{1.5, -2.0, 0.25}));
    EXPECT_EQ(StoredPosition(path, layout.priors, 1, 1),
              (std::vector<double>{3, 4, 5}));
    EXPECT_EQ(ReadColmapDatabaseVersion(path).label, layout.version);
  }
}

// A 3.9 database opened by 3.11 keeps its images.prior_* columns but gains
// pose_priors, which is where 3.11 reads priors.
TEST(ColmapDatabaseVersions, AnUpgradedDatabaseTakesTheNewerLayout) {
  Layout upgraded = Layouts()[1];
  upgraded.version = "3.11";
  upgraded.schema += kPosePriors311;
  upgraded.priors = ColmapPriorLayout::kPosePriorsWithCovariance;
  const std::string path = MakeDatabase(upgraded);
  const ColmapDatabaseVersion version = ReadColmapDatabaseVersion(path);
  EXPECT_EQ(version.label, "3.11");
  EXPECT_EQ(version.prior_layout, ColmapPriorLayout::kPosePriorsWithCovariance);
  WriteColmapDatabasePositionPriors(path, {{"a.png", {1, 2, 3}}});
  EXPECT_EQ(StoredPosition(path, upgraded.priors, 2, 1),
            (std::vector<double>{1, 2, 3}));
}

TEST(ColmapDatabaseVersions, DatabasesWithoutAPlaceForPriorsAreRefused) {
  Layout odd{"unknown",
             std::string(kCameras) + kImages +
                 "CREATE TABLE pose_priors (x INTEGER);"
                 "PRAGMA user_version = 3900;",
             10,
             ColmapPriorLayout::kNone,
             false};
  const std::string path = MakeDatabase(odd);
  const ColmapDatabaseVersion version = ReadColmapDatabaseVersion(path);
  EXPECT_EQ(version.prior_layout, ColmapPriorLayout::kNone);
  const std::string error = FormatErrorOf([&] {
    WriteColmapDatabasePositionPriors(path, {{"a.png", {1, 2, 3}}});
  });
  EXPECT_EQ(error,
            path +
                ": cannot write position priors: the database (an unknown "
                "COLMAP layout, user_version 3900) has neither "
                "images.prior_tx/ty/tz (COLMAP 3.8, 3.9) nor a pose_priors "
                "table of COLMAP 3.10 to 4.1");
  EXPECT_FALSE(Contains(error, "no such"));
}

TEST(ColmapDatabaseVersions, Version4NumbersAreDecoded) {
  Layout v411 = Layouts()[5];
  v411.version = "4.1.1";
  v411.schema += "PRAGMA user_version = 4010100;";
  v411.max_model_id = 17;
  const std::string path = MakeDatabase(v411);
  const ColmapDatabaseVersion version = ReadColmapDatabaseVersion(path);
  EXPECT_EQ(version.user_version, 4010100);
  EXPECT_EQ(version.label, "4.1.1");
  EXPECT_EQ(DescribeColmapDatabaseVersion(version),
            "COLMAP 4.1.1, user_version 4010100");
  EXPECT_EQ(ReadColmapDatabaseCameras(path)[1].camera.model,
            ColmapCameraModel::kEquirectangular);
}

}  // namespace
}  // namespace odomcal
