#include "odomcal/plugin/colmap/mapper_initialization.h"

#include "odomcal/adapters/colmap_two_view_geometries.h"
#include "odomcal/adapters/text_reader.h"
#include "odomcal/solver/format_number.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <stdexcept>
#include <tuple>

namespace odomcal {

void InitialPairTests::Check() const {
  if (min_inliers < 1) {
    throw std::invalid_argument("InitialPairTests: min_inliers must be >= 1");
  }
  if (!(max_forward_motion >= 0.0 && max_forward_motion <= 1.0)) {
    throw std::invalid_argument(
        "InitialPairTests: max_forward_motion must be in [0, 1]");
  }
}

double ForwardMotionOfEssential(const Eigen::Matrix3d& essential) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(essential, Eigen::ComputeFullU);
  return std::abs(svd.matrixU().col(2).normalized().z());
}

std::vector<InitialPairCandidate> RankInitialPairs(
    const std::vector<InitialPairImage>& images,
    const std::vector<ColmapVerifiedPair>& verified,
    const InitialPairTests& options) {
  options.Check();
  std::map<uint32_t, const InitialPairImage*> by_id;
  for (const InitialPairImage& image : images) by_id[image.image_id] = &image;
  std::vector<InitialPairCandidate> candidates;
  for (const ColmapVerifiedPair& pair : verified) {
    if (pair.num_inliers < options.min_inliers) continue;
    const auto a = by_id.find(pair.image_id1);
    const auto b = by_id.find(pair.image_id2);
    if (a == by_id.end() || b == by_id.end()) continue;
    if (!a->second->origin_from_odom || !b->second->origin_from_odom) continue;
    const Rigid3d& pose1 = *a->second->origin_from_odom;
    const Rigid3d& pose2 = *b->second->origin_from_odom;
    InitialPairCandidate candidate;
    candidate.image_id1 = pair.image_id1;
    candidate.image_id2 = pair.image_id2;
    candidate.name1 = a->second->name;
    candidate.name2 = b->second->name;
    candidate.num_inliers = pair.num_inliers;
    candidate.baseline_m = (pose2.translation - pose1.translation).norm();
    candidate.heading_change_deg =
        RotationAngle(pose1.rotation.conjugate() * pose2.rotation) * 180.0 /
        M_PI;
    if (!(candidate.baseline_m > 0.0)) continue;
    double across = 1.0;
    if (pair.essential) {
      const double forward = ForwardMotionOfEssential(*pair.essential);
      candidate.forward_motion = forward;
      // COLMAP's test is strict: |t_z| < max_forward_motion.
      if (!(forward < options.max_forward_motion)) continue;
      across = std::sqrt(std::max(0.0, 1.0 - forward * forward));
    }
    candidate.score = candidate.num_inliers * candidate.baseline_m * across;
    candidates.push_back(std::move(candidate));
  }
  std::sort(candidates.begin(),
            candidates.end(),
            [](const InitialPairCandidate& x, const InitialPairCandidate& y) {
              return std::make_tuple(-x.score, x.image_id1, x.image_id2) <
                     std::make_tuple(-y.score, y.image_id1, y.image_id2);
            });
  return candidates;
}

std::vector<std::string> MapperInitialization::MapperArguments() const {
  std::vector<std::string> arguments;
  if (pair) {
    arguments = {"--Mapper.init_image_id1",
                 std::to_string(pair->image_id1),
                 "--Mapper.init_image_id2",
                 std::to_string(pair->image_id2)};
  }
  if (kind == Kind::kRelaxedSearch || kind == Kind::kRelaxedOdometryPair ||
      kind == Kind::kNeighbourWindow) {
    arguments.insert(arguments.end(),
                     {"--Mapper.init_max_forward_motion",
                      FormatRounded(RelaxedInitialization::kMaxForwardMotion),
                      "--Mapper.init_min_num_inliers",
                      std::to_string(RelaxedInitialization::kMinNumInliers),
                      "--Mapper.init_min_tri_angle",
                      FormatRounded(RelaxedInitialization::kMinTriAngleDeg)});
  }
  return arguments;
}

std::string MapperInitialization::Describe() const {
  const std::string relaxed =
      "the initial pair's tests relaxed (forward motion accepted, from " +
      std::to_string(RelaxedInitialization::kMinNumInliers) + " inliers and " +
      FormatRounded(RelaxedInitialization::kMinTriAngleDeg) + " deg)";
  std::string pair_text;
  if (pair) {
    pair_text = "initial pair " + pair->name1 + " and " + pair->name2 +
                " from the odometry (" + FormatRounded(pair->baseline_m) +
                " m, " + FormatRounded(pair->heading_change_deg) + " deg, " +
                std::to_string(pair->num_inliers) + " inliers)";
  }
  switch (kind) {
    case Kind::kColmapSearch:
      return "COLMAP's initial pair search";
    case Kind::kOdometryPair:
      return pair_text;
    case Kind::kRelaxedSearch:
      return "COLMAP's initial pair search, " + relaxed;
    case Kind::kRelaxedOdometryPair:
      return pair_text + ", " + relaxed;
    case Kind::kNeighbourWindow:
      return "the chunk with its neighbours' images, " + relaxed;
  }
  return "";
}

std::string ToString(MapperInitialization::Kind kind) {
  switch (kind) {
    case MapperInitialization::Kind::kColmapSearch:
      return "colmap_search";
    case MapperInitialization::Kind::kOdometryPair:
      return "odometry_pair";
    case MapperInitialization::Kind::kRelaxedSearch:
      return "relaxed_search";
    case MapperInitialization::Kind::kRelaxedOdometryPair:
      return "relaxed_odometry_pair";
    case MapperInitialization::Kind::kNeighbourWindow:
      return "neighbour_window";
  }
  return "";
}

std::vector<MapperInitialization> InitializationLadder(
    const std::vector<InitialPairCandidate>& default_candidates,
    const std::vector<InitialPairCandidate>& relaxed_candidates,
    bool with_neighbour_window) {
  using Kind = MapperInitialization::Kind;
  std::vector<MapperInitialization> ladder;
  const size_t num_pairs =
      std::min<size_t>(default_candidates.size(), kMaxOdometryPairs);
  for (size_t i = 0; i < num_pairs; ++i) {
    ladder.push_back({Kind::kOdometryPair, default_candidates[i]});
  }
  ladder.push_back({Kind::kRelaxedSearch, std::nullopt});
  // The relaxed pair when it differs from every pair tried with the
  // default tests (those were tried already; relaxing the angle and
  // inliers is what COLMAP does for a given pair anyway).
  for (const InitialPairCandidate& candidate : relaxed_candidates) {
    const bool tried = std::any_of(
        ladder.begin(), ladder.end(), [&](const MapperInitialization& rung) {
          return rung.pair && rung.pair->image_id1 == candidate.image_id1 &&
                 rung.pair->image_id2 == candidate.image_id2;
        });
    if (!tried) {
      ladder.push_back({Kind::kRelaxedOdometryPair, candidate});
      break;
    }
  }
  if (with_neighbour_window) {
    ladder.push_back({Kind::kNeighbourWindow, std::nullopt});
  }
  return ladder;
}

std::string MapperFailureCause(const std::string& log_path) {
  std::ifstream log(log_path);
  if (!log) return "";
  std::string line;
  std::string last;
  std::string check_failed;
  bool no_initial_pair = false;
  bool initialization_failed = false;
  bool pair_missing = false;
  while (std::getline(log, line)) {
    const std::string trimmed(TrimBlanks(line));
    if (trimmed.empty()) continue;
    last = trimmed;
    if (trimmed.find("No good initial image pair found") != std::string::npos) {
      no_initial_pair = true;
    } else if (trimmed.find("Initialization failed") != std::string::npos) {
      initialization_failed = true;
    } else if (trimmed.find("do not exist") != std::string::npos &&
               trimmed.find("Initial image pair") != std::string::npos) {
      pair_missing = true;
    } else if (trimmed.find("Check failed") != std::string::npos &&
               check_failed.empty()) {
      check_failed = trimmed;
    }
  }
  if (!check_failed.empty()) return "COLMAP failed a CHECK: " + check_failed;
  if (no_initial_pair) {
    return "no initial image pair passed COLMAP's tests (\"No good initial "
           "image pair found\")";
  }
  if (initialization_failed) {
    return "the initial pair failed COLMAP's tests (\"Initialization "
           "failed\")";
  }
  if (pair_missing) return "the initial pair is not among the mapped images";
  return last.empty() ? "COLMAP's log is empty"
                      : "no model; the log ends \"" + last + "\"";
}

}  // namespace odomcal
