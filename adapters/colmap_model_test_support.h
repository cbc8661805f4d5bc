// Helpers shared by the COLMAP model tests (colmap_model*_test.cc): a
// model with every kind of record, a comparison, byte builders and the
// hand-made fixture in both formats.
#pragma once

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace odomcal::colmap_test {

// Quaternions are normalised again on reading: a normalised double quaternion
// may move by an ulp or two.
inline constexpr double kQuaternionTolerance = 1e-15;
// The fixture's expected point was computed separately (Python, double) from
// the rotation-matrix formula; both sides round at the 1e-16 level.
inline constexpr double kFixtureTolerance = 1e-11;

// A fresh, empty directory under the test temp dir.
inline std::string FreshDir(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) / ("odomcal_colmap_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

inline void WriteFile(const std::string& path, const std::string& bytes) {
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  stream.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(stream.good()) << path;
}

inline std::string ReadBytes(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(stream), {});
}

inline Rigid3d Pose(double qw,
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
inline ColmapModel MakeModel() {
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

inline void ExpectEqualModels(const ColmapModel& expected,
                              const ColmapModel& actual) {
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

// cam_from_world stored as QW QX QY QZ = (0.9274, 0.1, 0.2, 0.3) (norm
// 1.000035, normalised on reading), T = (0.5, -1, 2). With the Hamilton
// rotation matrix of the normalised (w, x, y, z), evaluated in Python:
//   cam_from_world * (1, -2, 0.5) = (2.488290068595, -2.036368186587,
//                                    1.528148768193)
// Reading the same numbers as x, y, z, w would give (1.4845, 0.6473, 0.7481)
// and the inverse rotation (-0.1082, -2.9637, 3.0119).
inline constexpr const char* kFixtureCameras =
    "# Camera list with one line of data per camera:\n"
    "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
    "# Number of cameras: 1\n"
    "4 SIMPLE_RADIAL 640 480 500 320 240 0.01\n";
inline constexpr const char* kFixtureImages =
    "# Image list with two lines of data per image:\n"
    "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
    "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
    "# Number of images: 2, mean observations per image: 0.5\n"
    "9 0.9274 0.1 0.2 0.3 0.5 -1 2 4 frames/img_b.png\n"
    "100.5 200.25 77 3 4 -1\n"
    "2 1 0 0 0 0 0 0 4 frames/img_a.png\n"
    "\n";
inline constexpr const char* kFixturePoints =
    "# 3D point list with one line of data per point:\n"
    "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, "
    "POINT2D_IDX)\n"
    "# Number of points: 1, mean track length: 1\n"
    "77 1 -2 0.5 10 20 30 0.75 9 0\n";

inline void ExpectFixture(const ColmapModel& model) {
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

// The same model as the text fixture, byte by byte per COLMAP's layout.
inline Bytes FixtureCamerasBin() {
  Bytes b;
  b.U64(1).U32(4).U32(2).U64(640).U64(480);
  b.F64(500).F64(320).F64(240).F64(0.01);
  return b;
}
inline Bytes FixtureImagesBin() {
  Bytes b;
  b.U64(2);
  b.U32(9).F64(0.9274).F64(0.1).F64(0.2).F64(0.3).F64(0.5).F64(-1).F64(2);
  b.U32(4).Text("frames/img_b.png").U8(0);
  b.U64(2).F64(100.5).F64(200.25).U64(77).F64(3).F64(4).U64(~uint64_t{0});
  b.U32(2).F64(1).F64(0).F64(0).F64(0).F64(0).F64(0).F64(0);
  b.U32(4).Text("frames/img_a.png").U8(0).U64(0);
  return b;
}
inline Bytes FixturePointsBin() {
  Bytes b;
  b.U64(1).U64(77).F64(1).F64(-2).F64(0.5).U8(10).U8(20).U8(30).F64(0.75);
  b.U64(1).U32(9).U32(0);
  return b;
}

inline std::string WriteBinaryFixture(const std::string& name) {
  const std::string dir = FreshDir(name);
  WriteFile(dir + "/cameras.bin", FixtureCamerasBin().data);
  WriteFile(dir + "/images.bin", FixtureImagesBin().data);
  WriteFile(dir + "/points3D.bin", FixturePointsBin().data);
  return dir;
}

}  // namespace odomcal::colmap_test
