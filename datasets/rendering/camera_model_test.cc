#include "odomcal/datasets/rendering/camera_model.h"

#include "odomcal/datasets/simulation/camera_mount.h"
#include "odomcal/solver/angles.h"

#include <gtest/gtest.h>

namespace odomcal {
namespace {

constexpr double kTolerance = 1e-9;

TEST(CameraIntrinsics, ProjectAndPixelToRayAreInverse) {
  CameraIntrinsics camera{640, 480, 500.0, 500.0, 321.5, 238.0, -0.12};
  ASSERT_NO_THROW(camera.Check());
  for (const Eigen::Vector2d& pixel : {Eigen::Vector2d(0.0, 0.0),
                                       Eigen::Vector2d(640, 480),
                                       Eigen::Vector2d(100.25, 400.75)}) {
    const Eigen::Vector3d ray = camera.PixelToRay(pixel);
    EXPECT_NEAR((camera.Project(2.5 * ray) - pixel).norm(), 0.0, kTolerance);
  }
  EXPECT_EQ(camera.ColmapModelName(), "SIMPLE_RADIAL");
  EXPECT_EQ(camera.ColmapParams(),
            (std::vector<double>{500.0, 321.5, 238.0, -0.12}));
  camera.k1 = 0.0;
  camera.fy = 510.0;
  EXPECT_EQ(camera.ColmapModelName(), "PINHOLE");
  EXPECT_EQ(camera.ColmapParams(),
            (std::vector<double>{500.0, 510.0, 321.5, 238.0}));
  // The optical axis hits (cx, cy): a centred camera has cx = width / 2.
  EXPECT_NEAR(
      (camera.Project(Eigen::Vector3d(0, 0, 1)) - Eigen::Vector2d(321.5, 238.0))
          .norm(),
      0.0,
      kTolerance);
}

TEST(CameraIntrinsics, CheckRejectsInvalid) {
  CameraIntrinsics camera;
  camera.fx = -1.0;
  EXPECT_THROW(camera.Check(), std::invalid_argument);
  camera = CameraIntrinsics();
  camera.k1 = 0.1;
  camera.fy = camera.fx + 1.0;
  EXPECT_THROW(camera.Check(), std::invalid_argument);  // SIMPLE_RADIAL: one f
  camera = CameraIntrinsics();
  camera.k1 = -5.0;
  EXPECT_THROW(camera.Check(), std::invalid_argument);  // folds over
}

TEST(MakeCameraMount, AxesOfTheNamedMounts) {
  const Eigen::Vector3d t(0.2, 0.1, 0.4);
  const auto axis = [](const Rigid3d& m, int i) -> Eigen::Vector3d {
    return m.rotation * Eigen::Vector3d::Unit(i);
  };
  const Rigid3d forward = MakeCameraMount(0, 0, 0, t);
  EXPECT_NEAR(
      (axis(forward, 2) - Eigen::Vector3d::UnitX()).norm(), 0, kTolerance);
  EXPECT_NEAR(
      (axis(forward, 0) + Eigen::Vector3d::UnitY()).norm(), 0, kTolerance);
  EXPECT_NEAR(
      (axis(forward, 1) + Eigen::Vector3d::UnitZ()).norm(), 0, kTolerance);
  EXPECT_EQ(forward.translation, t);
  const Rigid3d left = MakeCameraMount(90, 0, 0, t);
  EXPECT_NEAR((axis(left, 2) - Eigen::Vector3d::UnitY()).norm(), 0, kTolerance);
  const Rigid3d down = MakeCameraMount(0, 25, 0, t);
  EXPECT_NEAR(axis(down, 2).z(), -std::sin(25.0 * kPi / 180.0), kTolerance);
  const Rigid3d rolled = MakeCameraMount(0, 0, 90, t);
  EXPECT_NEAR(
      (axis(rolled, 0) + Eigen::Vector3d::UnitZ()).norm(), 0, kTolerance);
  EXPECT_NEAR(
      (axis(rolled, 2) - Eigen::Vector3d::UnitX()).norm(), 0, kTolerance);
}

}  // namespace
}  // namespace odomcal
