// CameraInfo -> COLMAP camera: the COLMAP camera must project points where
// OpenCV (ROS's calibration convention) does, shifted by half a pixel.
// COLMAP's projection is restated below from src/colmap/sensor/models.h.
#include "odomcal/adapters/bag/camera_info_conversion.h"

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace odomcal::bag {
namespace {

// COLMAP's ImgFromCam for the models the conversion produces.
Eigen::Vector2d ColmapProject(const ColmapCamera& camera,
                              const Eigen::Vector3d& p) {
  const std::vector<double>& k = camera.params;
  double u = p.x() / p.z();
  double v = p.y() / p.z();
  double du = 0.0;
  double dv = 0.0;
  switch (camera.model) {
    case ColmapCameraModel::kPinhole:
      break;
    case ColmapCameraModel::kOpenCV: {
      const double r2 = u * u + v * v;
      const double radial = k[4] * r2 + k[5] * r2 * r2;
      du = u * radial + 2 * k[6] * u * v + k[7] * (r2 + 2 * u * u);
      dv = v * radial + 2 * k[7] * u * v + k[6] * (r2 + 2 * v * v);
      break;
    }
    case ColmapCameraModel::kFullOpenCV: {
      const double r2 = u * u + v * v;
      const double r4 = r2 * r2;
      const double r6 = r4 * r2;
      const double radial = (1 + k[4] * r2 + k[5] * r4 + k[8] * r6) /
                            (1 + k[9] * r2 + k[10] * r4 + k[11] * r6);
      du = u * radial + 2 * k[6] * u * v + k[7] * (r2 + 2 * u * u) - u;
      dv = v * radial + 2 * k[7] * u * v + k[6] * (r2 + 2 * v * v) - v;
      break;
    }
    case ColmapCameraModel::kOpenCVFisheye: {
      // FisheyeFromNormal, then the radial polynomial in theta.
      const double r = std::sqrt(u * u + v * v);
      if (r > 1e-12) {
        const double theta = std::atan(r);
        u = u * theta / r;
        v = v * theta / r;
      }
      const double t2 = u * u + v * v;
      const double radial = k[4] * t2 + k[5] * t2 * t2 + k[6] * t2 * t2 * t2 +
                            k[7] * t2 * t2 * t2 * t2;
      du = u * radial;
      dv = v * radial;
      break;
    }
    default:
      ADD_FAILURE() << "unexpected model";
  }
  return {k[0] * (u + du) + k[2], k[1] * (v + dv) + k[3]};
}

std::vector<cv::Point3d> TestPoints() {
  std::vector<cv::Point3d> points;
  for (double x : {-0.9, -0.3, 0.0, 0.4, 0.8}) {
    for (double y : {-0.6, -0.1, 0.5}) points.emplace_back(x, y, 1.7);
  }
  return points;
}

CameraInfoMessage MakeInfo(const std::string& model, std::vector<double> d) {
  CameraInfoMessage info;
  info.width = 752;
  info.height = 480;
  info.distortion_model = model;
  info.d = std::move(d);
  info.k = {458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1};
  return info;
}

cv::Matx33d CvK(const CameraInfoMessage& info) {
  return cv::Matx33d(info.k.data());
}

// Projects with OpenCV in ROS's pixel convention and compares with COLMAP's
// projection of the converted camera minus the half-pixel shift.
void ExpectSameProjection(const CameraInfoMessage& info,
                          const ColmapCamera& camera,
                          bool fisheye) {
  const std::vector<cv::Point3d> points = TestPoints();
  std::vector<cv::Point2d> projected;
  const cv::Vec3d zero(0, 0, 0);
  if (fisheye) {
    cv::fisheye::projectPoints(
        points, projected, zero, zero, CvK(info), info.d);
  } else {
    cv::projectPoints(points, zero, zero, CvK(info), info.d, projected);
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d colmap = ColmapProject(
        camera, Eigen::Vector3d(points[i].x, points[i].y, points[i].z));
    EXPECT_NEAR(colmap.x() - 0.5, projected[i].x, 1e-9) << "point " << i;
    EXPECT_NEAR(colmap.y() - 0.5, projected[i].y, 1e-9) << "point " << i;
  }
}

TEST(CameraInfoConversionTest, PlumbBobWithoutK3IsOpenCV) {
  const CameraInfoMessage info = MakeInfo(
      "plumb_bob", {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0});
  const ColmapCamera camera = ColmapCameraFromCameraInfo(info, "b: /cam");
  EXPECT_EQ(camera.model, ColmapCameraModel::kOpenCV);
  EXPECT_EQ(camera.width, 752u);
  EXPECT_EQ(camera.height, 480u);
  ASSERT_EQ(camera.params.size(), 8u);
  EXPECT_DOUBLE_EQ(camera.params[2], 367.715);
  EXPECT_DOUBLE_EQ(camera.params[3], 248.875);
  ExpectSameProjection(info, camera, false);
}

TEST(CameraInfoConversionTest, PlumbBobWithK3IsFullOpenCV) {
  const CameraInfoMessage info =
      MakeInfo("plumb_bob", {-0.31, 0.12, 0.0011, -0.0007, -0.021});
  const ColmapCamera camera = ColmapCameraFromCameraInfo(info, "b: /cam");
  EXPECT_EQ(camera.model, ColmapCameraModel::kFullOpenCV);
  ASSERT_EQ(camera.params.size(), 12u);
  ExpectSameProjection(info, camera, false);
}

TEST(CameraInfoConversionTest, RationalPolynomialIsFullOpenCV) {
  const CameraInfoMessage info =
      MakeInfo("rational_polynomial",
               {0.52, -0.13, 0.0009, -0.0004, 0.041, 0.88, 0.011, 0.097});
  const ColmapCamera camera = ColmapCameraFromCameraInfo(info, "b: /cam");
  EXPECT_EQ(camera.model, ColmapCameraModel::kFullOpenCV);
  ExpectSameProjection(info, camera, false);
}

TEST(CameraInfoConversionTest, EquidistantIsOpenCVFisheye) {
  const CameraInfoMessage info =
      MakeInfo("equidistant", {-0.013, 0.021, -0.016, 0.0043});
  const ColmapCamera camera = ColmapCameraFromCameraInfo(info, "b: /cam");
  EXPECT_EQ(camera.model, ColmapCameraModel::kOpenCVFisheye);
  ExpectSameProjection(info, camera, true);
}

TEST(CameraInfoConversionTest, EquidistantWithoutCoefficientsStaysFisheye) {
  for (const auto& d : {std::vector<double>{}, std::vector<double>(4, 0.0)}) {
    CameraInfoMessage info = MakeInfo("equidistant", d);
    const ColmapCamera camera = ColmapCameraFromCameraInfo(info, "b: /cam");
    EXPECT_EQ(camera.model, ColmapCameraModel::kOpenCVFisheye);
    info.d.assign(4, 0.0);  // cv::fisheye needs all four
    ExpectSameProjection(info, camera, true);
  }
}

TEST(CameraInfoConversionTest, ZeroOrEmptyDistortionIsPinhole) {
  for (const auto& d : {std::vector<double>{}, std::vector<double>(5, 0.0)}) {
    const CameraInfoMessage info = MakeInfo("plumb_bob", d);
    const ColmapCamera camera = ColmapCameraFromCameraInfo(info, "b: /cam");
    EXPECT_EQ(camera.model, ColmapCameraModel::kPinhole);
    ExpectSameProjection(info, camera, false);
  }
}

std::string ErrorOf(const CameraInfoMessage& info) {
  return FormatErrorOf(
      [&] { ColmapCameraFromCameraInfo(info, "b.bag: /cam/info"); });
}

TEST(CameraInfoConversionTest, RefusesWhatCannotBeUsed) {
  CameraInfoMessage info = MakeInfo("kannala_brandt", {0.1, 0.2, 0.3, 0.4});
  std::string error = ErrorOf(info);
  EXPECT_TRUE(Contains(error, "b.bag: /cam/info: distortion_model")) << error;
  EXPECT_TRUE(Contains(error, "kannala_brandt")) << error;

  info = MakeInfo("plumb_bob", {0.1, 0.2});
  error = ErrorOf(info);
  EXPECT_TRUE(Contains(error, "needs 5 coefficients")) << error;

  info = MakeInfo("plumb_bob", {});
  info.k[0] = 0.0;
  error = ErrorOf(info);
  EXPECT_TRUE(Contains(error, ": K: ")) << error;

  info = MakeInfo("plumb_bob", {});
  info.binning_x = 2;
  error = ErrorOf(info);
  EXPECT_TRUE(Contains(error, "binning")) << error;
  info.binning_x = 1;
  info.binning_y = 1;
  EXPECT_EQ(ColmapCameraFromCameraInfo(info, "c").model,
            ColmapCameraModel::kPinhole);

  info = MakeInfo("plumb_bob", {});
  info.width = 0;
  error = ErrorOf(info);
  EXPECT_TRUE(Contains(error, "width/height")) << error;

  info = MakeInfo("plumb_bob", {});
  info.roi = {10, 20, 240, 320};
  error = ErrorOf(info);
  EXPECT_TRUE(Contains(error, ": roi: ")) << error;
  info.roi = {0, 0, 480, 752};  // the full image
  EXPECT_EQ(ColmapCameraFromCameraInfo(info, "c").model,
            ColmapCameraModel::kPinhole);
  info.roi = {};

  error = FormatErrorOf(
      [&] { CheckCameraInfoImageSize(info, 640, 480, "b.bag: /cam/info"); });
  EXPECT_TRUE(Contains(error, "b.bag: /cam/info: width/height")) << error;
  EXPECT_TRUE(Contains(error, "640 x 480")) << error;
  CheckCameraInfoImageSize(info, 752, 480, "c");
}

// The line must be one odomcal's COLMAP reader accepts, with the values.
TEST(CameraInfoConversionTest, LineReadsBackAsColmapCamera) {
  const CameraInfoMessage info = MakeInfo(
      "plumb_bob", {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0});
  const ColmapCamera camera = ColmapCameraFromCameraInfo(info, "c");
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) / "camera_line_model";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cameras.txt") << ColmapCameraLine(camera) << "\n";
  std::ofstream(dir / "images.txt") << "";
  std::ofstream(dir / "points3D.txt") << "";
  const ColmapModel model = ReadColmapModel(dir.string());
  std::filesystem::remove_all(dir);
  ASSERT_EQ(model.cameras.size(), 1u);
  const ColmapCamera& read = model.cameras.at(1);
  EXPECT_EQ(read.model, ColmapCameraModel::kOpenCV);
  EXPECT_EQ(read.width, 752u);
  EXPECT_EQ(read.height, 480u);
  const std::vector<double> expected = {458.654,
                                        457.296,
                                        367.715,
                                        248.875,
                                        -0.28340811,
                                        0.07395907,
                                        0.00019359,
                                        1.76187114e-05};
  // The flags hold the same numbers exactly.
  const std::string flags = OdomcalCameraFlags(camera);
  const std::string prefix = "--camera_model OPENCV --camera_params ";
  ASSERT_EQ(flags.substr(0, prefix.size()), prefix);
  std::stringstream numbers(flags.substr(prefix.size()));
  std::string number;
  for (const double value : camera.params) {
    ASSERT_TRUE(std::getline(numbers, number, ',')) << flags;
    EXPECT_EQ(std::strtod(number.c_str(), nullptr), value) << number;
  }
  EXPECT_FALSE(std::getline(numbers, number, ',')) << flags;
  EXPECT_TRUE(Contains(flags, ",-0.28340811,")) << flags;  // shortest form
  ASSERT_EQ(read.params.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_DOUBLE_EQ(read.params[i], expected[i]) << "parameter " << i;
  }
}

}  // namespace
}  // namespace odomcal::bag
