#include "odomcal/plugin/colmap/mapper_stretches.h"

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

// Loop partners of image i: the closest image of each later visit to its
// place (in place and direction, far along the path). A visit ends where the
// candidates are interrupted along the path.
std::vector<int> ClosestOnEachLaterVisit(const std::vector<Rigid3d>& poses,
                                         const std::vector<double>& path,
                                         int i,
                                         const CandidatePairOptions& options) {
  std::vector<int> closest;
  int best = -1, last = -1;
  double best_distance = 0.0;
  for (int j = i + 1; j < static_cast<int>(poses.size()); ++j) {
    const double distance = Distance(poses[i], poses[j]);
    if (path[j] - path[i] < options.loop_min_path_m ||
        distance > options.loop_max_distance_m ||
        TurnDeg(poses[i], poses[j]) > options.loop_max_view_angle_deg) {
      continue;
    }
    if (last >= 0 && path[j] - path[last] > 2.0 * options.loop_max_distance_m) {
      closest.push_back(best);
      best = -1;
    }
    if (best < 0 || distance < best_distance) {
      best = j;
      best_distance = distance;
    }
    last = j;
  }
  if (best >= 0) closest.push_back(best);
  return closest;
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
  if (baseline_levels < 0) {
    throw std::invalid_argument("baseline_levels must be >= 0, got " +
                                std::to_string(baseline_levels));
  }
}

std::vector<std::pair<int, int>> OdometryCandidatePairs(
    const std::vector<Rigid3d>& poses, const CandidatePairOptions& options) {
  options.Check();
  const int n = static_cast<int>(poses.size());
  // Path length and accumulated turn from the first pose: both grow along
  // the drive, so they bound a level's reach also while the robot turns in
  // place or jitters back and forth.
  std::vector<double> path(n, 0.0), turned(n, 0.0);
  for (int i = 1; i < n; ++i) {
    path[i] = path[i - 1] + Distance(poses[i - 1], poses[i]);
    turned[i] = turned[i - 1] + TurnDeg(poses[i - 1], poses[i]);
  }
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> level_best(options.baseline_levels);
  for (int i = 0; i < n; ++i) {
    std::fill(level_best.begin(), level_best.end(), -1);
    for (int j = i + 1; j < n; ++j) {
      if (j - i <= options.min_neighbors_each_side) {
        pairs.emplace_back(i, j);
        continue;
      }
      const double along = path[j] - path[i];
      const double turn_along = turned[j] - turned[i];
      if (along > options.max_distance_m ||
          turn_along > options.max_view_angle_deg) {
        break;
      }
      // The direct distance and turn are at most the accumulated ones, so
      // the pair's views are within both limits.
      double reach = 1.0;  // of level k: 1 / 2^k
      for (int k = 0; k < options.baseline_levels; ++k, reach *= 0.5) {
        if (along <= reach * options.max_distance_m &&
            turn_along <= reach * options.max_view_angle_deg) {
          level_best[k] = j;
        }
      }
    }
    for (const int j : level_best) {
      if (j >= 0) pairs.emplace_back(i, j);
    }
    for (const int j : ClosestOnEachLaterVisit(poses, path, i, options)) {
      pairs.emplace_back(i, j);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
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
