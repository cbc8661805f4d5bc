#include "odomcal/solver/similarity_alignment.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>

#include <random>

namespace odomcal {
namespace {

TEST(AlignSfmToOrigin, RecoversAKnownSimilarity) {
  auto rng = SeededRng(60);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const Sim3d truth{0.37,
                    Eigen::Quaterniond(0.3, -0.5, 0.7, 0.2).normalized(),
                    Eigen::Vector3d(1.0, -2.0, 0.5)};
  std::vector<Rigid3d> origin_from_cam, sfm_from_cam;
  for (int i = 0; i < 20; ++i) {
    const Rigid3d sfm(RandomOdomFromCam(&rng).rotation,
                      Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)));
    sfm_from_cam.push_back(sfm);
    origin_from_cam.push_back(
        Rigid3d(truth.rotation * sfm.rotation, truth * sfm.translation));
  }
  const Sim3d estimate = AlignSfmToOrigin(origin_from_cam, sfm_from_cam, 0.37);
  EXPECT_LT(RotationAngle(estimate.rotation.conjugate() * truth.rotation),
            1e-12);
  EXPECT_LT((estimate.translation - truth.translation).norm(), 1e-12);

  // Camera poses mapped through CamFromOrigin agree with the metric poses.
  for (size_t i = 0; i < sfm_from_cam.size(); ++i) {
    const Rigid3d cam_from_origin =
        CamFromOrigin(Inverse(sfm_from_cam[i]), estimate);
    const Rigid3d expected = Inverse(origin_from_cam[i]);
    EXPECT_LT(
        RotationAngle(cam_from_origin.rotation.conjugate() * expected.rotation),
        1e-12);
    EXPECT_LT((cam_from_origin.translation - expected.translation).norm(),
              1e-12);
  }
}

}  // namespace
}  // namespace odomcal
