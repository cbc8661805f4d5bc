#include "odomcal/plugin/mapper_stretches.h"

#include "odomcal/solver/angles.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>

namespace odomcal {
namespace {

double Distance(const Rigid3d& a, const Rigid3d& b) {
  return (a.translation - b.translation).norm();
}

// The angle between the two viewing directions: the odometry's rotation
// from a to b, which the rigidly mounted camera shares.
double TurnDeg(const Rigid3d& a, const Rigid3d& b) {
  return RotationAngle(a.rotation.inverse() * b.rotation) * kRadToDeg;
}

void CheckPositive(double value, const char* name) {
  if (!(std::isfinite(value) && value > 0.0)) {
    throw std::invalid_argument(std::string(name) +
                                " must be finite and > 0, got " +
                                std::to_string(value));
  }
}

}  // namespace

void CandidatePairOptions::Check() const {
  CheckPositive(max_distance_m, "max_distance_m");
  CheckPositive(max_view_angle_deg, "max_view_angle_deg");
  CheckPositive(loop_max_distance_m, "loop_max_distance_m");
  CheckPositive(loop_max_view_angle_deg, "loop_max_view_angle_deg");
  CheckPositive(loop_min_path_m, "loop_min_path_m");
  if (min_neighbors_each_side < 0) {
    throw std::invalid_argument("min_neighbors_each_side must be >= 0, got " +
                                std::to_string(min_neighbors_each_side));
  }
}

std::vector<std::pair<int, int>> OdometryCandidatePairs(
    const std::vector<Rigid3d>& poses, const CandidatePairOptions& options) {
  options.Check();
  const int n = static_cast<int>(poses.size());
  // Path length from the first pose, to tell a loop from a neighbour.
  std::vector<double> path(n, 0.0);
  for (int i = 1; i < n; ++i) {
    path[i] = path[i - 1] + Distance(poses[i - 1], poses[i]);
  }
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double distance = Distance(poses[i], poses[j]);
      const double turn = TurnDeg(poses[i], poses[j]);
      const bool neighbor = j - i <= options.min_neighbors_each_side;
      const bool along_path = path[j] - path[i] <= options.max_distance_m &&
                              distance <= options.max_distance_m &&
                              turn <= options.max_view_angle_deg;
      const bool loop = path[j] - path[i] >= options.loop_min_path_m &&
                        distance <= options.loop_max_distance_m &&
                        turn <= options.loop_max_view_angle_deg;
      if (neighbor || along_path || loop) pairs.emplace_back(i, j);
    }
  }
  return pairs;
}

double ViewAngleLimitDeg(double field_of_view_deg, double max_view_angle_deg) {
  if (!(std::isfinite(field_of_view_deg) && field_of_view_deg > 0.0)) {
    return max_view_angle_deg;
  }
  return std::min(max_view_angle_deg, 0.5 * field_of_view_deg);
}

std::optional<std::pair<int, int>> ChooseInitialPair(
    const std::vector<Rigid3d>& poses,
    const std::vector<std::pair<int, int>>& candidates,
    const InitialPairOptions& options) {
  const int n = static_cast<int>(poses.size());
  std::optional<std::pair<int, int>> best;
  // (turns enough, baseline in cm, -distance of the pair's middle from the
  // stretch's middle): larger is better. Baselines within 1 cm count as
  // equal, so that the middle decides between them.
  std::tuple<bool, double, int> best_score;
  for (const auto& [i, j] : candidates) {
    const double baseline = Distance(poses.at(i), poses.at(j));
    const double turn = TurnDeg(poses[i], poses[j]);
    if (baseline < options.min_baseline_m ||
        baseline > options.max_baseline_m || turn > options.max_turn_deg) {
      continue;
    }
    const std::tuple<bool, double, int> score{turn >= options.min_turn_deg,
                                              std::floor(baseline * 100.0),
                                              -std::abs(i + j - (n - 1))};
    if (!best || score > best_score) {
      best = std::make_pair(std::min(i, j), std::max(i, j));
      best_score = score;
    }
  }
  return best;
}

}  // namespace odomcal
