#include "odomcal/adapters/colmap_database.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// The cameras and images tables exactly as `colmap database_creator` (3.8)
// creates them (read back from sqlite_master).
constexpr const char* kColmap38Schema =
    "CREATE TABLE cameras (camera_id INTEGER PRIMARY KEY AUTOINCREMENT NOT "
    "NULL, model INTEGER NOT NULL, width INTEGER NOT NULL, height INTEGER NOT "
    "NULL, params BLOB, prior_focal_length INTEGER NOT NULL);"
    "CREATE TABLE images (image_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, "
    "name TEXT NOT NULL UNIQUE, camera_id INTEGER NOT NULL, prior_qw REAL, "
    "prior_qx REAL, prior_qy REAL, prior_qz REAL, prior_tx REAL, prior_ty "
    "REAL, prior_tz REAL, CONSTRAINT image_id_check CHECK(image_id >= 0 and "
    "image_id < 2147483647), FOREIGN KEY(camera_id) REFERENCES "
    "cameras(camera_id));";

std::string FreshDir(const std::string& name) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("odomcal_colmap_db_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

std::string ReadBytes(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(stream), {});
}

// Little-endian float64 blob, as COLMAP stores camera params.
std::string ParamsBlob(const std::vector<double>& params) {
  std::string blob;
  for (const double value : params) {
    uint64_t bits = 0;
    std::memcpy(&bits, &value, 8);
    for (int i = 0; i < 8; ++i)
      blob.push_back(static_cast<char>(bits >> (8 * i)));
  }
  return blob;
}

class TestDatabase {
 public:
  explicit TestDatabase(const std::string& path) {
    EXPECT_EQ(sqlite3_open(path.c_str(), &db_), SQLITE_OK);
  }
  ~TestDatabase() { sqlite3_close(db_); }

  void Exec(const std::string& sql) {
    char* message = nullptr;
    EXPECT_EQ(sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &message),
              SQLITE_OK)
        << (message != nullptr ? message : "") << "\n"
        << sql;
    sqlite3_free(message);
  }

  void AddCamera(int64_t id,
                 int64_t model,
                 int64_t width,
                 int64_t height,
                 const std::string& blob,
                 int prior) {
    sqlite3_stmt* statement = nullptr;
    ASSERT_EQ(
        sqlite3_prepare_v2(db_,
                           "INSERT INTO cameras VALUES (?, ?, ?, ?, ?, ?)",
                           -1,
                           &statement,
                           nullptr),
        SQLITE_OK);
    sqlite3_bind_int64(statement, 1, id);
    sqlite3_bind_int64(statement, 2, model);
    sqlite3_bind_int64(statement, 3, width);
    sqlite3_bind_int64(statement, 4, height);
    sqlite3_bind_blob(statement,
                      5,
                      blob.data(),
                      static_cast<int>(blob.size()),
                      SQLITE_TRANSIENT);
    sqlite3_bind_int64(statement, 6, prior);
    EXPECT_EQ(sqlite3_step(statement), SQLITE_DONE);
    sqlite3_finalize(statement);
  }

 private:
  sqlite3* db_ = nullptr;
};

// A COLMAP 3.8 project database: image_ids in import order, which is not
// name order.
std::string MakeDatabase(const std::string& dir, const std::string& name) {
  const std::string path = dir + "/" + name;
  TestDatabase db(path);
  db.Exec(kColmap38Schema);
  db.AddCamera(1, 1, 640, 480, ParamsBlob({500.5, 501.25, 320, 240}), 1);
  db.AddCamera(2,
               4,
               1280,
               720,
               ParamsBlob({900, 901, 640, 360, -0.1, 0.01, 1e-4, -2e-5}),
               0);
  db.Exec(
      "INSERT INTO images (image_id, name, camera_id) VALUES "
      "(1, 'cam0/000003.png', 1), (2, 'cam0/000001.png', 1), "
      "(3, 'cam1/000002.png', 2), (7, 'cam0/000002.png', 1);");
  return path;
}

TEST(ColmapDatabase, ReadsImagesAndCamerasOfAColmap38Database) {
  const std::string path = MakeDatabase(FreshDir("read"), "database.db");
  const std::vector<ColmapDatabaseImage> images =
      ReadColmapDatabaseImages(path);
  ASSERT_EQ(images.size(), 4u);
  EXPECT_EQ(images[0].image_id, 1u);
  EXPECT_EQ(images[0].name, "cam0/000003.png");
  EXPECT_EQ(images[1].name, "cam0/000001.png");
  EXPECT_EQ(images[2].camera_id, 2u);
  EXPECT_EQ(images[3].image_id, 7u);
  EXPECT_EQ(images[3].name, "cam0/000002.png");

  const std::vector<ColmapDatabaseCamera> cameras =
      ReadColmapDatabaseCameras(path);
  ASSERT_EQ(cameras.size(), 2u);
  EXPECT_EQ(cameras[0].camera.camera_id, 1u);
  EXPECT_EQ(cameras[0].camera.model, ColmapCameraModel::kPinhole);
  EXPECT_EQ(cameras[0].camera.width, 640u);
  EXPECT_EQ(cameras[0].camera.height, 480u);
  EXPECT_EQ(cameras[0].camera.params,
            (std::vector<double>{500.5, 501.25, 320, 240}));
  EXPECT_TRUE(cameras[0].prior_focal_length);
  EXPECT_EQ(cameras[1].camera.model, ColmapCameraModel::kOpenCV);
  EXPECT_EQ(cameras[1].camera.params,
            (std::vector<double>{900, 901, 640, 360, -0.1, 0.01, 1e-4, -2e-5}));
  EXPECT_FALSE(cameras[1].prior_focal_length);
}

TEST(ColmapDatabase, ReadingLeavesTheDatabaseByteIdentical) {
  const std::string dir = FreshDir("untouched");
  const std::string path = MakeDatabase(dir, "database.db");
  const std::string before = ReadBytes(path);
  const auto modified = fs::last_write_time(path);
  ReadColmapDatabaseImages(path);
  ReadColmapDatabaseCameras(path);
  EXPECT_EQ(ReadBytes(path), before);
  EXPECT_EQ(fs::last_write_time(path), modified);
  // No journal, -wal or -shm file appeared next to it.
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) {
    names.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(names, std::vector<std::string>{"database.db"});
}

TEST(ColmapDatabase, ReadsADatabaseWhoseFolderIsReadOnly) {
  const std::string dir = FreshDir("read_only_folder");
  const std::string path = MakeDatabase(dir, "database.db");
  fs::permissions(path, fs::perms::owner_read, fs::perm_options::replace);
  fs::permissions(dir,
                  fs::perms::owner_read | fs::perms::owner_exec,
                  fs::perm_options::replace);
  EXPECT_EQ(ReadColmapDatabaseImages(path).size(), 4u);
  fs::permissions(dir, fs::perms::owner_all, fs::perm_options::replace);
}

TEST(ColmapDatabase, PathsWithUriSyntaxCharacters) {
  const std::string path =
      MakeDatabase(FreshDir("uri_chars"), "my db?x=1#%41.db");
  EXPECT_EQ(ReadColmapDatabaseImages(path).size(), 4u);
}

TEST(ColmapDatabase, MissingOrUnreadableDatabasesAreNamed) {
  const std::string dir = FreshDir("errors");
  const std::string missing = dir + "/missing.db";
  std::string error = FormatErrorOf([&] { ReadColmapDatabaseImages(missing); });
  EXPECT_TRUE(Contains(error,
                       missing + ": cannot open the COLMAP database: "
                                 "no such file"))
      << error;
  EXPECT_FALSE(fs::exists(missing));  // not created

  error = FormatErrorOf([&] { ReadColmapDatabaseImages(dir); });
  EXPECT_TRUE(Contains(error,
                       dir + ": cannot open the COLMAP database: not a "
                             "regular file"))
      << error;

  const std::string text = dir + "/text.db";
  std::ofstream(text) << "this is not an SQLite database, just some text\n";
  error = FormatErrorOf([&] { ReadColmapDatabaseCameras(text); });
  EXPECT_TRUE(Contains(error, text + ": ")) << error;

  const std::string empty = dir + "/empty.db";
  {
    TestDatabase db(empty);
    db.Exec("CREATE TABLE other (x INTEGER);");
  }
  error = FormatErrorOf([&] { ReadColmapDatabaseImages(empty); });
  EXPECT_TRUE(Contains(error,
                       empty + ": not a readable COLMAP database "
                               "(reading table 'images'): no such "
                               "table: images"))
      << error;
}

TEST(ColmapDatabase, RejectsBadCameraRows) {
  struct Case {
    int64_t model;
    std::string blob;
    const char* part;
  };
  const Case cases[] = {
      {18,
       ParamsBlob({1, 2, 3}),
       "camera_id 1: unknown camera model id 18 (COLMAP 3.8 to 4.1 models are "
       "0 to 17)"},
      {-1, ParamsBlob({1, 2, 3}), "unknown camera model id -1"},
      {1,
       ParamsBlob({1, 2, 3}),
       "camera_id 1: params blob has 24 bytes, model PINHOLE needs 4 float64"},
      {0, "", "params blob has 0 bytes"},
      {0, ParamsBlob({1, NAN, 3}), "param 1 is not finite"},
  };
  for (size_t k = 0; k < std::size(cases); ++k) {
    SCOPED_TRACE(k);
    const std::string path =
        FreshDir("bad_camera_" + std::to_string(k)) + "/database.db";
    {
      TestDatabase db(path);
      db.Exec(kColmap38Schema);
      db.AddCamera(1, cases[k].model, 640, 480, cases[k].blob, 0);
    }
    const std::string error =
        FormatErrorOf([&] { ReadColmapDatabaseCameras(path); });
    EXPECT_TRUE(Contains(error, path + ": ")) << error;
    EXPECT_TRUE(Contains(error, cases[k].part)) << error;
  }
}

}  // namespace
}  // namespace odomcal
