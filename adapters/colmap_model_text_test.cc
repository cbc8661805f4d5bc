// The text model files: COLMAP's layout, a fixture, truncation, and errors
// naming path:line.
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/colmap_model_test_support.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using namespace colmap_test;  // NOLINT(google-build-using-namespace)

TEST(ColmapModel, WrittenTextMatchesColmapsLayout) {
  const std::string dir = FreshDir("text_layout");
  ColmapModel model = MakeModel();
  model.points3D.clear();
  for (auto& [id, image] : model.images) {
    for (ColmapPoint2D& point : image.points2D) {
      point.point3D_id = kColmapNoPoint3D;
    }
  }
  model.images.erase(1);
  model.cameras.erase(7);
  model.images[3].points2D.resize(1);
  model.images[12].cam_from_world = Pose(1, 0, 0, 0, 0.1, 2, -3);
  WriteColmapModel(model, dir, ColmapFormat::kText);
  EXPECT_EQ(ReadBytes(dir + "/cameras.txt"),
            "# Camera list with one line of data per camera:\n"
            "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
            "# Number of cameras: 1\n"
            "1 PINHOLE 640 480 500.25 501.5 320.10000000000002 "
            "239.90000000000001\n");
  const std::string images = ReadBytes(dir + "/images.txt");
  const std::string header =
      "# Image list with two lines of data per image:\n"
      "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
      "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
      "# Number of images: 2, mean observations per image: 0\n";
  EXPECT_EQ(images.substr(0, header.size()), header);
  // The second line of an image without points2D is empty.
  EXPECT_TRUE(Contains(images,
                       "\n12 1 0 0 0 0.10000000000000001 2 -3 1 "
                       "000001.png\n\n"))
      << images;
  EXPECT_TRUE(Contains(images, "cam0/000002.png\n10.5 20.25 -1\n")) << images;
  EXPECT_EQ(ReadBytes(dir + "/points3D.txt"),
            "# 3D point list with one line of data per point:\n"
            "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, "
            "POINT2D_IDX)\n"
            "# Number of points: 0, mean track length: 0\n");
}

TEST(ColmapModel, TextFixtureWithAsymmetricQuaternion) {
  const std::string dir = FreshDir("text_fixture");
  WriteFile(dir + "/cameras.txt", kFixtureCameras);
  WriteFile(dir + "/images.txt", kFixtureImages);
  WriteFile(dir + "/points3D.txt", kFixturePoints);
  ExpectFixture(ReadColmapModel(dir));
}

// Text files cut anywhere either still parse (a cut at a line end or inside
// a number can leave a valid file) or fail naming path:line. Every third
// offset keeps the test quick; the binary test above takes every offset.
TEST(ColmapModel, TruncatedTextFilesFailOrParseNeverCrash) {
  const std::string source = FreshDir("truncate_text_source");
  WriteColmapModel(MakeModel(), source, ColmapFormat::kText);
  const std::string dir = FreshDir("truncate_text");
  int num_errors = 0;
  for (const char* name : {"cameras.txt", "images.txt", "points3D.txt"}) {
    const std::string full = ReadBytes(source + "/" + name);
    for (const char* other : {"cameras.txt", "images.txt", "points3D.txt"}) {
      fs::copy_file(source + "/" + other,
                    dir + "/" + other,
                    fs::copy_options::overwrite_existing);
    }
    for (size_t size = 0; size < full.size(); size += 3) {
      WriteFile(dir + "/" + name, full.substr(0, size));
      try {
        ReadColmapModel(dir);
      } catch (const FormatError& error) {
        ++num_errors;
        ASSERT_TRUE(Contains(error.what(), dir + "/")) << error.what();
      }
    }
  }
  EXPECT_GT(num_errors, 0);
}

void ExpectTextError(const std::string& name,
                     const std::string& cameras,
                     const std::string& images,
                     const std::string& points,
                     const std::string& where,
                     const std::string& part) {
  SCOPED_TRACE(name);
  const std::string dir = FreshDir(name);
  WriteFile(dir + "/cameras.txt", cameras);
  WriteFile(dir + "/images.txt", images);
  WriteFile(dir + "/points3D.txt", points);
  const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
  EXPECT_TRUE(Contains(error, dir + "/" + where + ": ")) << error;
  EXPECT_TRUE(Contains(error, part)) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

TEST(ColmapModel, TextErrorsNamePathAndLine) {
  const std::string cameras = kFixtureCameras;
  const std::string images = kFixtureImages;
  const std::string points = kFixturePoints;
  ExpectTextError("few_params",
                  "1 PINHOLE 640 480 1 2 3\n",
                  "",
                  "",
                  "cameras.txt:1",
                  "camera_id 1: model PINHOLE takes 4 parameters, got 3");
  ExpectTextError("camera_columns",
                  "# c\n1 PINHOLE 640\n",
                  "",
                  "",
                  "cameras.txt:2",
                  "got 3 fields");
  ExpectTextError("nan_param",
                  "1 SIMPLE_PINHOLE 640 480 nan 2 3\n",
                  "",
                  "",
                  "cameras.txt:1",
                  "PARAMS: 'nan' is not a finite number");
  ExpectTextError("negative_width",
                  "1 SIMPLE_PINHOLE -640 480 1 2 3\n",
                  "",
                  "",
                  "cameras.txt:1",
                  "WIDTH: '-640' is not a non-negative");
  ExpectTextError("duplicate_camera",
                  cameras + cameras,
                  "",
                  "",
                  "cameras.txt:8",
                  "duplicate camera_id 4");
  ExpectTextError("image_columns",
                  cameras,
                  "9 0.9274 0.1 0.2 0.3 0.5 -1 2 4 my image.png\n\n",
                  points,
                  "images.txt:1",
                  "expected 10 fields");
  ExpectTextError("image_missing_name",
                  cameras,
                  "9 0.9274 0.1 0.2 0.3 0.5 -1 2 4\n\n",
                  points,
                  "images.txt:1",
                  "got 9");
  ExpectTextError("image_inf",
                  cameras,
                  "9 0.9274 0.1 0.2 0.3 inf -1 2 4 a.png\n\n",
                  points,
                  "images.txt:1",
                  "TX: 'inf' is not a finite number");
  ExpectTextError("image_points_line_missing",
                  cameras,
                  "9 0.9274 0.1 0.2 0.3 0.5 -1 2 4 a.png\n",
                  "",
                  "images.txt:1",
                  "missing its POINTS2D line");
  ExpectTextError("image_points_columns",
                  cameras,
                  "9 1 0 0 0 0 0 0 4 a.png\n1 2 -1 3 4\n",
                  "",
                  "images.txt:2",
                  "expected triples X Y POINT3D_ID, got 5");
  ExpectTextError("image_points_comment",
                  cameras,
                  "9 1 0 0 0 0 0 0 4 a.png\n# points\n",
                  "",
                  "images.txt:2",
                  "found a comment");
  ExpectTextError("image_bad_point3D",
                  cameras,
                  "9 1 0 0 0 0 0 0 4 a.png\n1 2 -2\n",
                  "",
                  "images.txt:2",
                  "POINT3D_ID: '-2'");
  ExpectTextError("image_quaternion_norm",
                  cameras,
                  "9 0.5 0.1 0.2 0.3 0 0 0 4 a.png\n\n",
                  "",
                  "images.txt:1",
                  "image_id 9: quaternion (QW QX QY QZ) has norm");
  ExpectTextError("image_zero_quaternion",
                  cameras,
                  "9 0 0 0 0 0 0 0 4 a.png\n\n",
                  "",
                  "images.txt:1",
                  "has norm 0");
  ExpectTextError("image_missing_camera",
                  cameras,
                  "9 1 0 0 0 0 0 0 5 a.png\n\n",
                  "",
                  "images.txt:1",
                  "camera_id 5 is not in");
  ExpectTextError("image_id_range",
                  cameras,
                  "4294967296 1 0 0 0 0 0 0 4 a.png\n\n",
                  "",
                  "images.txt:1",
                  "IMAGE_ID: 4294967296 is out of range");
  ExpectTextError("duplicate_image",
                  cameras,
                  "9 1 0 0 0 0 0 0 4 a.png\n\n9 1 0 0 0 0 0 0 4 b.png\n\n",
                  "",
                  "images.txt:3",
                  "duplicate image_id 9");
  ExpectTextError("point_columns",
                  cameras,
                  images,
                  "77 1 -2 0.5 10 20 30\n",
                  "points3D.txt:1",
                  "got 7 fields");
  ExpectTextError("point_odd_track",
                  cameras,
                  images,
                  "77 1 -2 0.5 10 20 30 0.75 9\n",
                  "points3D.txt:1",
                  "got 9 fields");
  ExpectTextError("point_rgb",
                  cameras,
                  images,
                  "77 1 -2 0.5 10 256 30 0.75 9 0\n",
                  "points3D.txt:1",
                  "G: 256 is out of range");
  ExpectTextError("point_track_image",
                  cameras,
                  images,
                  "77 1 -2 0.5 10 20 30 0.75 8 0\n",
                  "points3D.txt:1",
                  "track names image_id 8");
  ExpectTextError("point_track_index",
                  cameras,
                  images,
                  "77 1 -2 0.5 10 20 30 0.75 9 2\n",
                  "points3D.txt:1",
                  "track names point2D_idx 2");
  ExpectTextError("point_missing",
                  cameras,
                  images,
                  "",
                  "images.txt",
                  "point2D 0 names point3D_id 77, which is not in");
}

}  // namespace
}  // namespace odomcal
