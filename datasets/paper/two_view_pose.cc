// The 8-point algorithm runs on normalised coordinates, so the fundamental
// matrix OpenCV returns is the essential matrix of the pair (up to scale and
// with unequal singular values, which recoverPose's SVD-based decomposition
// tolerates). recoverPose returns cam_j_from_cam_i with a unit translation;
// it is inverted to cam_i_from_cam_j, the convention of MotionPair. Points
// are triangulated linearly (DLT) with that pose and, with the pose, refined
// by a bundle adjustment whose reprojection residuals are in pixels. The
// pose covariance is the inverse of the Schur complement of the points in
// J^T J (points marginalised), scaled by sigma_px^2, and mapped from Ceres'
// tangent spaces to MotionPair's rotation-vector / 3D-translation layout.

#include "odomcal/datasets/paper/two_view_pose.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <ceres/ceres.h>
#include <ceres/sphere_manifold.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

namespace odomcal {
namespace {

constexpr int kMinNumPoints = 8;
// Points further than this (in baselines) count as at infinity in
// recoverPose's cheirality test; ours are never, so it is set out of reach.
constexpr double kRecoverPoseDistance = 1e9;
// H_pose is treated as singular below this ratio of its eigenvalues.
constexpr double kMinInformationRatio = 1e-14;

// Reprojection residual in view i, where the point is expressed:
//   r = f * (p.xy / p.z - u_i)
struct ViewIResidual {
  ViewIResidual(const Eigen::Vector2d& observed, double focal)
      : observed(observed), focal(focal) {}
  template <typename T>
  bool operator()(const T* point, T* residual) const {
    residual[0] = T(focal) * (point[0] / point[2] - T(observed.x()));
    residual[1] = T(focal) * (point[1] / point[2] - T(observed.y()));
    return true;
  }
  Eigen::Vector2d observed;
  double focal;
};

// Reprojection residual in view j, with (R, t) = cam_i_from_cam_j:
//   y = R^T (p - t),  r = f * (y.xy / y.z - u_j)
struct ViewJResidual {
  ViewJResidual(const Eigen::Vector2d& observed, double focal)
      : observed(observed), focal(focal) {}
  template <typename T>
  bool operator()(const T* rotation,
                  const T* translation,
                  const T* point,
                  T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(translation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p(point);
    const Eigen::Matrix<T, 3, 1> y = q.conjugate() * (p - t);
    residual[0] = T(focal) * (y.x() / y.z() - T(observed.x()));
    residual[1] = T(focal) * (y.y() / y.z() - T(observed.y()));
    return true;
  }
  Eigen::Vector2d observed;
  double focal;
};

// Linear (DLT) triangulation with P_i = [I | 0] and P_j = cam_j_from_cam_i.
Eigen::Vector3d Triangulate(const Eigen::Vector2d& u_i,
                            const Eigen::Vector2d& u_j,
                            const Rigid3d& cam_j_from_cam_i) {
  Eigen::Matrix<double, 3, 4> p_i = Eigen::Matrix<double, 3, 4>::Zero();
  p_i.leftCols<3>().setIdentity();
  Eigen::Matrix<double, 3, 4> p_j;
  p_j.leftCols<3>() = cam_j_from_cam_i.rotation.toRotationMatrix();
  p_j.col(3) = cam_j_from_cam_i.translation;
  Eigen::Matrix4d a;
  a.row(0) = u_i.x() * p_i.row(2) - p_i.row(0);
  a.row(1) = u_i.y() * p_i.row(2) - p_i.row(1);
  a.row(2) = u_j.x() * p_j.row(2) - p_j.row(0);
  a.row(3) = u_j.y() * p_j.row(2) - p_j.row(1);
  const Eigen::JacobiSVD<Eigen::Matrix4d> svd(a, Eigen::ComputeFullV);
  const Eigen::Vector4d x = svd.matrixV().col(3);
  return x.head<3>() / x(3);
}

double ReprojectionRms(const std::vector<Eigen::Vector2d>& u_i,
                       const std::vector<Eigen::Vector2d>& u_j,
                       const Rigid3d& cam_i_from_cam_j,
                       const std::vector<Eigen::Vector3d>& points,
                       double focal) {
  const Rigid3d cam_j_from_cam_i = Inverse(cam_i_from_cam_j);
  double sum = 0.0;
  for (size_t k = 0; k < points.size(); ++k) {
    const Eigen::Vector3d y = cam_j_from_cam_i * points[k];
    sum += (points[k].head<2>() / points[k].z() - u_i[k]).squaredNorm() +
           (y.head<2>() / y.z() - u_j[k]).squaredNorm();
  }
  return focal * std::sqrt(sum / (2.0 * static_cast<double>(points.size())));
}

}  // namespace

void TwoViewOptions::Check() const {
  if (!(focal_length_px > 0.0) || !std::isfinite(focal_length_px)) {
    throw std::invalid_argument("focal_length_px must be positive, got " +
                                std::to_string(focal_length_px));
  }
  if (!(pixel_sigma >= 0.0) || !std::isfinite(pixel_sigma)) {
    throw std::invalid_argument("pixel_sigma must be >= 0, got " +
                                std::to_string(pixel_sigma));
  }
  if (max_num_iterations < 1) {
    throw std::invalid_argument("max_num_iterations must be >= 1, got " +
                                std::to_string(max_num_iterations));
  }
}

TwoViewEstimate EstimateTwoViewPose(
    const std::vector<Eigen::Vector2d>& normalized_in_cam_i,
    const std::vector<Eigen::Vector2d>& normalized_in_cam_j,
    const TwoViewOptions& options) {
  options.Check();
  if (normalized_in_cam_i.size() != normalized_in_cam_j.size()) {
    throw std::invalid_argument(
        "EstimateTwoViewPose: the two views have different point counts");
  }
  TwoViewEstimate estimate;
  const int num_points = static_cast<int>(normalized_in_cam_i.size());
  if (num_points < kMinNumPoints) {
    estimate.failure = "fewer than 8 correspondences";
    return estimate;
  }

  // (1) 8-point + cheirality.
  std::vector<cv::Point2d> points_i, points_j;
  for (int k = 0; k < num_points; ++k) {
    points_i.emplace_back(normalized_in_cam_i[k].x(),
                          normalized_in_cam_i[k].y());
    points_j.emplace_back(normalized_in_cam_j[k].x(),
                          normalized_in_cam_j[k].y());
  }
  cv::Mat essential;
  try {
    essential = cv::findFundamentalMat(points_i, points_j, cv::FM_8POINT);
  } catch (const cv::Exception& error) {
    estimate.failure = std::string("8-point algorithm failed: ") + error.what();
    return estimate;
  }
  if (essential.rows != 3 || essential.cols != 3) {
    estimate.failure = "8-point algorithm found no essential matrix";
    return estimate;
  }
  cv::Mat rotation_cv, translation_cv, mask, triangulated;
  int num_in_front = 0;
  try {
    num_in_front = cv::recoverPose(essential,
                                   points_i,
                                   points_j,
                                   cv::Mat::eye(3, 3, CV_64F),
                                   rotation_cv,
                                   translation_cv,
                                   kRecoverPoseDistance,
                                   mask,
                                   triangulated);
  } catch (const cv::Exception& error) {
    estimate.failure = std::string("recoverPose failed: ") + error.what();
    return estimate;
  }
  if (num_in_front == 0) {
    estimate.failure =
        "no decomposition puts the points in front of both views";
    return estimate;
  }
  Eigen::Matrix3d r_ji;
  Eigen::Vector3d t_ji;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      r_ji(row, col) = rotation_cv.at<double>(row, col);
    }
    t_ji(row) = translation_cv.at<double>(row, 0);
  }
  const Rigid3d cam_j_from_cam_i(Eigen::Quaterniond(r_ji).normalized(),
                                 t_ji.normalized());
  Rigid3d cam_i_from_cam_j = Inverse(cam_j_from_cam_i);
  if (options.initial_cam_i_from_cam_j) {
    cam_i_from_cam_j = *options.initial_cam_i_from_cam_j;
    cam_i_from_cam_j.translation.normalize();
  }

  // (2) Triangulation.
  estimate.points_in_cam_i.resize(num_points);
  for (int k = 0; k < num_points; ++k) {
    estimate.points_in_cam_i[k] = Triangulate(normalized_in_cam_i[k],
                                              normalized_in_cam_j[k],
                                              Inverse(cam_i_from_cam_j));
  }
  estimate.initial_rms_px = ReprojectionRms(normalized_in_cam_i,
                                            normalized_in_cam_j,
                                            cam_i_from_cam_j,
                                            estimate.points_in_cam_i,
                                            options.focal_length_px);
  estimate.cam_i_from_cam_j = cam_i_from_cam_j;
  estimate.final_rms_px = estimate.initial_rms_px;
  if (!options.refine) {
    estimate.success = true;
    return estimate;
  }

  // (3) Bundle adjustment.
  double rotation[4];
  double translation[3];
  const Eigen::Quaterniond q0 = cam_i_from_cam_j.rotation.normalized();
  for (int k = 0; k < 4; ++k) rotation[k] = q0.coeffs()[k];
  for (int k = 0; k < 3; ++k) translation[k] = cam_i_from_cam_j.translation(k);
  std::vector<double> points(3 * num_points);
  for (int k = 0; k < num_points; ++k) {
    for (int c = 0; c < 3; ++c)
      points[3 * k + c] = estimate.points_in_cam_i[k](c);
  }
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::EigenQuaternionManifold quaternion_manifold;
  ceres::SphereManifold<3> sphere_manifold;
  const double focal = options.focal_length_px;
  for (int k = 0; k < num_points; ++k) {
    double* point = &points[3 * k];
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<ViewIResidual, 2, 3>(
            new ViewIResidual(normalized_in_cam_i[k], focal)),
        nullptr,
        point);
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<ViewJResidual, 2, 4, 3, 3>(
            new ViewJResidual(normalized_in_cam_j[k], focal)),
        nullptr,
        rotation,
        translation,
        point);
  }
  problem.SetManifold(rotation, &quaternion_manifold);
  problem.SetManifold(translation, &sphere_manifold);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_num_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.logging_type = ceres::SILENT;
  solver_options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  estimate.num_iterations = static_cast<int>(summary.iterations.size()) - 1;
  estimate.final_cost = summary.final_cost;
  if (!summary.IsSolutionUsable()) {
    estimate.failure = "bundle adjustment failed: " + summary.BriefReport();
    return estimate;
  }
  // The reprojection cost is invariant under (t, p) -> (-t, -p), which puts
  // the points behind both cameras: the bundle adjustment can drift there.
  // Cheirality decides; the cost, and so the covariance, are unchanged.
  int num_behind = 0;
  for (int k = 0; k < num_points; ++k) {
    if (points[3 * k + 2] < 0.0) ++num_behind;
  }
  if (2 * num_behind > num_points) {
    for (double& value : translation) value = -value;
    for (double& value : points) value = -value;
  }
  cam_i_from_cam_j = Rigid3d(
      Eigen::Quaterniond(rotation[3], rotation[0], rotation[1], rotation[2])
          .normalized(),
      Eigen::Vector3d(translation[0], translation[1], translation[2])
          .normalized());
  for (int k = 0; k < num_points; ++k) {
    estimate.points_in_cam_i[k] =
        Eigen::Map<const Eigen::Vector3d>(&points[3 * k]);
  }
  estimate.cam_i_from_cam_j = cam_i_from_cam_j;
  estimate.final_rms_px = ReprojectionRms(normalized_in_cam_i,
                                          normalized_in_cam_j,
                                          cam_i_from_cam_j,
                                          estimate.points_in_cam_i,
                                          focal);

  // Covariance: J in tangent coordinates [delta_q(3), delta_t(2), points].
  ceres::Problem::EvaluateOptions evaluate_options;
  evaluate_options.parameter_blocks = {rotation, translation};
  for (int k = 0; k < num_points; ++k) {
    evaluate_options.parameter_blocks.push_back(&points[3 * k]);
  }
  ceres::CRSMatrix crs;
  problem.Evaluate(evaluate_options, nullptr, nullptr, nullptr, &crs);
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) {
      jacobian(row, crs.cols[k]) = crs.values[k];
    }
  }
  const Eigen::MatrixXd h = jacobian.transpose() * jacobian;
  const int num_landmark_params = 3 * num_points;
  const Eigen::Matrix<double, 5, 5> h_pp = h.topLeftCorner<5, 5>();
  const Eigen::MatrixXd h_pl = h.topRightCorner(5, num_landmark_params);
  const Eigen::MatrixXd h_ll =
      h.bottomRightCorner(num_landmark_params, num_landmark_params);
  const Eigen::LDLT<Eigen::MatrixXd> h_ll_ldlt(h_ll);
  if (h_ll_ldlt.info() != Eigen::Success || !h_ll_ldlt.isPositive()) {
    estimate.failure = "the points are not determined (singular information)";
    return estimate;
  }
  Eigen::Matrix<double, 5, 5> h_pose =
      h_pp - h_pl * h_ll_ldlt.solve(h_pl.transpose());
  h_pose = 0.5 * (h_pose + h_pose.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 5, 5>> eigen(
      h_pose);
  const Eigen::Matrix<double, 5, 1> values = eigen.eigenvalues();
  if (!(values(0) > kMinInformationRatio * values(4))) {
    estimate.failure =
        "the relative pose is not determined (singular information)";
    return estimate;
  }
  const Eigen::Matrix<double, 5, 5> covariance_tangent =
      options.pixel_sigma * options.pixel_sigma * eigen.eigenvectors() *
      values.cwiseInverse().asDiagonal() * eigen.eigenvectors().transpose();
  Eigen::Matrix<double, 3, 2, Eigen::RowMajor> sphere_jacobian;
  sphere_manifold.PlusJacobian(translation, sphere_jacobian.data());
  Eigen::Matrix<double, 6, 5> to_motion = Eigen::Matrix<double, 6, 5>::Zero();
  to_motion.topLeftCorner<3, 3>() = 2.0 * Eigen::Matrix3d::Identity();
  to_motion.bottomRightCorner<3, 2>() = sphere_jacobian;
  estimate.covariance = to_motion * covariance_tangent * to_motion.transpose();
  estimate.success = true;
  return estimate;
}

}  // namespace odomcal
