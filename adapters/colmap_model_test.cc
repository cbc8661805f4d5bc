// The COLMAP model API: camera models, round trips in both formats, format
// choice, and what the writer refuses.
#include "odomcal/adapters/colmap_model.h"

#include "odomcal/adapters/colmap_model_test_support.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using namespace colmap_test;  // NOLINT(google-build-using-namespace)

// Ids, names and parameter counts as in COLMAP's sensor/models.h: 0-10 at
// 3.8 (src/base/camera_models.h), 11 at 3.11.0, 12-15 at 4.0.0, 16-17 at
// 4.1.0, checked at each tag.
TEST(ColmapCameraModel, IdsNamesAndParameterCountsOfColmap38To41) {
  struct Expected {
    int id;
    const char* name;
    int num_params;
    int num_focal;  // 1: f, cx, cy; 2: fx, fy, cx, cy; 0: none
  };
  const Expected expected[] = {{0, "SIMPLE_PINHOLE", 3, 1},
                               {1, "PINHOLE", 4, 2},
                               {2, "SIMPLE_RADIAL", 4, 1},
                               {3, "RADIAL", 5, 1},
                               {4, "OPENCV", 8, 2},
                               {5, "OPENCV_FISHEYE", 8, 2},
                               {6, "FULL_OPENCV", 12, 2},
                               {7, "FOV", 5, 2},
                               {8, "SIMPLE_RADIAL_FISHEYE", 4, 1},
                               {9, "RADIAL_FISHEYE", 5, 1},
                               {10, "THIN_PRISM_FISHEYE", 12, 2},
                               {11, "RAD_TAN_THIN_PRISM_FISHEYE", 16, 2},
                               {12, "SIMPLE_DIVISION", 4, 1},
                               {13, "DIVISION", 5, 2},
                               {14, "SIMPLE_FISHEYE", 3, 1},
                               {15, "FISHEYE", 4, 2},
                               {16, "EUCM", 6, 2},
                               {17, "EQUIRECTANGULAR", 2, 0}};
  for (const Expected& e : expected) {
    SCOPED_TRACE(e.name);
    const std::optional<ColmapCameraModel> model =
        ColmapCameraModelFromId(e.id);
    ASSERT_TRUE(model.has_value()) << e.id;
    EXPECT_EQ(static_cast<int>(*model), e.id);
    EXPECT_STREQ(ColmapCameraModelName(*model), e.name);
    EXPECT_EQ(ColmapCameraModelNumParams(*model), e.num_params);
    EXPECT_EQ(ColmapCameraModelFromName(e.name), model);
    const std::optional<ColmapPinholeIndices> indices =
        ColmapCameraModelPinholeIndices(*model);
    ASSERT_EQ(indices.has_value(), e.num_focal > 0);
    if (indices) {
      EXPECT_EQ(indices->fx, 0);
      EXPECT_EQ(indices->fy, e.num_focal - 1);
      EXPECT_EQ(indices->cx, e.num_focal);
      EXPECT_EQ(indices->cy, e.num_focal + 1);
    }
  }
  EXPECT_EQ(ColmapCameraModel::kRadTanThinPrismFisheye,
            *ColmapCameraModelFromId(11));
  EXPECT_EQ(ColmapCameraModel::kEquirectangular, *ColmapCameraModelFromId(17));
  EXPECT_FALSE(ColmapCameraModelFromId(-1).has_value());
  EXPECT_FALSE(ColmapCameraModelFromId(18).has_value());
  EXPECT_FALSE(ColmapCameraModelFromName("pinhole").has_value());
  EXPECT_THROW(ColmapCameraModelName(static_cast<ColmapCameraModel>(18)),
               std::invalid_argument);
}

TEST(ColmapModel, BinaryRoundTrip) {
  const std::string dir = FreshDir("binary_round_trip");
  const ColmapModel model = MakeModel();
  WriteColmapModel(model, dir, ColmapFormat::kBinary);
  EXPECT_EQ(DetectColmapModelFormat(dir), ColmapFormat::kBinary);
  ExpectEqualModels(model, ReadColmapModel(dir));
}

TEST(ColmapModel, TextRoundTripIsExact) {
  const std::string dir = FreshDir("text_round_trip");
  const ColmapModel model = MakeModel();
  WriteColmapModel(model, dir, ColmapFormat::kText);
  EXPECT_EQ(DetectColmapModelFormat(dir), ColmapFormat::kText);
  ExpectEqualModels(model, ReadColmapModel(dir));
}

// One camera of every model 0-17, each with an image: read back equal, and
// written again byte for byte the same (rigs and frames included).
TEST(ColmapModel, EveryCameraModelRoundTripsBitIdenticallyInBothFormats) {
  ColmapModel model;
  for (int id = 0; id <= 17; ++id) {
    ColmapCamera camera;
    camera.camera_id = static_cast<uint32_t>(100 + id);
    camera.model = *ColmapCameraModelFromId(id);
    camera.width = 10 + id;
    camera.height = 20 + id;
    for (int k = 0; k < ColmapCameraModelNumParams(camera.model); ++k) {
      camera.params.push_back(0.5 * k + id + 1.0 / 3.0);
    }
    model.cameras[camera.camera_id] = camera;
    ColmapImage image;
    image.image_id = static_cast<uint32_t>(id + 1);
    image.name = "cam" + std::to_string(id) + "/000001.png";
    image.camera_id = camera.camera_id;
    image.cam_from_world = Pose(1, 0.1 * id, -0.2, 0.3, id, -1.0 / 7.0, 2);
    model.images[image.image_id] = image;
  }
  const char* const kFiles[] = {
      "cameras", "images", "points3D", "rigs", "frames"};
  for (const ColmapFormat format :
       {ColmapFormat::kBinary, ColmapFormat::kText}) {
    const std::string extension =
        format == ColmapFormat::kBinary ? ".bin" : ".txt";
    SCOPED_TRACE(extension);
    const std::string first = FreshDir("all_models_first" + extension);
    const std::string second = FreshDir("all_models_second" + extension);
    WriteColmapModel(model, first, format);
    const ColmapModel read = ReadColmapModel(first);
    ExpectEqualModels(model, read);
    WriteColmapModel(read, second, format);
    for (const char* stem : kFiles) {
      const std::string name = stem + extension;
      ASSERT_TRUE(fs::exists(first + "/" + name)) << name;
      EXPECT_EQ(ReadBytes(first + "/" + name), ReadBytes(second + "/" + name))
          << name;
    }
  }
}

TEST(ColmapModel, PrefersBinaryWhenBothFormatsExist) {
  const std::string dir = FreshDir("both_formats");
  const ColmapModel binary_model = MakeModel();
  WriteColmapModel(binary_model, dir, ColmapFormat::kBinary);
  WriteFile(dir + "/cameras.txt", kFixtureCameras);
  WriteFile(dir + "/images.txt", kFixtureImages);
  WriteFile(dir + "/points3D.txt", kFixturePoints);
  EXPECT_EQ(DetectColmapModelFormat(dir), ColmapFormat::kBinary);
  ExpectEqualModels(binary_model, ReadColmapModel(dir));
  // An incomplete binary set falls back to text, as in COLMAP.
  fs::remove(dir + "/points3D.bin");
  EXPECT_EQ(DetectColmapModelFormat(dir), ColmapFormat::kText);
  ExpectFixture(ReadColmapModel(dir));
}

TEST(ColmapModel, MissingOrEmptyFolderNamesIt) {
  const std::string empty = FreshDir("empty_model");
  WriteFile(empty + "/cameras.bin", "");
  std::string error = FormatErrorOf([&] { ReadColmapModel(empty); });
  EXPECT_TRUE(Contains(error, empty + ": not a COLMAP model")) << error;
  EXPECT_TRUE(Contains(error, "found cameras.bin")) << error;
  const std::string missing = empty + "/nope";
  error = FormatErrorOf([&] { ReadColmapModel(missing); });
  EXPECT_TRUE(Contains(error, missing + ": not a COLMAP model: no such"))
      << error;
}

TEST(ColmapModel, SkipsPoints3DOnRequest) {
  const std::string dir = WriteBinaryFixture("skip_points");
  WriteFile(dir + "/points3D.bin", "garbage");
  ColmapReadOptions options;
  options.read_points3D = false;
  const ColmapModel model = ReadColmapModel(dir, options);
  EXPECT_EQ(model.images.size(), 2u);
  EXPECT_TRUE(model.points3D.empty());
  EXPECT_THROW(ReadColmapModel(dir), FormatError);
}

TEST(ColmapModel, RejectsUnknownCameraModelIds) {
  for (const uint32_t model_id : {18u, 0xffffffffu, 1000u}) {
    const std::string dir = WriteBinaryFixture("unknown_model");
    Bytes cameras;
    cameras.U64(1).U32(4).U32(model_id).U64(640).U64(480);
    cameras.F64(500).F64(320).F64(240).F64(0.01);
    WriteFile(dir + "/cameras.bin", cameras.data);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(error,
                         dir + "/cameras.bin: byte 12: camera 1 of 1 "
                               "(camera_id 4): unknown camera model id"))
        << error;
    EXPECT_TRUE(Contains(error, "(COLMAP 3.8 to 4.1 models are 0 to 17)"))
        << error;
  }
  const std::string dir = FreshDir("unknown_model_text");
  WriteFile(dir + "/cameras.txt", "4 PINHOLE_FANCY 640 480 1 2 3\n");
  WriteFile(dir + "/images.txt", "");
  WriteFile(dir + "/points3D.txt", "");
  const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
  EXPECT_TRUE(Contains(error,
                       dir + "/cameras.txt:1: unknown camera model "
                             "'PINHOLE_FANCY'"))
      << error;
}

TEST(ColmapModel, WriterRejectsModelsItCannotWriteFaithfully) {
  const std::string dir = FreshDir("writer_rejects");
  {
    ColmapModel model = MakeModel();
    model.images[3].name = "with space.png";
    EXPECT_THROW(WriteColmapModel(model, dir, ColmapFormat::kText),
                 std::invalid_argument);
    // Binary names may hold blanks.
    WriteColmapModel(model, dir, ColmapFormat::kBinary);
    EXPECT_EQ(ReadColmapModel(dir).images.at(3).name, "with space.png");
  }
  const std::vector<std::function<void(ColmapModel*)>> breakers = {
      [](ColmapModel* m) { m->cameras[1].params.pop_back(); },
      [](ColmapModel* m) { m->cameras[1].camera_id = 2; },
      [](ColmapModel* m) { m->cameras[1].params[0] = NAN; },
      [](ColmapModel* m) { m->images[3].name = ""; },
      [](ColmapModel* m) { m->images[3].camera_id = 99; },
      [](ColmapModel* m) {
        m->images[3].cam_from_world.rotation = Eigen::Quaterniond(0, 0, 0, 0);
      },
      [](ColmapModel* m) { m->images[3].points2D[0].point3D_id = 5; },
      [](ColmapModel* m) {
        m->points3D[100].track.push_back({3, 9});
      },
      [](ColmapModel* m) { m->points3D[100].error = INFINITY; },
  };
  for (size_t k = 0; k < breakers.size(); ++k) {
    SCOPED_TRACE(k);
    ColmapModel model = MakeModel();
    breakers[k](&model);
    EXPECT_THROW(WriteColmapModel(model, dir, ColmapFormat::kBinary),
                 std::invalid_argument);
  }
}

}  // namespace
}  // namespace odomcal
