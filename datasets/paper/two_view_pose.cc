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

#include "odomcal/datasets/paper/two_view_direction_scan.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <ceres/ceres.h>
#include <ceres/sphere_manifold.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

namespace odomcal {
namespace {

constexpr int kMinNumPoints = 8;
// Points further than this (in baselines) count as at infinity in
// recoverPose's cheirality test; ours are never, so it is set out of reach.
constexpr double kRecoverPoseDistance = 1e9;
// H_pose is treated as singular below this ratio of its eigenvalues.
constexpr double kMinPoseInformationRatio = 1e-14;
// Two starts closer than this (rotation, and angle between translation
// lines) are one start.
constexpr double kSameStartRad = 1e-3;
// Other minima less likely than this relative to the best one are ignored
// by the covariance (their weight would be below it).
constexpr double kMinMinimumLikelihoodRatio = 1e-4;
// Seed of the minimal-sample subsets: the estimate depends on the data only.
constexpr unsigned kMinimalSampleSeed = 5489u;
// RANSAC of OpenCV's 5-point essential-matrix estimation: confidence, and
// the inlier threshold in image noise standard deviations (at least
// kFivePointMinSigmaPx pixels, so that noise-free data have a threshold).
constexpr double kFivePointConfidence = 0.999;
constexpr double kFivePointThresholdSigmas = 3.0;
constexpr double kFivePointMinSigmaPx = 0.1;

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

// cam_i_from_cam_j with a unit translation from OpenCV's cam_j_from_cam_i.
Rigid3d FromOpenCv(const cv::Mat& rotation_cv, const cv::Mat& translation_cv) {
  Eigen::Matrix3d r_ji;
  Eigen::Vector3d t_ji;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      r_ji(row, col) = rotation_cv.at<double>(row, col);
    }
    t_ji(row) = translation_cv.at<double>(row, 0);
  }
  return Inverse(
      Rigid3d(Eigen::Quaterniond(r_ji).normalized(), t_ji.normalized()));
}

// Starts that differ in rotation or in the translation's line. The sign of
// the translation does not make another start: the reprojection cost is
// invariant under (t, p) -> (-t, -p), and cheirality fixes the sign after.
void AddDistinctStart(const Rigid3d& start, std::vector<Rigid3d>* starts) {
  for (const Rigid3d& other : *starts) {
    if (RotationAngle(other.rotation.conjugate() * start.rotation) <
            kSameStartRad &&
        std::abs(other.translation.dot(start.translation)) >
            std::cos(kSameStartRad)) {
      return;
    }
  }
  starts->push_back(start);
}

// Number of points in front of both views when triangulated with the pose.
int NumInFront(const std::vector<cv::Point2d>& points_i,
               const std::vector<cv::Point2d>& points_j,
               const Rigid3d& cam_i_from_cam_j) {
  const Rigid3d cam_j_from_cam_i = Inverse(cam_i_from_cam_j);
  int count = 0;
  for (size_t k = 0; k < points_i.size(); ++k) {
    const Eigen::Vector3d p_i =
        Triangulate(Eigen::Vector2d(points_i[k].x, points_i[k].y),
                    Eigen::Vector2d(points_j[k].x, points_j[k].y),
                    cam_j_from_cam_i);
    if (p_i.z() > 0.0 && (cam_j_from_cam_i * p_i).z() > 0.0) ++count;
  }
  return count;
}

// Every decomposition of `essential` that the cheirality test leaves
// viable: at least half of the points in front of both views. recoverPose
// keeps only the one with the most points in front; with short baselines
// and noise the twisted pair (the other rotation) can be close in that
// count and is the start whose minimum is the right one.
std::vector<Rigid3d> ViableDecompositions(
    const cv::Mat& essential,
    const std::vector<cv::Point2d>& points_i,
    const std::vector<cv::Point2d>& points_j) {
  cv::Mat r1, r2, t;
  cv::decomposeEssentialMat(essential, r1, r2, t);
  std::vector<Rigid3d> viable;
  const int num_points = static_cast<int>(points_i.size());
  for (const cv::Mat& rotation : {r1, r2}) {
    int best_count = -1;
    Rigid3d best;
    for (const double sign : {1.0, -1.0}) {
      const Rigid3d candidate = FromOpenCv(rotation, sign * t);
      const int count = NumInFront(points_i, points_j, candidate);
      if (count > best_count) {
        best_count = count;
        best = candidate;
      }
    }
    if (2 * best_count >= num_points) viable.push_back(best);
  }
  return viable;
}

// The 8-point solution that recoverPose picks, then the other viable
// decomposition of the same essential matrix.
std::vector<Rigid3d> EightPointStarts(const std::vector<cv::Point2d>& points_i,
                                      const std::vector<cv::Point2d>& points_j,
                                      std::string* failure) {
  cv::Mat essential;
  try {
    essential = cv::findFundamentalMat(points_i, points_j, cv::FM_8POINT);
  } catch (const cv::Exception& error) {
    *failure = std::string("8-point algorithm failed: ") + error.what();
    return {};
  }
  if (essential.rows != 3 || essential.cols != 3) {
    *failure = "8-point algorithm found no essential matrix";
    return {};
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
    *failure = std::string("recoverPose failed: ") + error.what();
    return {};
  }
  if (num_in_front == 0) {
    *failure = "no decomposition puts the points in front of both views";
    return {};
  }
  std::vector<Rigid3d> starts = {FromOpenCv(rotation_cv, translation_cv)};
  for (const Rigid3d& start :
       ViableDecompositions(essential, points_i, points_j)) {
    AddDistinctStart(start, &starts);
  }
  return starts;
}

// The viable decompositions of the 5-point solutions (Nister's solver inside
// OpenCV's RANSAC; the simulated correspondences have no outliers, so it
// stops after a few samples: LMedS, which needs no threshold, always runs
// hundreds and took 30x the rest of the estimator). Empty when OpenCV finds
// none.
std::vector<Rigid3d> FivePointStarts(const std::vector<cv::Point2d>& points_i,
                                     const std::vector<cv::Point2d>& points_j,
                                     const TwoViewOptions& options) {
  const double threshold = kFivePointThresholdSigmas *
                           std::max(options.pixel_sigma, kFivePointMinSigmaPx) /
                           options.focal_length_px;
  cv::Mat essentials;
  try {
    essentials = cv::findEssentialMat(points_i,
                                      points_j,
                                      cv::Mat::eye(3, 3, CV_64F),
                                      cv::RANSAC,
                                      kFivePointConfidence,
                                      threshold);
  } catch (const cv::Exception&) {
    return {};
  }
  std::vector<Rigid3d> starts;
  // OpenCV stacks several solutions as a (3k x 3) matrix.
  for (int row = 0; row + 3 <= essentials.rows; row += 3) {
    if (essentials.cols != 3) break;
    const cv::Mat essential = essentials.rowRange(row, row + 3).clone();
    for (const Rigid3d& start :
         ViableDecompositions(essential, points_i, points_j)) {
      AddDistinctStart(start, &starts);
    }
  }
  return starts;
}

// Sum over the points of the squared Sampson error (normalised units) of
// the pose: the first-order approximation of the reprojection cost of the
// optimally triangulated points, without the points.
double SampsonCost(const std::vector<cv::Point2d>& points_i,
                   const std::vector<cv::Point2d>& points_j,
                   const Rigid3d& cam_i_from_cam_j) {
  const Rigid3d cam_j_from_cam_i = Inverse(cam_i_from_cam_j);
  const Eigen::Vector3d& t = cam_j_from_cam_i.translation;
  Eigen::Matrix3d skew;
  skew << 0.0, -t.z(), t.y(), t.z(), 0.0, -t.x(), -t.y(), t.x(), 0.0;
  const Eigen::Matrix3d e = skew * cam_j_from_cam_i.rotation.toRotationMatrix();
  double sum = 0.0;
  for (size_t k = 0; k < points_i.size(); ++k) {
    const Eigen::Vector3d x_i(points_i[k].x, points_i[k].y, 1.0);
    const Eigen::Vector3d x_j(points_j[k].x, points_j[k].y, 1.0);
    const Eigen::Vector3d e_x_i = e * x_i;
    const Eigen::Vector3d et_x_j = e.transpose() * x_j;
    const double numerator = x_j.dot(e_x_i);
    const double denominator =
        e_x_i.head<2>().squaredNorm() + et_x_j.head<2>().squaredNorm();
    if (denominator > 0.0) sum += numerator * numerator / denominator;
  }
  return sum;
}

// Starts from minimal samples: the 7-point solutions (up to 3 essential
// matrices; on normalised coordinates the fundamental matrix is the
// essential one) of num_minimal_samples subsets drawn by a fixed generator,
// their viable decompositions ranked by the Sampson cost over all points,
// the best num_minimal_sample_starts distinct ones kept. Minimal samples
// spread the starts over the basins of the cost; the 8-point solution of
// all points sits in one of them (docs/paper_reproduction.md: they remove
// the local minima the other starts miss). The 7-point solver is several
// times cheaper than OpenCV's 5-point one and found the same minima.
std::vector<Rigid3d> MinimalSampleStarts(
    const std::vector<cv::Point2d>& points_i,
    const std::vector<cv::Point2d>& points_j,
    const TwoViewOptions& options) {
  constexpr int kSampleSize = 7;
  const int num_points = static_cast<int>(points_i.size());
  std::mt19937 rng(kMinimalSampleSeed);
  std::vector<int> order(num_points);
  std::vector<std::pair<double, Rigid3d>> scored;
  for (int sample = 0; sample < options.num_minimal_samples; ++sample) {
    for (int k = 0; k < num_points; ++k) order[k] = k;
    for (int k = 0; k < kSampleSize; ++k) {
      std::uniform_int_distribution<int> pick(k, num_points - 1);
      std::swap(order[k], order[pick(rng)]);
    }
    std::vector<cv::Point2d> sample_i, sample_j;
    for (int k = 0; k < kSampleSize; ++k) {
      sample_i.push_back(points_i[order[k]]);
      sample_j.push_back(points_j[order[k]]);
    }
    cv::Mat essentials;
    try {
      essentials = cv::findFundamentalMat(sample_i, sample_j, cv::FM_7POINT);
    } catch (const cv::Exception&) {
      continue;
    }
    // OpenCV stacks the solutions as a (3k x 3) matrix.
    if (essentials.cols != 3) continue;
    for (int row = 0; row + 3 <= essentials.rows; row += 3) {
      const cv::Mat essential = essentials.rowRange(row, row + 3).clone();
      for (const Rigid3d& start :
           ViableDecompositions(essential, points_i, points_j)) {
        scored.emplace_back(SampsonCost(points_i, points_j, start), start);
      }
    }
  }
  std::stable_sort(
      scored.begin(), scored.end(), [](const auto& a, const auto& b) {
        return a.first < b.first;
      });
  std::vector<Rigid3d> starts;
  for (const auto& [cost, start] : scored) {
    if (static_cast<int>(starts.size()) >= options.num_minimal_sample_starts) {
      break;
    }
    AddDistinctStart(start, &starts);
  }
  return starts;
}

// A bundle adjustment from one start.
struct Refinement {
  bool usable = false;
  std::string failure;
  Rigid3d cam_i_from_cam_j;  // unit translation
  std::vector<Eigen::Vector3d> points_in_cam_i;
  double initial_rms_px = 0.0;
  double final_rms_px = 0.0;
  double cost = 0.0;  // Ceres cost, 1/2 sum of squared px
  int num_iterations = 0;
  int num_in_front = 0;  // refined points in front of both views
};

// Adds the reprojection residuals of both views to `problem`.
void AddReprojectionResiduals(const std::vector<Eigen::Vector2d>& u_i,
                              const std::vector<Eigen::Vector2d>& u_j,
                              double focal,
                              double* rotation,
                              double* translation,
                              std::vector<double>* points,
                              ceres::Problem* problem) {
  for (size_t k = 0; k < u_i.size(); ++k) {
    double* point = &(*points)[3 * k];
    problem->AddResidualBlock(
        new ceres::AutoDiffCostFunction<ViewIResidual, 2, 3>(
            new ViewIResidual(u_i[k], focal)),
        nullptr,
        point);
    problem->AddResidualBlock(
        new ceres::AutoDiffCostFunction<ViewJResidual, 2, 4, 3, 3>(
            new ViewJResidual(u_j[k], focal)),
        nullptr,
        rotation,
        translation,
        point);
  }
}

Refinement Refine(const std::vector<Eigen::Vector2d>& u_i,
                  const std::vector<Eigen::Vector2d>& u_j,
                  const Rigid3d& start,
                  const TwoViewOptions& options) {
  const int num_points = static_cast<int>(u_i.size());
  Refinement refinement;
  Rigid3d cam_i_from_cam_j = start;
  refinement.points_in_cam_i.resize(num_points);
  for (int k = 0; k < num_points; ++k) {
    refinement.points_in_cam_i[k] =
        Triangulate(u_i[k], u_j[k], Inverse(cam_i_from_cam_j));
  }
  const double focal = options.focal_length_px;
  refinement.initial_rms_px = ReprojectionRms(
      u_i, u_j, cam_i_from_cam_j, refinement.points_in_cam_i, focal);
  refinement.cam_i_from_cam_j = cam_i_from_cam_j;
  refinement.final_rms_px = refinement.initial_rms_px;
  refinement.cost = 0.5 * 2.0 * num_points * refinement.initial_rms_px *
                    refinement.initial_rms_px;
  if (!options.refine) {
    refinement.usable = true;
    return refinement;
  }

  double rotation[4];
  double translation[3];
  const Eigen::Quaterniond q0 = cam_i_from_cam_j.rotation.normalized();
  for (int k = 0; k < 4; ++k) rotation[k] = q0.coeffs()[k];
  for (int k = 0; k < 3; ++k) translation[k] = cam_i_from_cam_j.translation(k);
  std::vector<double> points(3 * static_cast<size_t>(num_points));
  for (int k = 0; k < num_points; ++k) {
    for (int c = 0; c < 3; ++c)
      points[3 * k + c] = refinement.points_in_cam_i[k](c);
  }
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::EigenQuaternionManifold quaternion_manifold;
  ceres::SphereManifold<3> sphere_manifold;
  AddReprojectionResiduals(
      u_i, u_j, focal, rotation, translation, &points, &problem);
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
  refinement.num_iterations = static_cast<int>(summary.iterations.size()) - 1;
  refinement.cost = summary.final_cost;
  if (!summary.IsSolutionUsable()) {
    refinement.failure = "bundle adjustment failed: " + summary.BriefReport();
    return refinement;
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
  refinement.cam_i_from_cam_j = Rigid3d(
      Eigen::Quaterniond(rotation[3], rotation[0], rotation[1], rotation[2])
          .normalized(),
      Eigen::Vector3d(translation[0], translation[1], translation[2])
          .normalized());
  for (int k = 0; k < num_points; ++k) {
    refinement.points_in_cam_i[k] =
        Eigen::Map<const Eigen::Vector3d>(&points[3 * static_cast<size_t>(k)]);
  }
  refinement.final_rms_px = ReprojectionRms(
      u_i, u_j, refinement.cam_i_from_cam_j, refinement.points_in_cam_i, focal);
  const Rigid3d cam_j_from_cam_i = Inverse(refinement.cam_i_from_cam_j);
  for (const Eigen::Vector3d& point : refinement.points_in_cam_i) {
    if (point.z() > 0.0 && (cam_j_from_cam_i * point).z() > 0.0) {
      ++refinement.num_in_front;
    }
  }
  refinement.usable = true;
  return refinement;
}

// The covariance of the pose at a minimum; see the file comment.
std::optional<MotionCovariance> PoseCovariance(
    const std::vector<Eigen::Vector2d>& u_i,
    const std::vector<Eigen::Vector2d>& u_j,
    const Rigid3d& cam_i_from_cam_j,
    const std::vector<Eigen::Vector3d>& points_in_cam_i,
    const TwoViewOptions& options,
    std::string* failure) {
  const int num_points = static_cast<int>(u_i.size());
  double rotation[4];
  double translation[3];
  const Eigen::Quaterniond q = cam_i_from_cam_j.rotation.normalized();
  for (int k = 0; k < 4; ++k) rotation[k] = q.coeffs()[k];
  for (int k = 0; k < 3; ++k) translation[k] = cam_i_from_cam_j.translation(k);
  std::vector<double> points(3 * static_cast<size_t>(num_points));
  for (int k = 0; k < num_points; ++k) {
    for (int c = 0; c < 3; ++c) points[3 * k + c] = points_in_cam_i[k](c);
  }
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::EigenQuaternionManifold quaternion_manifold;
  ceres::SphereManifold<3> sphere_manifold;
  AddReprojectionResiduals(u_i,
                           u_j,
                           options.focal_length_px,
                           rotation,
                           translation,
                           &points,
                           &problem);
  problem.SetManifold(rotation, &quaternion_manifold);
  problem.SetManifold(translation, &sphere_manifold);

  // J in tangent coordinates [delta_q(3), delta_t(2), points].
  ceres::Problem::EvaluateOptions evaluate_options;
  evaluate_options.parameter_blocks = {rotation, translation};
  for (int k = 0; k < num_points; ++k) {
    evaluate_options.parameter_blocks.push_back(
        &points[3 * static_cast<size_t>(k)]);
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
    *failure = "the points are not determined (singular information)";
    return std::nullopt;
  }
  Eigen::Matrix<double, 5, 5> h_pose =
      h_pp - h_pl * h_ll_ldlt.solve(h_pl.transpose());
  h_pose = 0.5 * (h_pose + h_pose.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 5, 5>> eigen(
      h_pose);
  const Eigen::Matrix<double, 5, 1>& values = eigen.eigenvalues();
  if (!(values(0) > kMinPoseInformationRatio * values(4))) {
    *failure = "the relative pose is not determined (singular information)";
    return std::nullopt;
  }
  const Eigen::Matrix<double, 5, 5> covariance_tangent =
      options.pixel_sigma * options.pixel_sigma * eigen.eigenvectors() *
      values.cwiseInverse().asDiagonal() * eigen.eigenvectors().transpose();
  Eigen::Matrix<double, 3, 2, Eigen::RowMajor> sphere_jacobian;
  sphere_manifold.PlusJacobian(translation, sphere_jacobian.data());
  Eigen::Matrix<double, 6, 5> to_motion = Eigen::Matrix<double, 6, 5>::Zero();
  to_motion.topLeftCorner<3, 3>() = 2.0 * Eigen::Matrix3d::Identity();
  to_motion.bottomRightCorner<3, 2>() = sphere_jacobian;
  return MotionCovariance(to_motion * covariance_tangent *
                          to_motion.transpose());
}

// The spread of the other minima, see the file comment ("Other minima").
void AddOtherMinima(const std::vector<Eigen::Vector2d>& u_i,
                    const std::vector<Eigen::Vector2d>& /*u_j*/,
                    const Refinement& best,
                    const std::vector<Refinement>& minima,
                    const TwoViewOptions& options,
                    TwoViewEstimate* estimate) {
  const double variance = options.pixel_sigma * options.pixel_sigma;
  if (!(variance > 0.0)) return;
  const int num_points = static_cast<int>(u_i.size());
  std::vector<Rigid3d> distinct = {best.cam_i_from_cam_j};
  MotionCovariance spread = MotionCovariance::Zero();
  double total_weight = 1.0;
  for (const Refinement& minimum : minima) {
    if (2 * minimum.num_in_front < num_points) continue;
    const double delta_chi2 = 2.0 * (minimum.cost - best.cost) / variance;
    const double weight = std::exp(-0.5 * delta_chi2);
    if (!(weight > kMinMinimumLikelihoodRatio)) continue;
    bool seen = false;
    for (const Rigid3d& other : distinct) {
      if (RotationAngle(other.rotation.conjugate() *
                        minimum.cam_i_from_cam_j.rotation) < kSameStartRad &&
          other.translation.dot(minimum.cam_i_from_cam_j.translation) >
              std::cos(kSameStartRad)) {
        seen = true;
      }
    }
    if (seen) continue;
    distinct.push_back(minimum.cam_i_from_cam_j);
    Eigen::Matrix<double, 6, 1> d;
    d.head<3>() = LogRotation(minimum.cam_i_from_cam_j.rotation *
                              best.cam_i_from_cam_j.rotation.conjugate());
    // In the tangent plane of the best (unit) translation, like C_best.
    const Eigen::Vector3d& u = best.cam_i_from_cam_j.translation;
    d.tail<3>() = (Eigen::Matrix3d::Identity() - u * u.transpose()) *
                  minimum.cam_i_from_cam_j.translation;
    spread += weight * d * d.transpose();
    total_weight += weight;
    ++estimate->num_other_minima;
  }
  estimate->covariance += spread / total_weight;
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
  if (num_minimal_samples < 0 || num_minimal_sample_starts < 0) {
    throw std::invalid_argument(
        "num_minimal_samples and num_minimal_sample_starts must be >= 0");
  }
  if (direction_scan_points < 0) {
    throw std::invalid_argument("direction_scan_points must be >= 0, got " +
                                std::to_string(direction_scan_points));
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

  // (1) Starting poses.
  std::vector<cv::Point2d> points_i, points_j;
  for (int k = 0; k < num_points; ++k) {
    points_i.emplace_back(normalized_in_cam_i[k].x(),
                          normalized_in_cam_i[k].y());
    points_j.emplace_back(normalized_in_cam_j[k].x(),
                          normalized_in_cam_j[k].y());
  }
  std::vector<Rigid3d> starts;
  if (options.initial_cam_i_from_cam_j) {
    starts.push_back(*options.initial_cam_i_from_cam_j);
    starts.back().translation.normalize();
  } else {
    std::string failure;
    starts = EightPointStarts(points_i, points_j, &failure);
    if (starts.empty()) {
      estimate.failure = failure;
      return estimate;
    }
    if (options.multi_start && options.refine) {
      for (const Rigid3d& start :
           FivePointStarts(points_i, points_j, options)) {
        AddDistinctStart(start, &starts);
      }
      for (const Rigid3d& start :
           MinimalSampleStarts(points_i, points_j, options)) {
        AddDistinctStart(start, &starts);
      }
    }
  }
  if (!options.multi_start || !options.refine) starts.resize(1);

  // (2) Triangulation and (3) bundle adjustment from each start; the lowest
  // cost wins (the earliest of equals: the 8-point solution).
  std::optional<Refinement> best;
  std::vector<Refinement> minima;  // the other usable ends
  for (const Rigid3d& start : starts) {
    Refinement refinement =
        Refine(normalized_in_cam_i, normalized_in_cam_j, start, options);
    ++estimate.num_starts;
    if (!refinement.usable) {
      if (!best) estimate.failure = refinement.failure;
      continue;
    }
    if (!best || refinement.cost < best->cost) {
      estimate.best_start = estimate.num_starts - 1;
      if (best) minima.push_back(std::move(*best));
      best = std::move(refinement);
    } else {
      minima.push_back(std::move(refinement));
    }
  }
  if (!best) return estimate;
  estimate.failure.clear();
  estimate.cam_i_from_cam_j = best->cam_i_from_cam_j;
  estimate.points_in_cam_i = best->points_in_cam_i;
  estimate.initial_rms_px = best->initial_rms_px;
  estimate.final_rms_px = best->final_rms_px;
  estimate.final_cost = best->cost;
  estimate.num_iterations = best->num_iterations;
  if (!options.refine) {
    estimate.success = true;
    return estimate;
  }
  std::string failure;
  const std::optional<MotionCovariance> covariance =
      PoseCovariance(normalized_in_cam_i,
                     normalized_in_cam_j,
                     estimate.cam_i_from_cam_j,
                     estimate.points_in_cam_i,
                     options,
                     &failure);
  if (!covariance) {
    estimate.failure = failure;
    return estimate;
  }
  estimate.covariance = *covariance;
  if (options.covariance_of_other_minima) {
    AddOtherMinima(normalized_in_cam_i,
                   normalized_in_cam_j,
                   *best,
                   minima,
                   options,
                   &estimate);
  }
  estimate.core_covariance = estimate.covariance;
  if (options.multi_start) {
    const DirectionScan scan =
        ScanTranslationDirection(normalized_in_cam_i,
                                 normalized_in_cam_j,
                                 estimate.cam_i_from_cam_j,
                                 estimate.covariance,
                                 options.focal_length_px,
                                 options.pixel_sigma,
                                 options.direction_scan_points);
    estimate.covariance = scan.covariance;
    estimate.direction_scanned = scan.scanned;
    estimate.num_direction_cells = scan.num_cells_used;
  }
  estimate.success = true;
  return estimate;
}

std::optional<MotionCovariance> TwoViewPoseCovarianceAt(
    const std::vector<Eigen::Vector2d>& normalized_in_cam_i,
    const std::vector<Eigen::Vector2d>& normalized_in_cam_j,
    const Rigid3d& cam_i_from_cam_j,
    const std::vector<Eigen::Vector3d>& points_in_cam_i,
    const TwoViewOptions& options) {
  options.Check();
  if (normalized_in_cam_i.size() != normalized_in_cam_j.size() ||
      points_in_cam_i.size() != normalized_in_cam_i.size()) {
    throw std::invalid_argument(
        "TwoViewPoseCovarianceAt: different point counts");
  }
  std::string failure;
  return PoseCovariance(normalized_in_cam_i,
                        normalized_in_cam_j,
                        cam_i_from_cam_j,
                        points_in_cam_i,
                        options,
                        &failure);
}

}  // namespace odomcal
