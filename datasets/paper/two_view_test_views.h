// Test data of the two-view tests: a random relative pose and 12 noisy
// correspondences (header-only; not part of the library).
#pragma once

#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <random>
#include <vector>

namespace odomcal {

struct TwoViewTestViews {
  Rigid3d cam_i_from_cam_j;  // unit translation
  std::vector<Eigen::Vector2d> u_i, u_j;
};

// A random relative pose (rotation up to 60 degrees about a random axis, a
// random direction) `baseline_m` long, and 12 points 1-5 m deep within +-45
// degrees of camera i, at least 0.5 m in front of camera j, observed with
// `pixel_sigma` noise at f = 400 px (normalised coordinates).
inline TwoViewTestViews RandomTwoViewTestViews(double baseline_m,
                                               double pixel_sigma,
                                               std::mt19937_64* rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::uniform_real_distribution<double> depth(1.0, 5.0);
  Eigen::Vector3d axis, direction;
  for (int c = 0; c < 3; ++c) axis(c) = normal(*rng);
  for (int c = 0; c < 3; ++c) direction(c) = normal(*rng);
  const double angle = 0.5 * (uniform(*rng) + 1.0);
  TwoViewTestViews views;
  views.cam_i_from_cam_j =
      Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized())),
              direction.normalized());
  Rigid3d metric = views.cam_i_from_cam_j;
  metric.translation *= baseline_m;
  const Rigid3d cam_j_from_cam_i = Inverse(metric);
  const double sigma = pixel_sigma / 400.0;
  while (views.u_i.size() < 12) {
    const double z = depth(*rng);
    const double x = uniform(*rng);
    const double y = uniform(*rng);
    const Eigen::Vector3d p_j =
        cam_j_from_cam_i * Eigen::Vector3d(x * z, y * z, z);
    if (p_j.z() < 0.5) continue;
    Eigen::Vector4d n;
    for (int c = 0; c < 4; ++c) n(c) = sigma * normal(*rng);
    views.u_i.emplace_back(x + n(0), y + n(1));
    views.u_j.emplace_back(p_j.x() / p_j.z() + n(2), p_j.y() / p_j.z() + n(3));
  }
  return views;
}

}  // namespace odomcal
