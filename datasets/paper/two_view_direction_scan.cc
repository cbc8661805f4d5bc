#include "odomcal/datasets/paper/two_view_direction_scan.h"

#include <Eigen/Eigenvalues>
#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

namespace odomcal {
namespace {

// Cells less likely than this relative to the core add nothing.
constexpr double kMinCellMass = 1e-6;
// The core: directions within this Mahalanobis distance of the estimate.
constexpr double kCoreSigmas = 3.0;
constexpr int kMaxProfileIterations = 50;

// Sampson error of one correspondence for p_i = R p_j + t, E = [t]x R, times
// the focal length (pixels):
//   f x_i^T E x_j / sqrt((E x_j)_1^2 + (E x_j)_2^2 + (E^T x_i)_1^2 +
//   (E^T x_i)_2^2).
struct SampsonResidual {
  SampsonResidual(const Eigen::Vector2d& u_i,
                  const Eigen::Vector2d& u_j,
                  const Eigen::Vector3d& translation,
                  double focal)
      : u_i(u_i), u_j(u_j), translation(translation), focal(focal) {}

  template <typename T>
  bool operator()(const T* rotation_xyzw, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> rotation(rotation_xyzw);
    const Eigen::Matrix<T, 3, 1> x_i(T(u_i.x()), T(u_i.y()), T(1.0));
    const Eigen::Matrix<T, 3, 1> x_j(T(u_j.x()), T(u_j.y()), T(1.0));
    const Eigen::Matrix<T, 3, 1> t = translation.cast<T>();
    const Eigen::Matrix<T, 3, 1> e_x_j = t.cross(rotation * x_j);
    const Eigen::Matrix<T, 3, 1> e_t_x_i =
        -(rotation.conjugate() * t.cross(x_i));
    const T denominator = e_x_j(0) * e_x_j(0) + e_x_j(1) * e_x_j(1) +
                          e_t_x_i(0) * e_t_x_i(0) + e_t_x_i(1) * e_t_x_i(1);
    // The floor keeps a correspondence on the epipole finite.
    residual[0] =
        T(focal) * x_i.dot(e_x_j) / ceres::sqrt(denominator + T(1e-30));
    return true;
  }

  Eigen::Vector2d u_i, u_j;
  Eigen::Vector3d translation;
  double focal;
};

// min over R of the Sampson cost (1/2 sum of squares) with t held, from
// *rotation; *rotation becomes the minimiser.
double SampsonProfile(const std::vector<Eigen::Vector2d>& u_i,
                      const std::vector<Eigen::Vector2d>& u_j,
                      const Eigen::Vector3d& translation,
                      double focal,
                      Eigen::Quaterniond* rotation) {
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::EigenQuaternionManifold manifold;
  Eigen::Quaterniond q = *rotation;
  for (size_t k = 0; k < u_i.size(); ++k) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<SampsonResidual, 1, 4>(
            new SampsonResidual(u_i[k], u_j[k], translation, focal)),
        nullptr,
        q.coeffs().data());
  }
  problem.SetManifold(q.coeffs().data(), &manifold);
  ceres::Solver::Options options;
  options.max_num_iterations = kMaxProfileIterations;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  *rotation = q.normalized();
  return summary.final_cost;
}

}  // namespace

DirectionScan ScanTranslationDirection(
    const std::vector<Eigen::Vector2d>& normalized_in_cam_i,
    const std::vector<Eigen::Vector2d>& normalized_in_cam_j,
    const Rigid3d& cam_i_from_cam_j,
    const MotionCovariance& covariance,
    double focal_length_px,
    double pixel_sigma,
    int num_points) {
  DirectionScan scan;
  scan.covariance = covariance;
  if (num_points <= 0 || !(pixel_sigma > 0.0)) return scan;
  const Eigen::Vector3d& direction = cam_i_from_cam_j.translation;
  // Rank 2 (the unit length carries none): eigenvalues 1 and 2 span the
  // tangent plane.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(
      covariance.bottomRightCorner<3, 3>());
  const double sigma_1 = std::sqrt(std::max(eigen.eigenvalues()(2), 0.0));
  const double sigma_2 = std::sqrt(std::max(eigen.eigenvalues()(1), 0.0));
  const double cell_area = 2.0 * M_PI / num_points;
  if (!(sigma_2 > 0.0) ||
      sigma_1 < kDirectionScanMinSpreadOfSpacing * std::sqrt(cell_area)) {
    return scan;
  }
  scan.scanned = true;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  for (int d = 1; d < 3; ++d) {
    information += eigen.eigenvectors().col(d) *
                   eigen.eigenvectors().col(d).transpose() /
                   eigen.eigenvalues()(d);
  }
  const double variance = pixel_sigma * pixel_sigma;
  Eigen::Quaterniond best_rotation = cam_i_from_cam_j.rotation;
  const double best_cost = SampsonProfile(normalized_in_cam_i,
                                          normalized_in_cam_j,
                                          direction,
                                          focal_length_px,
                                          &best_rotation);
  const double mass_per_cell = cell_area / (2.0 * M_PI * sigma_1 * sigma_2);
  const Eigen::Matrix3d across =
      Eigen::Matrix3d::Identity() - direction * direction.transpose();
  MotionCovariance spread = MotionCovariance::Zero();
  double total_mass = 1.0;
  // 2 num_points Fibonacci directions over the sphere, the hemisphere's kept.
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < 2 * num_points; ++k) {
    const double z = 1.0 - (k + 0.5) / num_points;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Eigen::Vector3d cell(
        r * std::cos(golden_angle * k), r * std::sin(golden_angle * k), z);
    if (!(cell.dot(direction) > 0.0)) continue;
    const Eigen::Vector3d offset = across * cell;
    if (offset.dot(information * offset) < kCoreSigmas * kCoreSigmas) continue;
    Eigen::Quaterniond rotation = best_rotation;
    const double cost = SampsonProfile(normalized_in_cam_i,
                                       normalized_in_cam_j,
                                       cell,
                                       focal_length_px,
                                       &rotation);
    const double delta_chi2 = 2.0 * (cost - best_cost) / variance;
    const double mass = mass_per_cell * std::exp(-0.5 * delta_chi2);
    if (!(mass > kMinCellMass)) continue;
    Eigen::Matrix<double, 6, 1> d;
    d.head<3>() = LogRotation(rotation * best_rotation.conjugate());
    d.tail<3>() = offset;
    spread += mass * d * d.transpose();
    total_mass += mass;
    ++scan.num_cells_used;
  }
  scan.covariance += spread / total_mass;
  return scan;
}

}  // namespace odomcal
