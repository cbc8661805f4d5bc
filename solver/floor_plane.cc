#include "odomcal/solver/floor_plane.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/chi_square.h"
#include "odomcal/solver/format_number.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <stdexcept>
#include <utility>

namespace odomcal {
namespace {

constexpr int kMaxRefitIterations = 10;
constexpr int kMaxJackknifeBlocks = 10;
// The floor's parts for its tilt error (TiltPartJackknife): distance bands
// times stretches of the drive; fewer than kMinSpreadParts parts of
// kMinSpreadPartPoints points leave the jackknife unmeasured, a band with
// fewer the bands' spread.
constexpr int kSpreadBands = 3;
constexpr int kSpreadBlocks = 4;
constexpr int kMinSpreadPartPoints = 12;
constexpr int kMinSpreadParts = 4;

struct Candidate {
  Eigen::Vector3d xyz;
  double weight = 1.0;    // 1 / sigma^2
  int camera = 0;         // the camera that saw it (nearest observer)
  double distance = 0.0;  // from that camera (metres)
};

// The candidates: below the lowest camera, near a camera centre. Camera
// centres are binned in a grid of max_path_distance_m cells so that each
// point is compared with the cameras of its 3 x 3 cells only.
std::vector<Candidate> SelectCandidates(
    const std::vector<FloorCandidatePoint>& points,
    const std::vector<Eigen::Vector3d>& centres,
    const FloorPlaneOptions& options) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& c : centres) lowest = std::min(lowest, c.z());
  const double cell = options.max_path_distance_m;
  const auto key = [cell](double x, double y) {
    return std::make_pair(static_cast<int64_t>(std::floor(x / cell)),
                          static_cast<int64_t>(std::floor(y / cell)));
  };
  std::map<std::pair<int64_t, int64_t>, std::vector<int>> grid;
  for (size_t i = 0; i < centres.size(); ++i) {
    grid[key(centres[i].x(), centres[i].y())].push_back(static_cast<int>(i));
  }
  const double max_distance2 = cell * cell;
  std::vector<Candidate> candidates;
  for (const FloorCandidatePoint& point : points) {
    if (!point.xyz.allFinite() || !(point.sigma_m > 0.0)) continue;
    if (point.xyz.z() > lowest - options.min_depth_below_cameras_m) continue;
    const auto [gx, gy] = key(point.xyz.x(), point.xyz.y());
    double best = max_distance2;
    int nearest = -1;
    for (int64_t dx = -1; dx <= 1; ++dx) {
      for (int64_t dy = -1; dy <= 1; ++dy) {
        const auto it = grid.find({gx + dx, gy + dy});
        if (it == grid.end()) continue;
        for (const int i : it->second) {
          const double d2 =
              (point.xyz.head<2>() - centres[i].head<2>()).squaredNorm();
          if (d2 <= best) {
            best = d2;
            nearest = i;
          }
        }
      }
    }
    if (nearest < 0) continue;
    // The point shares the errors of the camera that saw it.
    const int camera =
        point.camera >= 0 && point.camera < static_cast<int>(centres.size())
            ? point.camera
            : nearest;
    const double distance = point.distance_m > 0.0
                                ? point.distance_m
                                : (point.xyz - centres[camera]).norm();
    candidates.push_back(
        {point.xyz, 1.0 / (point.sigma_m * point.sigma_m), camera, distance});
  }
  return candidates;
}

// MSAC over planes through 3 candidates within max_tilt_deg of level.
// Returns the best plane's unit normal (up) and a point on it; false when
// no sample gave a level plane.
bool RansacLevelPlane(const std::vector<Candidate>& candidates,
                      const FloorPlaneOptions& options,
                      Eigen::Vector3d* normal,
                      Eigen::Vector3d* on_plane) {
  std::mt19937_64 random(options.ransac_seed);
  std::uniform_int_distribution<size_t> pick(0, candidates.size() - 1);
  const double min_up = std::cos(options.max_tilt_deg * kDegToRad);
  const double t2 =
      options.ransac_inlier_distance_m * options.ransac_inlier_distance_m;
  double best_score = std::numeric_limits<double>::infinity();
  for (int iteration = 0; iteration < options.ransac_iterations; ++iteration) {
    const size_t i = pick(random);
    const size_t j = pick(random);
    const size_t k = pick(random);
    if (i == j || j == k || i == k) continue;
    Eigen::Vector3d n = (candidates[j].xyz - candidates[i].xyz)
                            .cross(candidates[k].xyz - candidates[i].xyz);
    const double norm = n.norm();
    if (!(norm > 1e-12)) continue;
    n /= norm;
    if (n.z() < 0.0) n = -n;
    if (n.z() < min_up) continue;
    double score = 0.0;
    for (const Candidate& c : candidates) {
      const double r = n.dot(c.xyz - candidates[i].xyz);
      score += std::min(r * r, t2);
      if (score >= best_score) break;
    }
    if (score < best_score) {
      best_score = score;
      *normal = n;
      *on_plane = candidates[i].xyz;
    }
  }
  return std::isfinite(best_score);
}

// Weighted least squares z = c + a (x - x0) + b (y - y0) over `members`.
// Returns false when the normal equations are singular.
bool FitPlane(const std::vector<Candidate>& candidates,
              const std::vector<int>& members,
              const Eigen::Vector2d& reference,
              Eigen::Vector3d* parameters,
              Eigen::Matrix3d* normal_matrix) {
  Eigen::Matrix3d n = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const int m : members) {
    const Candidate& c = candidates[m];
    const Eigen::Vector3d row(
        c.xyz.x() - reference.x(), c.xyz.y() - reference.y(), 1.0);
    n += c.weight * row * row.transpose();
    rhs += c.weight * row * c.xyz.z();
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(n);
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) return false;
  *parameters = ldlt.solve(rhs);
  if (normal_matrix != nullptr) *normal_matrix = n;
  return parameters->allFinite();
}

double VerticalResidual(const Candidate& c,
                        const Eigen::Vector2d& reference,
                        const Eigen::Vector3d& p) {
  return c.xyz.z() - (p.z() + p.x() * (c.xyz.x() - reference.x()) +
                      p.y() * (c.xyz.y() - reference.y()));
}

Eigen::Vector3d PlaneNormal(const Eigen::Vector3d& p) {
  return Eigen::Vector3d(-p.x(), -p.y(), 1.0).normalized();
}

std::vector<int> AllOf(const std::vector<FloorCamera>& cameras) {
  std::vector<int> all(cameras.size());
  for (size_t i = 0; i < cameras.size(); ++i) all[i] = static_cast<int>(i);
  return all;
}

// The camera height and the roll/pitch correction from the plane `p` and
// the cameras `subset`, with their Jacobians with respect to p.
struct Derived {
  double height = 0.0;
  std::vector<double> heights;  // per camera of the subset
  Eigen::RowVector3d height_jacobian = Eigen::RowVector3d::Zero();
  Eigen::Vector2d phi = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, 3> phi_jacobian =
      Eigen::Matrix<double, 2, 3>::Zero();
};

Derived Derive(const Eigen::Vector3d& p,
               const Eigen::Vector2d& reference,
               const std::vector<Eigen::Vector3d>& centres,
               const std::vector<FloorCamera>& cameras,
               const std::vector<int>& subset,
               const Rigid3d& odom_from_cam) {
  Derived derived;
  // Perpendicular heights of the camera centres above the plane.
  const double norm = std::sqrt(1.0 + p.x() * p.x() + p.y() * p.y());
  double sum = 0.0;
  for (const int i : subset) {
    const Eigen::Vector2d d = centres[i].head<2>() - reference;
    const double h =
        (centres[i].z() - (p.z() + p.x() * d.x() + p.y() * d.y())) / norm;
    derived.heights.push_back(h);
    sum += h;
    derived.height_jacobian += Eigen::RowVector3d(-d.x(), -d.y(), -1.0) / norm;
  }
  const double n = static_cast<double>(subset.size());
  derived.height = sum / n;
  derived.height_jacobian /= n;
  // The floor's normal seen from the cameras, in the odometry frame by the
  // motion's extrinsic: up = mean_i(R_oc R_i^T) n.
  const Eigen::Matrix3d odom_from_cam_rotation =
      odom_from_cam.rotation.toRotationMatrix();
  Eigen::Matrix3d to_odom = Eigen::Matrix3d::Zero();
  for (const int i : subset) {
    to_odom +=
        odom_from_cam_rotation *
        cameras[i].origin_from_cam.rotation.toRotationMatrix().transpose();
  }
  to_odom /= n;
  const Eigen::Vector3d up = (to_odom * PlaneNormal(p)).normalized();
  // Exp(-phi) e_z = up: phi = angle * (up_y, -up_x) / |(up_x, up_y)|.
  const double horizontal = up.head<2>().norm();
  const double angle = std::atan2(horizontal, up.z());
  if (horizontal > 0.0) {
    derived.phi = Eigen::Vector2d(up.y(), -up.x()) * (angle / horizontal);
  }
  // d n = (-d a, -d b, 0) to first order about level; d phi = (d up_y,
  // -d up_x).
  Eigen::Matrix<double, 2, 3> swap;
  swap << 0.0, 1.0, 0.0, -1.0, 0.0, 0.0;
  Eigen::Matrix3d dn_dp = Eigen::Matrix3d::Zero();
  dn_dp(0, 0) = -1.0;
  dn_dp(1, 1) = -1.0;
  derived.phi_jacobian = swap * to_odom * dn_dp;
  return derived;
}

// The floor's tilt error from its parts: the delete-a-part jackknife of the
// plane's slope (a, b) and the roll/pitch correction, each refitted without
// each part, and the spread of the distance bands' corrections.
struct PartJackknife {
  int num_parts = 0;  // 0: not measured
  Eigen::Matrix2d slope_covariance = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d phi_covariance = Eigen::Matrix2d::Zero();
  // tau^2: the variance of the distance bands' roll/pitch corrections
  // (each band fitted alone) beyond their fits' (zero when not measured).
  double band_variance = 0.0;
};

// The Paule-Mandel estimate of tau^2: the variance that, added to each
// value's variance, makes their weighted scatter about their weighted mean
// its expectation, G - 1. Zero when the values' variances explain the
// scatter.
double RandomEffectsVariance(const std::vector<double>& values,
                             const std::vector<double>& variances) {
  const auto scatter = [&](double tau2) {
    double weight_sum = 0.0, weighted = 0.0;
    for (size_t g = 0; g < values.size(); ++g) {
      weight_sum += 1.0 / (variances[g] + tau2);
      weighted += values[g] / (variances[g] + tau2);
    }
    const double mean = weighted / weight_sum;
    double q = 0.0;
    for (size_t g = 0; g < values.size(); ++g) {
      q += (values[g] - mean) * (values[g] - mean) / (variances[g] + tau2);
    }
    return q;
  };
  const double expected = static_cast<double>(values.size()) - 1.0;
  if (values.size() < 2 || !(scatter(0.0) > expected)) return 0.0;
  // The scatter falls with tau^2; at the values' mean square it is below
  // its expectation.
  double high = 0.0;
  for (const double v : values) high += v * v;
  if (!(high > 0.0) || !std::isfinite(high)) return 0.0;
  double low = 0.0;
  while (scatter(high) > expected) high *= 2.0;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double mid = 0.5 * (low + high);
    (scatter(mid) > expected ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

// The parts: thirds of the inliers by their distance from the camera that
// saw them (near, middle, far: triangulation error and grazing views grow
// with it) times kSpreadBlocks stretches of the drive (by that camera).
// Parts with fewer than kMinSpreadPartPoints points stay in every refit.
PartJackknife TiltPartJackknife(const std::vector<Candidate>& candidates,
                                const std::vector<int>& members,
                                const Eigen::Vector2d& reference,
                                const std::vector<Eigen::Vector3d>& centres,
                                const std::vector<FloorCamera>& cameras,
                                const Rigid3d& odom_from_cam) {
  PartJackknife result;
  std::vector<double> distances;
  distances.reserve(members.size());
  for (const int m : members) distances.push_back(candidates[m].distance);
  std::sort(distances.begin(), distances.end());
  std::vector<double> bounds;
  bounds.reserve(kSpreadBands);
  for (int b = 1; b < kSpreadBands; ++b) {
    bounds.push_back(distances[distances.size() * static_cast<size_t>(b) /
                               static_cast<size_t>(kSpreadBands)]);
  }
  std::vector<int> part_of(candidates.size(), -1);
  std::vector<int> part_size(
      static_cast<size_t>(kSpreadBands) * static_cast<size_t>(kSpreadBlocks),
      0);
  for (const int m : members) {
    const int band = static_cast<int>(
        std::upper_bound(bounds.begin(), bounds.end(), candidates[m].distance) -
        bounds.begin());
    const int block =
        static_cast<int>(static_cast<int64_t>(candidates[m].camera) *
                         kSpreadBlocks / static_cast<int64_t>(cameras.size()));
    part_of[m] = band * kSpreadBlocks + block;
    ++part_size[part_of[m]];
  }
  const std::vector<int> all_cameras = AllOf(cameras);
  // Each band alone: its roll/pitch correction and the variances of its fit.
  std::vector<std::vector<double>> values(2), variances(2);
  for (int band = 0; band < kSpreadBands; ++band) {
    std::vector<int> in_band;
    for (const int m : members) {
      if (part_of[m] / kSpreadBlocks == band) in_band.push_back(m);
    }
    Eigen::Vector3d q;
    Eigen::Matrix3d normal_matrix;
    if (static_cast<int>(in_band.size()) < kMinSpreadPartPoints ||
        !FitPlane(candidates, in_band, reference, &q, &normal_matrix)) {
      continue;
    }
    double weighted_sum = 0.0;
    for (const int m : in_band) {
      const double r = VerticalResidual(candidates[m], reference, q);
      weighted_sum += candidates[m].weight * r * r;
    }
    const double variance_factor =
        weighted_sum / static_cast<double>(in_band.size() - 3);
    const Derived derived =
        Derive(q, reference, centres, cameras, all_cameras, odom_from_cam);
    const Eigen::Matrix2d covariance =
        derived.phi_jacobian * (variance_factor * normal_matrix.inverse()) *
        derived.phi_jacobian.transpose();
    if (!derived.phi.allFinite() || !covariance.allFinite()) continue;
    for (int axis = 0; axis < 2; ++axis) {
      values[axis].push_back(derived.phi(axis));
      variances[axis].push_back(covariance(axis, axis));
    }
  }
  if (static_cast<int>(values[0].size()) == kSpreadBands) {
    for (int axis = 0; axis < 2; ++axis) {
      result.band_variance =
          std::max(result.band_variance,
                   RandomEffectsVariance(values[axis], variances[axis]));
    }
  }
  std::vector<Eigen::Vector4d> estimates;  // a, b, phi_x, phi_y
  for (int part = 0; part < static_cast<int>(part_size.size()); ++part) {
    if (part_size[part] < kMinSpreadPartPoints) continue;
    std::vector<int> kept;
    for (const int m : members) {
      if (part_of[m] != part) kept.push_back(m);
    }
    Eigen::Vector3d q;
    if (!FitPlane(candidates, kept, reference, &q, nullptr)) continue;
    const Derived derived =
        Derive(q, reference, centres, cameras, all_cameras, odom_from_cam);
    if (!derived.phi.allFinite()) continue;
    estimates.emplace_back(q.x(), q.y(), derived.phi.x(), derived.phi.y());
  }
  if (static_cast<int>(estimates.size()) < kMinSpreadParts) return result;
  Eigen::Vector4d mean = Eigen::Vector4d::Zero();
  for (const Eigen::Vector4d& v : estimates) mean += v;
  const double g = static_cast<double>(estimates.size());
  mean /= g;
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
  for (const Eigen::Vector4d& v : estimates) {
    covariance += (v - mean) * (v - mean).transpose();
  }
  covariance *= (g - 1.0) / g;
  result.num_parts = static_cast<int>(estimates.size());
  result.slope_covariance = covariance.topLeftCorner<2, 2>();
  result.phi_covariance = covariance.bottomRightCorner<2, 2>();
  return result;
}

}  // namespace

std::string ToString(FloorPlaneUse use) {
  switch (use) {
    case FloorPlaneUse::kOff:
      return "off";
    case FloorPlaneUse::kCheck:
      return "check";
    case FloorPlaneUse::kEstimateZ:
      return "estimate";
  }
  return "estimate";
}

FloorPlaneUse FloorPlaneUseFromString(const std::string& name) {
  if (name == "off") return FloorPlaneUse::kOff;
  if (name == "check") return FloorPlaneUse::kCheck;
  if (name == "estimate") return FloorPlaneUse::kEstimateZ;
  throw std::invalid_argument(
      "floor_plane must be estimate, check or off, got '" + name + "'");
}

std::string ToString(FloorPlaneStatus status) {
  switch (status) {
    case FloorPlaneStatus::kNotRun:
      return "not_run";
    case FloorPlaneStatus::kFitted:
      return "fitted";
    case FloorPlaneStatus::kTooFewPoints:
      return "too_few_points";
    case FloorPlaneStatus::kNotLevel:
      return "not_level";
    case FloorPlaneStatus::kNotDistinct:
      return "not_distinct";
    case FloorPlaneStatus::kSloped:
      return "sloped";
    case FloorPlaneStatus::kDisagreesWithMotion:
      return "disagrees_with_motion";
    case FloorPlaneStatus::kTiltUncertain:
      return "tilt_uncertain";
  }
  return "not_run";
}

void FloorPlaneOptions::Check() const {
  const auto positive = [](double value, const char* name) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(
          std::string(name) + " must be positive, got " + FormatNumber(value));
    }
  };
  if (!std::isfinite(odometry_height_m)) {
    throw std::invalid_argument("odometry_height_m must be finite, got " +
                                FormatNumber(odometry_height_m));
  }
  positive(max_path_distance_m, "floor_max_path_distance_m");
  if (!(min_depth_below_cameras_m >= 0.0) ||
      !std::isfinite(min_depth_below_cameras_m)) {
    throw std::invalid_argument(
        "floor_min_depth_below_cameras_m must be >= 0, got " +
        FormatNumber(min_depth_below_cameras_m));
  }
  if (!(max_tilt_deg > 0.0 && max_tilt_deg < 90.0)) {
    throw std::invalid_argument("floor_max_tilt_deg must be in (0, 90), got " +
                                FormatNumber(max_tilt_deg));
  }
  positive(ransac_inlier_distance_m, "floor_inlier_distance_m");
  if (!(common_orientation_sigma_deg >= 0.0) ||
      !std::isfinite(common_orientation_sigma_deg)) {
    throw std::invalid_argument(
        "floor common_orientation_sigma_deg must be >= 0, got " +
        FormatNumber(common_orientation_sigma_deg));
  }
  if (ransac_iterations < 1) {
    throw std::invalid_argument("floor_ransac_iterations must be >= 1, got " +
                                std::to_string(ransac_iterations));
  }
  if (min_inliers < 3) {
    throw std::invalid_argument("floor_min_inliers must be >= 3, got " +
                                std::to_string(min_inliers));
  }
  if (!(max_slope_deg > 0.0 && max_slope_deg < max_tilt_deg)) {
    throw std::invalid_argument("floor_max_slope_deg must be in (0, " +
                                FormatNumber(max_tilt_deg) + "), got " +
                                FormatNumber(max_slope_deg));
  }
  if (!(max_beside_ratio > 0.0) || !std::isfinite(max_beside_ratio)) {
    throw std::invalid_argument(
        "floor_max_beside_ratio must be positive, got " +
        FormatNumber(max_beside_ratio));
  }
  if (!(disagreement_alpha > 0.0 && disagreement_alpha < 1.0)) {
    throw std::invalid_argument(
        "floor_disagreement_alpha must be in (0, 1), got " +
        FormatNumber(disagreement_alpha));
  }
}

FloorPlane FitFloorPlane(const std::vector<FloorCandidatePoint>& points,
                         const std::vector<FloorCamera>& cameras,
                         const Rigid3d& odom_from_cam,
                         const Eigen::Matrix2d& roll_pitch_covariance,
                         const std::vector<double>& metric_scales,
                         const FloorPlaneOptions& options) {
  options.Check();
  FloorPlane floor;
  floor.odometry_height_m = options.odometry_height_m;
  if (cameras.empty()) {
    floor.reason = "no camera in the metric model";
    return floor;
  }
  std::vector<Eigen::Vector3d> centres;
  centres.reserve(cameras.size());
  for (const FloorCamera& camera : cameras) {
    centres.push_back(camera.origin_from_cam.translation);
  }
  const std::vector<Candidate> candidates =
      SelectCandidates(points, centres, options);
  floor.num_candidates = static_cast<int>(candidates.size());
  const std::string where = " below the cameras within " +
                            FormatNumber(options.max_path_distance_m) +
                            " m of the path";
  if (floor.num_candidates < options.min_inliers) {
    floor.status = FloorPlaneStatus::kTooFewPoints;
    floor.reason =
        "the floor is not seen: " + std::to_string(floor.num_candidates) +
        " points" + where + " (at least " +
        std::to_string(options.min_inliers) + " needed)";
    return floor;
  }
  Eigen::Vector3d ransac_normal, on_plane;
  if (!RansacLevelPlane(candidates, options, &ransac_normal, &on_plane)) {
    floor.status = FloorPlaneStatus::kNotLevel;
    floor.reason = "no plane within " + FormatNumber(options.max_tilt_deg) +
                   " deg of level among the " +
                   std::to_string(floor.num_candidates) + " points" + where;
    return floor;
  }

  // Refit on the inliers: the RANSAC gate first, then 3 a-posteriori sigma
  // (within the gate) until the set settles; the plane, its normal matrix
  // and variance factor are always those of `members`.
  std::vector<int> members;
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (std::abs(ransac_normal.dot(candidates[i].xyz - on_plane)) <=
        options.ransac_inlier_distance_m) {
      members.push_back(static_cast<int>(i));
    }
  }
  Eigen::Vector2d reference = Eigen::Vector2d::Zero();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
  double variance_factor = 1.0;
  for (int iteration = 0; iteration < kMaxRefitIterations; ++iteration) {
    if (static_cast<int>(members.size()) < options.min_inliers) break;
    double weight_sum = 0.0;
    reference.setZero();
    for (const int m : members) {
      reference += candidates[m].weight * candidates[m].xyz.head<2>();
      weight_sum += candidates[m].weight;
    }
    reference /= weight_sum;
    if (!FitPlane(candidates, members, reference, &p, &normal_matrix)) {
      members.clear();
      break;
    }
    double weighted_sum = 0.0;
    for (const int m : members) {
      const double r = VerticalResidual(candidates[m], reference, p);
      weighted_sum += candidates[m].weight * r * r;
    }
    variance_factor = weighted_sum / static_cast<double>(std::max<size_t>(
                                         members.size() - 3, 1));
    std::vector<int> next;
    for (size_t i = 0; i < candidates.size(); ++i) {
      const double r = VerticalResidual(candidates[i], reference, p);
      if (std::abs(r) <= options.ransac_inlier_distance_m &&
          r * r * candidates[i].weight <= 9.0 * variance_factor) {
        next.push_back(static_cast<int>(i));
      }
    }
    // The last iteration keeps the set it fitted.
    if (next == members || iteration + 1 == kMaxRefitIterations) break;
    members = std::move(next);
  }
  floor.num_inliers = static_cast<int>(members.size());
  if (floor.num_inliers < options.min_inliers) {
    floor.status = FloorPlaneStatus::kTooFewPoints;
    floor.reason = "the floor plane has " + std::to_string(floor.num_inliers) +
                   " points of the " + std::to_string(floor.num_candidates) +
                   where + " (at least " + std::to_string(options.min_inliers) +
                   " needed)";
    return floor;
  }
  double rms = 0.0;
  for (const int m : members) {
    const double r = VerticalResidual(candidates[m], reference, p);
    rms += r * r;
  }
  floor.inlier_rms_m = std::sqrt(rms / static_cast<double>(members.size()));
  for (const Candidate& c : candidates) {
    const double r = std::abs(VerticalResidual(c, reference, p));
    if (r > options.ransac_inlier_distance_m &&
        r <= 2.0 * options.ransac_inlier_distance_m) {
      ++floor.num_beside;
    }
  }
  if (floor.num_beside > options.max_beside_ratio * floor.num_inliers) {
    floor.status = FloorPlaneStatus::kNotDistinct;
    floor.reason = "the floor is not seen: no plane stands out, " +
                   std::to_string(floor.num_beside) + " points lie beside (" +
                   FormatNumber(options.ransac_inlier_distance_m) + " to " +
                   FormatNumber(2.0 * options.ransac_inlier_distance_m) +
                   " m from) the best level plane and " +
                   std::to_string(floor.num_inliers) + " on it";
    return floor;
  }
  floor.reference_xy = reference;
  floor.parameters = p;

  // What the floor gives, from the plane and the cameras; the same on
  // every subset of the jackknife.
  const Derived all =
      Derive(p, reference, centres, cameras, AllOf(cameras), odom_from_cam);
  // Covariances from the fit alone (points independent).
  const Eigen::Matrix3d fit_covariance =
      variance_factor * normal_matrix.inverse();
  Eigen::Matrix3d covariance = fit_covariance;
  double height_variance = (all.height_jacobian * fit_covariance *
                            all.height_jacobian.transpose())(0);
  Eigen::Matrix2d phi_covariance =
      all.phi_jacobian * fit_covariance * all.phi_jacobian.transpose();
  // The delete-a-block jackknife over blocks of consecutive cameras (each
  // point in its observing camera's block) takes in the errors the points and
  // cameras share along the drive; each quantity takes the larger.
  const int num_blocks =
      std::min<int>(kMaxJackknifeBlocks, static_cast<int>(cameras.size()) / 2);
  if (num_blocks >= 4) {
    const auto block_of_camera = [&](int camera) {
      return static_cast<int>(static_cast<int64_t>(camera) * num_blocks /
                              static_cast<int64_t>(cameras.size()));
    };
    std::vector<Eigen::Matrix<double, 6, 1>> estimates;
    for (int b = 0; b < num_blocks; ++b) {
      std::vector<int> kept_points, kept_cameras;
      for (const int m : members) {
        if (block_of_camera(candidates[m].camera) != b)
          kept_points.push_back(m);
      }
      for (int i = 0; i < static_cast<int>(cameras.size()); ++i) {
        if (block_of_camera(i) != b) kept_cameras.push_back(i);
      }
      Eigen::Vector3d q;
      if (static_cast<int>(kept_points.size()) < options.min_inliers ||
          kept_cameras.empty() ||
          !FitPlane(candidates, kept_points, reference, &q, nullptr)) {
        continue;
      }
      const Derived part =
          Derive(q, reference, centres, cameras, kept_cameras, odom_from_cam);
      Eigen::Matrix<double, 6, 1> v;
      v << q, part.height, part.phi;
      estimates.push_back(v);
    }
    if (estimates.size() >= 4) {
      Eigen::Matrix<double, 6, 1> mean = Eigen::Matrix<double, 6, 1>::Zero();
      for (const auto& v : estimates) mean += v;
      mean /= static_cast<double>(estimates.size());
      Eigen::Matrix<double, 6, 6> jackknife =
          Eigen::Matrix<double, 6, 6>::Zero();
      for (const auto& v : estimates) {
        jackknife += (v - mean) * (v - mean).transpose();
      }
      const double g = static_cast<double>(estimates.size());
      jackknife *= (g - 1.0) / g;
      if (jackknife.topLeftCorner<3, 3>().trace() > covariance.trace()) {
        covariance = jackknife.topLeftCorner<3, 3>();
      }
      height_variance = std::max(height_variance, jackknife(3, 3));
      if (jackknife.bottomRightCorner<2, 2>().trace() >
          phi_covariance.trace()) {
        phi_covariance = jackknife.bottomRightCorner<2, 2>();
      }
    }
  }
  // The floor's own tilt error from parts near and far along the drive:
  // the tilt's and the roll/pitch correction's covariances take the larger
  // (by trace) of theirs and the part jackknife's, plus the bands' spread.
  const PartJackknife parts = TiltPartJackknife(
      candidates, members, reference, centres, cameras, odom_from_cam);
  floor.tilt_parts = parts.num_parts;
  Eigen::Matrix2d slope_covariance = covariance.topLeftCorner<2, 2>();
  if (parts.slope_covariance.trace() > slope_covariance.trace()) {
    slope_covariance = parts.slope_covariance;
  }
  if (parts.phi_covariance.trace() > phi_covariance.trace()) {
    phi_covariance = parts.phi_covariance;
  }
  // Where the bands near and far disagree beyond their fits (a model that
  // bends, grazing views), tau^2 is part of the whole floor's tilt error in
  // any direction (shared by the bands, not averaged away).
  slope_covariance += parts.band_variance * Eigen::Matrix2d::Identity();
  phi_covariance += parts.band_variance * Eigen::Matrix2d::Identity();
  const double common_rad = options.common_orientation_sigma_deg * kDegToRad;
  phi_covariance += common_rad * common_rad * Eigen::Matrix2d::Identity();
  floor.tilt_band_sigma_rad = std::sqrt(parts.band_variance);
  floor.tilt_parts_sigma_rad = std::sqrt(std::max(
      0.0,
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(parts.phi_covariance)
          .eigenvalues()
          .maxCoeff()));
  floor.parameter_covariance = covariance;
  floor.normal = PlaneNormal(p);
  floor.offset_m =
      floor.normal.dot(Eigen::Vector3d(reference.x(), reference.y(), p.z()));
  floor.tilt_deg =
      std::acos(std::clamp(floor.normal.z(), -1.0, 1.0)) * kRadToDeg;

  floor.disagreement_threshold =
      ChiSquareCriticalValue(options.disagreement_alpha, 2.0);
  const Eigen::LDLT<Eigen::Matrix2d> slope_ldlt(slope_covariance);
  floor.tilt_chi_square =
      slope_ldlt.info() == Eigen::Success && slope_ldlt.rcond() > 1e-15
          ? p.head<2>().dot(slope_ldlt.solve(p.head<2>()))
          : std::numeric_limits<double>::infinity();

  const double n_cameras = static_cast<double>(cameras.size());
  floor.camera_height_m = all.height;
  floor.camera_height_stddev_m = std::sqrt(std::max(0.0, height_variance));
  double spread = 0.0;
  for (const double h : all.heights) {
    spread += (h - floor.camera_height_m) * (h - floor.camera_height_m);
  }
  floor.camera_height_spread_m = std::sqrt(spread / n_cameras);
  floor.height_per_scale.assign(metric_scales.size(), 0.0);
  for (size_t i = 0; i < cameras.size(); ++i) {
    const int segment = cameras[i].segment;
    if (segment < 0 || segment >= static_cast<int>(metric_scales.size()) ||
        !(metric_scales[segment] > 0.0)) {
      continue;
    }
    floor.height_per_scale[segment] +=
        all.heights[i] / metric_scales[segment] / n_cameras;
  }
  const Eigen::Vector2d phi = all.phi;
  const double angle = phi.norm();
  floor.roll_pitch_correction_rad = phi;
  floor.roll_pitch_correction_covariance = phi_covariance;
  const Eigen::Vector3d floor_rpy =
      RollPitchYaw(ExpRotation(Eigen::Vector3d(phi.x(), phi.y(), 0.0)) *
                   odom_from_cam.rotation);
  floor.floor_roll_deg = floor_rpy.x() * kRadToDeg;
  floor.floor_pitch_deg = floor_rpy.y() * kRadToDeg;
  const Eigen::Matrix2d total =
      floor.roll_pitch_correction_covariance + roll_pitch_covariance;
  const Eigen::LDLT<Eigen::Matrix2d> total_ldlt(total);
  floor.disagreement_chi_square =
      total_ldlt.info() == Eigen::Success && total_ldlt.rcond() > 1e-15
          ? phi.dot(total_ldlt.solve(phi))
          : std::numeric_limits<double>::infinity();
  if (floor.tilt_deg > options.max_slope_deg &&
      !(floor.tilt_chi_square <= floor.disagreement_threshold)) {
    floor.status = FloorPlaneStatus::kSloped;
    floor.reason = "the floor is tilted " + FormatRounded(floor.tilt_deg, 3) +
                   " deg against the plane the robot drives in (more than " +
                   FormatNumber(options.max_slope_deg) + " deg, chi-square " +
                   FormatRounded(floor.tilt_chi_square, 3) + " > " +
                   FormatRounded(floor.disagreement_threshold, 3) +
                   "): a sloped floor or a model that is not flat";
    return floor;
  }
  if (!(floor.disagreement_chi_square <= floor.disagreement_threshold)) {
    floor.status = FloorPlaneStatus::kDisagreesWithMotion;
    floor.reason =
        "the floor's roll/pitch differ from the motion's by " +
        FormatRounded(angle * kRadToDeg, 3) + " deg (chi-square " +
        FormatRounded(floor.disagreement_chi_square, 3) + " > " +
        FormatRounded(floor.disagreement_threshold, 3) +
        "): a sloped floor, a model that is not flat, or a wrong roll/pitch";
    return floor;
  }
  // Neither check may pass a max_slope_deg slope or contradiction: the
  // floor's tilt (largest standard deviation of its own covariances) must be
  // within max_slope_deg / sqrt(threshold).
  const double max_sigma = options.max_slope_deg * kDegToRad /
                           std::sqrt(floor.disagreement_threshold);
  const double tilt_sigma = std::sqrt(
      std::max(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(slope_covariance)
                   .eigenvalues()
                   .maxCoeff(),
               Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(
                   floor.roll_pitch_correction_covariance)
                   .eigenvalues()
                   .maxCoeff()));
  if (!(tilt_sigma <= max_sigma)) {
    floor.status = FloorPlaneStatus::kTiltUncertain;
    floor.reason =
        "the floor's tilt is known only to " +
        FormatRounded(tilt_sigma * kRadToDeg, 3) + " deg (1 sigma, of which " +
        FormatRounded(floor.tilt_band_sigma_rad * kRadToDeg, 3) +
        " deg from its points near and far disagreeing): a " +
        FormatNumber(options.max_slope_deg) +
        " deg slope or roll/pitch error would pass unseen (at most " +
        FormatRounded(max_sigma * kRadToDeg, 3) + " deg)";
    return floor;
  }
  floor.status = FloorPlaneStatus::kFitted;
  return floor;
}

}  // namespace odomcal
