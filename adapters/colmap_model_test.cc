#include "odomcal/adapters/colmap_model.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// Quaternions are normalised again on reading: a normalised double quaternion
// may move by an ulp or two.
constexpr double kQuaternionTolerance = 1e-15;
// The fixture's expected point was computed separately (Python, double) from
// the rotation-matrix formula; both sides round at the 1e-16 level.
constexpr double kFixtureTolerance = 1e-11;

// A fresh, empty directory under the test temp dir.
std::string FreshDir(const std::string& name) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("odomcal_colmap_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

void WriteFile(const std::string& path, const std::string& bytes) {
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  stream.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(stream.good()) << path;
}

std::string ReadBytes(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(stream), {});
}

Rigid3d Pose(double qw,
             double qx,
             double qy,
             double qz,
             double tx,
             double ty,
             double tz) {
  return Rigid3d(Eigen::Quaterniond(qw, qx, qy, qz).normalized(),
                 Eigen::Vector3d(tx, ty, tz));
}

// Two cameras, three images (ids not in name order, one name in a
// sub-folder), three points; one point2D without a 3D point, one image
// without points2D.
ColmapModel MakeModel() {
  ColmapModel model;
  model.cameras[1] = MakeColmapCamera(
      1, ColmapCameraModel::kPinhole, 640, 480, {500.25, 501.5, 320.1, 239.9});
  model.cameras[7] =
      MakeColmapCamera(7,
                       ColmapCameraModel::kOpenCV,
                       1280,
                       720,
                       {900.0, 901.0, 640.5, 360.5, -0.1, 0.01, 1e-4, -2e-5});

  ColmapImage a;
  a.image_id = 3;
  a.name = "cam0/000002.png";
  a.camera_id = 1;
  a.cam_from_world = Pose(0.9274, 0.1, 0.2, 0.3, 0.5, -1.0, 2.0);
  a.points2D = {{Eigen::Vector2d(10.5, 20.25), 100},
                {Eigen::Vector2d(30.0, 40.0), kColmapNoPoint3D},
                {Eigen::Vector2d(1.0 / 3.0, 2.0 / 3.0), 101}};
  model.images[3] = a;
  ColmapImage b;
  b.image_id = 1;
  b.name = "cam0/000003.png";
  b.camera_id = 7;
  b.cam_from_world = Pose(0.1, -0.7, 0.3, 0.2, -3.0, 0.1, 1e-9);
  b.points2D = {{Eigen::Vector2d(5.0, 6.0), 101},
                {Eigen::Vector2d(7.0, 8.0), 100}};
  model.images[1] = b;
  ColmapImage c;
  c.image_id = 12;
  c.name = "000001.png";
  c.camera_id = 1;
  c.cam_from_world = Pose(-0.3, 0.1, 0.9, -0.2, 1e6, -2.5, 0.0);
  model.images[12] = c;

  ColmapPoint3D p;
  p.point3D_id = 100;
  p.xyz = Eigen::Vector3d(1.0, -2.0, 0.5);
  p.rgb = {255, 0, 17};
  p.error = 0.123456789012345;
  p.track = {{3, 0}, {1, 1}};
  model.points3D[100] = p;
  ColmapPoint3D q;
  q.point3D_id = 101;
  q.xyz = Eigen::Vector3d(0.1, 0.2, 0.3);
  q.rgb = {1, 2, 3};
  q.error = 2.5;
  q.track = {{3, 2}, {1, 0}};
  model.points3D[101] = q;
  ColmapPoint3D lonely;  // allowed: no track
  lonely.point3D_id = (int64_t{1} << 40) + 5;
  lonely.xyz = Eigen::Vector3d(-1e-300, 1e300, 0.0);
  model.points3D[lonely.point3D_id] = lonely;
  return model;
}

void ExpectEqualModels(const ColmapModel& expected, const ColmapModel& actual) {
  ASSERT_EQ(expected.cameras.size(), actual.cameras.size());
  for (const auto& [id, camera] : expected.cameras) {
    SCOPED_TRACE("camera_id " + std::to_string(id));
    ASSERT_EQ(actual.cameras.count(id), 1u);
    const ColmapCamera& other = actual.cameras.at(id);
    EXPECT_EQ(other.camera_id, camera.camera_id);
    EXPECT_EQ(other.model, camera.model);
    EXPECT_EQ(other.width, camera.width);
    EXPECT_EQ(other.height, camera.height);
    EXPECT_EQ(other.params, camera.params);
  }
  ASSERT_EQ(expected.images.size(), actual.images.size());
  for (const auto& [id, image] : expected.images) {
    SCOPED_TRACE("image_id " + std::to_string(id));
    ASSERT_EQ(actual.images.count(id), 1u);
    const ColmapImage& other = actual.images.at(id);
    EXPECT_EQ(other.image_id, image.image_id);
    EXPECT_EQ(other.name, image.name);
    EXPECT_EQ(other.camera_id, image.camera_id);
    EXPECT_NEAR(other.cam_from_world.rotation.w(),
                image.cam_from_world.rotation.w(),
                kQuaternionTolerance);
    EXPECT_NEAR(other.cam_from_world.rotation.x(),
                image.cam_from_world.rotation.x(),
                kQuaternionTolerance);
    EXPECT_NEAR(other.cam_from_world.rotation.y(),
                image.cam_from_world.rotation.y(),
                kQuaternionTolerance);
    EXPECT_NEAR(other.cam_from_world.rotation.z(),
                image.cam_from_world.rotation.z(),
                kQuaternionTolerance);
    EXPECT_EQ(other.cam_from_world.translation,
              image.cam_from_world.translation);
    ASSERT_EQ(other.points2D.size(), image.points2D.size());
    for (size_t k = 0; k < image.points2D.size(); ++k) {
      EXPECT_EQ(other.points2D[k].xy, image.points2D[k].xy);
      EXPECT_EQ(other.points2D[k].point3D_id, image.points2D[k].point3D_id);
    }
  }
  ASSERT_EQ(expected.points3D.size(), actual.points3D.size());
  for (const auto& [id, point] : expected.points3D) {
    SCOPED_TRACE("point3D_id " + std::to_string(id));
    ASSERT_EQ(actual.points3D.count(id), 1u);
    const ColmapPoint3D& other = actual.points3D.at(id);
    EXPECT_EQ(other.point3D_id, point.point3D_id);
    EXPECT_EQ(other.xyz, point.xyz);
    EXPECT_EQ(other.rgb, point.rgb);
    EXPECT_EQ(other.error, point.error);
    ASSERT_EQ(other.track.size(), point.track.size());
    for (size_t k = 0; k < point.track.size(); ++k) {
      EXPECT_EQ(other.track[k].image_id, point.track[k].image_id);
      EXPECT_EQ(other.track[k].point2D_idx, point.track[k].point2D_idx);
    }
  }
}

// Little-endian byte builders for hand-made binary fixtures.
struct Bytes {
  std::string data;
  Bytes& U8(uint8_t v) {
    data.push_back(static_cast<char>(v));
    return *this;
  }
  Bytes& U32(uint32_t v) {
    for (int i = 0; i < 4; ++i) U8(static_cast<uint8_t>(v >> (8 * i)));
    return *this;
  }
  Bytes& U64(uint64_t v) {
    for (int i = 0; i < 8; ++i) U8(static_cast<uint8_t>(v >> (8 * i)));
    return *this;
  }
  Bytes& F64(double v) {
    uint64_t bits = 0;
    std::memcpy(&bits, &v, 8);
    return U64(bits);
  }
  Bytes& Text(const std::string& text) {
    data += text;
    return *this;
  }
};

TEST(ColmapCameraModel, IdsNamesAndParameterCountsOfColmap38) {
  struct Expected {
    int id;
    const char* name;
    int num_params;
  };
  const Expected expected[] = {{0, "SIMPLE_PINHOLE", 3},
                               {1, "PINHOLE", 4},
                               {2, "SIMPLE_RADIAL", 4},
                               {3, "RADIAL", 5},
                               {4, "OPENCV", 8},
                               {5, "OPENCV_FISHEYE", 8},
                               {6, "FULL_OPENCV", 12},
                               {7, "FOV", 5},
                               {8, "SIMPLE_RADIAL_FISHEYE", 4},
                               {9, "RADIAL_FISHEYE", 5},
                               {10, "THIN_PRISM_FISHEYE", 12}};
  for (const Expected& e : expected) {
    const std::optional<ColmapCameraModel> model =
        ColmapCameraModelFromId(e.id);
    ASSERT_TRUE(model.has_value()) << e.id;
    EXPECT_EQ(static_cast<int>(*model), e.id);
    EXPECT_STREQ(ColmapCameraModelName(*model), e.name);
    EXPECT_EQ(ColmapCameraModelNumParams(*model), e.num_params);
    EXPECT_EQ(ColmapCameraModelFromName(e.name), model);
  }
  EXPECT_FALSE(ColmapCameraModelFromId(-1).has_value());
  EXPECT_FALSE(ColmapCameraModelFromId(11).has_value());
  EXPECT_FALSE(ColmapCameraModelFromName("pinhole").has_value());
  EXPECT_THROW(ColmapCameraModelName(static_cast<ColmapCameraModel>(11)),
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

TEST(ColmapModel, EveryCameraModelRoundTripsInBothFormats) {
  ColmapModel model;
  for (int id = 0; id <= 10; ++id) {
    ColmapCamera camera;
    camera.camera_id = static_cast<uint32_t>(100 + id);
    camera.model = *ColmapCameraModelFromId(id);
    camera.width = 10 + id;
    camera.height = 20 + id;
    for (int k = 0; k < ColmapCameraModelNumParams(camera.model); ++k) {
      camera.params.push_back(0.5 * k + id);
    }
    model.cameras[camera.camera_id] = camera;
  }
  for (const ColmapFormat format :
       {ColmapFormat::kBinary, ColmapFormat::kText}) {
    const std::string dir = FreshDir(
        format == ColmapFormat::kBinary ? "all_models_bin" : "all_models_txt");
    WriteColmapModel(model, dir, format);
    ExpectEqualModels(model, ReadColmapModel(dir));
  }
}

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

// cam_from_world stored as QW QX QY QZ = (0.9274, 0.1, 0.2, 0.3) (norm
// 1.000035, normalised on reading), T = (0.5, -1, 2). With the Hamilton
// rotation matrix of the normalised (w, x, y, z), evaluated in Python:
//   cam_from_world * (1, -2, 0.5) = (2.488290068595, -2.036368186587,
//                                    1.528148768193)
// Reading the same numbers as x, y, z, w would give (1.4845, 0.6473, 0.7481)
// and the inverse rotation (-0.1082, -2.9637, 3.0119).
constexpr const char* kFixtureCameras =
    "# Camera list with one line of data per camera:\n"
    "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
    "# Number of cameras: 1\n"
    "4 SIMPLE_RADIAL 640 480 500 320 240 0.01\n";
constexpr const char* kFixtureImages =
    "# Image list with two lines of data per image:\n"
    "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
    "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
    "# Number of images: 2, mean observations per image: 0.5\n"
    "9 0.9274 0.1 0.2 0.3 0.5 -1 2 4 frames/img_b.png\n"
    "100.5 200.25 77 3 4 -1\n"
    "2 1 0 0 0 0 0 0 4 frames/img_a.png\n"
    "\n";
constexpr const char* kFixturePoints =
    "# 3D point list with one line of data per point:\n"
    "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, "
    "POINT2D_IDX)\n"
    "# Number of points: 1, mean track length: 1\n"
    "77 1 -2 0.5 10 20 30 0.75 9 0\n";

void ExpectFixture(const ColmapModel& model) {
  ASSERT_EQ(model.cameras.size(), 1u);
  const ColmapCamera& camera = model.cameras.at(4);
  EXPECT_EQ(camera.model, ColmapCameraModel::kSimpleRadial);
  EXPECT_EQ(camera.params, (std::vector<double>{500, 320, 240, 0.01}));
  ASSERT_EQ(model.images.size(), 2u);
  const ColmapImage& image = model.images.at(9);
  EXPECT_EQ(image.name, "frames/img_b.png");
  const Eigen::Vector3d p_in_world(1.0, -2.0, 0.5);
  const Eigen::Vector3d p_in_cam = image.cam_from_world * p_in_world;
  EXPECT_NEAR(p_in_cam.x(), 2.488290068595, kFixtureTolerance);
  EXPECT_NEAR(p_in_cam.y(), -2.036368186587, kFixtureTolerance);
  EXPECT_NEAR(p_in_cam.z(), 1.528148768193, kFixtureTolerance);
  EXPECT_NEAR(image.cam_from_world.rotation.norm(), 1.0, 1e-15);
  // The camera centre maps to the camera origin.
  const Eigen::Vector3d centre = Inverse(image.cam_from_world).translation;
  EXPECT_NEAR((image.cam_from_world * centre).norm(), 0.0, kFixtureTolerance);
  ASSERT_EQ(image.points2D.size(), 2u);
  EXPECT_EQ(image.points2D[0].point3D_id, 77);
  EXPECT_EQ(image.points2D[1].point3D_id, kColmapNoPoint3D);
  EXPECT_TRUE(model.images.at(2).points2D.empty());
  const ColmapPoint3D& point = model.points3D.at(77);
  EXPECT_EQ(point.xyz, p_in_world);
  EXPECT_EQ(point.rgb, (std::array<uint8_t, 3>{10, 20, 30}));
  ASSERT_EQ(point.track.size(), 1u);
  EXPECT_EQ(point.track[0].image_id, 9u);
}

TEST(ColmapModel, TextFixtureWithAsymmetricQuaternion) {
  const std::string dir = FreshDir("text_fixture");
  WriteFile(dir + "/cameras.txt", kFixtureCameras);
  WriteFile(dir + "/images.txt", kFixtureImages);
  WriteFile(dir + "/points3D.txt", kFixturePoints);
  ExpectFixture(ReadColmapModel(dir));
}

// The same model as the text fixture, byte by byte per COLMAP's layout.
Bytes FixtureCamerasBin() {
  Bytes b;
  b.U64(1).U32(4).U32(2).U64(640).U64(480);
  b.F64(500).F64(320).F64(240).F64(0.01);
  return b;
}
Bytes FixtureImagesBin() {
  Bytes b;
  b.U64(2);
  b.U32(9).F64(0.9274).F64(0.1).F64(0.2).F64(0.3).F64(0.5).F64(-1).F64(2);
  b.U32(4).Text("frames/img_b.png").U8(0);
  b.U64(2).F64(100.5).F64(200.25).U64(77).F64(3).F64(4).U64(~uint64_t{0});
  b.U32(2).F64(1).F64(0).F64(0).F64(0).F64(0).F64(0).F64(0);
  b.U32(4).Text("frames/img_a.png").U8(0).U64(0);
  return b;
}
Bytes FixturePointsBin() {
  Bytes b;
  b.U64(1).U64(77).F64(1).F64(-2).F64(0.5).U8(10).U8(20).U8(30).F64(0.75);
  b.U64(1).U32(9).U32(0);
  return b;
}

std::string WriteBinaryFixture(const std::string& name) {
  const std::string dir = FreshDir(name);
  WriteFile(dir + "/cameras.bin", FixtureCamerasBin().data);
  WriteFile(dir + "/images.bin", FixtureImagesBin().data);
  WriteFile(dir + "/points3D.bin", FixturePointsBin().data);
  return dir;
}

TEST(ColmapModel, BinaryFixtureBuiltByteByByte) {
  ExpectFixture(ReadColmapModel(WriteBinaryFixture("binary_fixture")));
}

TEST(ColmapModel, WriterProducesColmapsBinaryLayout) {
  ColmapModel model = ReadColmapModel(WriteBinaryFixture("binary_layout_in"));
  // Write the stored (unnormalised) quaternion, to compare with the fixture
  // bytes: the writer normalises, so give it the already-normal one.
  const std::string dir = FreshDir("binary_layout_out");
  WriteColmapModel(model, dir, ColmapFormat::kBinary);
  EXPECT_EQ(ReadBytes(dir + "/cameras.bin"), FixtureCamerasBin().data);
  EXPECT_EQ(ReadBytes(dir + "/points3D.bin"), FixturePointsBin().data);
  // images.bin: same size and layout; only the quaternion of image 9 differs
  // (the fixture stores it unnormalised).
  const Eigen::Quaterniond q =
      model.images.at(9).cam_from_world.rotation.normalized();
  Bytes expected;
  expected.U64(2);
  expected.U32(2).F64(1).F64(0).F64(0).F64(0).F64(0).F64(0).F64(0);
  expected.U32(4).Text("frames/img_a.png").U8(0).U64(0);
  expected.U32(9).F64(q.w()).F64(q.x()).F64(q.y()).F64(q.z());
  expected.F64(0.5).F64(-1).F64(2).U32(4).Text("frames/img_b.png").U8(0);
  expected.U64(2).F64(100.5).F64(200.25).U64(77).F64(3).F64(4).U64(
      ~uint64_t{0});
  EXPECT_EQ(ReadBytes(dir + "/images.bin"), expected.data);
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

// Every proper prefix of every binary file must fail with the file's name,
// never crash or read past the end.
TEST(ColmapModel, TruncatedBinaryFilesFailNamingTheFile) {
  const std::string source = FreshDir("truncate_source");
  WriteColmapModel(MakeModel(), source, ColmapFormat::kBinary);
  const std::string dir = FreshDir("truncate");
  for (const char* name : {"cameras.bin", "images.bin", "points3D.bin"}) {
    const std::string full = ReadBytes(source + "/" + name);
    ASSERT_GT(full.size(), 100u);
    for (const char* other : {"cameras.bin", "images.bin", "points3D.bin"}) {
      fs::copy_file(source + "/" + other,
                    dir + "/" + other,
                    fs::copy_options::overwrite_existing);
    }
    for (size_t size = 0; size < full.size(); ++size) {
      WriteFile(dir + "/" + name, full.substr(0, size));
      const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
      ASSERT_TRUE(Contains(error, dir + "/" + name + ": byte "))
          << "size " << size << ": " << error;
      ASSERT_EQ(error.find('\n'), std::string::npos) << error;
    }
  }
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

TEST(ColmapModel, GarbledCountsFailBeforeAllocating) {
  const uint64_t kHuge = uint64_t{1} << 60;
  struct Case {
    const char* file;
    size_t count_offset;  // byte offset of the uint64 count to garble
    const char* what;
  };
  // Offsets into the fixture: the file counts, image 9's num_points2D
  // (8 + 4 + 56 + 4 + 17 bytes in), point 77's track length (8 + 8 + 24 + 3
  // + 8).
  const Case cases[] = {{"cameras.bin", 0, "number of cameras"},
                        {"images.bin", 0, "number of images"},
                        {"images.bin", 89, "number of points2D"},
                        {"points3D.bin", 0, "number of points3D"},
                        {"points3D.bin", 51, "track length"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.file) + " " + c.what);
    const std::string dir = WriteBinaryFixture("garbled");
    std::string bytes = ReadBytes(dir + "/" + c.file);
    Bytes huge;
    huge.U64(kHuge);
    bytes.replace(c.count_offset, 8, huge.data);
    WriteFile(dir + "/" + c.file, bytes);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(
        error,
        dir + "/" + c.file + ": byte " + std::to_string(c.count_offset) + ": "))
        << error;
    EXPECT_TRUE(
        Contains(error, std::string(c.what) + " is " + std::to_string(kHuge)))
        << error;
    EXPECT_TRUE(Contains(error, "remaining bytes hold at most")) << error;
  }
}

TEST(ColmapModel, RejectsUnknownCameraModelIds) {
  for (const uint32_t model_id : {11u, 0xffffffffu, 1000u}) {
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

TEST(ColmapModel, BinaryTrailingBytesAndBadValuesAreRejected) {
  {
    const std::string dir = WriteBinaryFixture("trailing");
    WriteFile(dir + "/cameras.bin", FixtureCamerasBin().F64(1.0).data);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(error, "cameras.bin: byte 64: 8 unexpected bytes"))
        << error;
  }
  {
    const std::string dir = WriteBinaryFixture("nan_param");
    Bytes cameras;
    cameras.U64(1).U32(4).U32(2).U64(640).U64(480);
    cameras.F64(500).F64(std::nan("")).F64(240).F64(0.01);
    WriteFile(dir + "/cameras.bin", cameras.data);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(error,
                         "cameras.bin: byte 40: camera 1 of 1 "
                         "(camera_id 4): param is not finite"))
        << error;
  }
  {
    const std::string dir = WriteBinaryFixture("bad_quaternion");
    std::string bytes = FixtureImagesBin().data;
    Bytes zero;
    zero.F64(0.0);
    bytes.replace(8 + 4, 8, zero.data);  // QW of image 9: norm 0.37
    WriteFile(dir + "/images.bin", bytes);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(error,
                         "(image_id 9): quaternion (QW QX QY QZ) has "
                         "norm"))
        << error;
  }
  {
    const std::string dir = WriteBinaryFixture("missing_camera");
    std::string bytes = FixtureImagesBin().data;
    Bytes camera_id;
    camera_id.U32(5);
    bytes.replace(8 + 4 + 56, 4, camera_id.data);
    WriteFile(dir + "/images.bin", bytes);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(
        Contains(error, "camera_id 5 is not in " + dir + "/cameras.bin"))
        << error;
  }
  {
    const std::string dir = WriteBinaryFixture("unterminated_name");
    Bytes images;
    images.U64(1).U32(9);
    for (int k = 0; k < 7; ++k) images.F64(k == 0 ? 1.0 : 0.0);
    images.U32(4).Text(std::string(64, 'x'));
    WriteFile(dir + "/images.bin", images.data);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(error, "name has no terminating")) << error;
  }
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
