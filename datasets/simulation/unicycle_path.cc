#include "odomcal/datasets/simulation/unicycle_path.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <utility>

namespace odomcal {

PlanarPose UnicycleStep(const PlanarPose& pose, double v, double w, double dt) {
  const double dyaw = w * dt;
  double forward, left;
  if (std::abs(dyaw) < 1e-9) {
    forward = v * dt;
    left = 0.5 * v * dt * dyaw;
  } else {
    forward = v / w * std::sin(dyaw);
    left = v / w * (1.0 - std::cos(dyaw));
  }
  PlanarPose next;
  next.x =
      pose.x + std::cos(pose.yaw_rad) * forward - std::sin(pose.yaw_rad) * left;
  next.y =
      pose.y + std::sin(pose.yaw_rad) * forward + std::cos(pose.yaw_rad) * left;
  next.yaw_rad = pose.yaw_rad + dyaw;
  return next;
}

UnicyclePath::UnicyclePath(std::vector<PathManoeuvre> manoeuvres)
    : manoeuvres_(std::move(manoeuvres)) {
  if (manoeuvres_.empty()) {
    throw std::invalid_argument("UnicyclePath: no manoeuvres");
  }
}

int64_t UnicyclePath::duration_ns() const {
  if (manoeuvres_.empty()) return 0;
  return manoeuvres_.back().start_ns + manoeuvres_.back().duration_ns;
}

PlanarPose UnicyclePath::PoseAt(int64_t t_ns) const {
  if (manoeuvres_.empty()) return PlanarPose();
  t_ns = std::clamp<int64_t>(t_ns, 0, duration_ns());
  // Last manoeuvre starting at or before t.
  auto it = std::upper_bound(
      manoeuvres_.begin(),
      manoeuvres_.end(),
      t_ns,
      [](int64_t t, const PathManoeuvre& m) { return t < m.start_ns; });
  const PathManoeuvre& m = *std::prev(it);
  return UnicycleStep(
      m.start, m.speed_mps, m.yaw_rate_radps, 1e-9 * (t_ns - m.start_ns));
}

Eigen::Vector2d UnicyclePath::DistanceAndYawBetween(int64_t t0_ns,
                                                    int64_t t1_ns) const {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const PathManoeuvre& m : manoeuvres_) {
    const int64_t a = std::max(t0_ns, m.start_ns);
    const int64_t b = std::min(t1_ns, m.start_ns + m.duration_ns);
    if (b <= a) continue;
    const double dt = 1e-9 * (b - a);
    sum += Eigen::Vector2d(m.speed_mps * dt, m.yaw_rate_radps * dt);
  }
  return sum;
}

}  // namespace odomcal
