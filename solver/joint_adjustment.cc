// See the header for the model. Ceres problem: per image a pose block (3),
// the extrinsic as [q (4, EigenQuaternionManifold), t_xy (2), t_z (1,
// constant)], per point a block (3), per camera an intrinsics block (held
// unless refined). Solved with the sparse Schur complement (points
// eliminated first), two or three times: each pass estimates the pixel
// sigma from its residuals and leaves out the observations beyond
// max_reprojection_sigmas for the next.

#include "odomcal/solver/joint_adjustment.h"

#include "odomcal/solver/joint_adjustment_covariance.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace odomcal {
namespace {

template <typename T>
T WrapAngle(const T& angle) {
  using std::atan2;
  using std::cos;
  using std::sin;
  return atan2(sin(angle), cos(angle));
}

// Reprojection residual of one observation (see the header), in pixel
// sigmas.
template <ProjectionModel kModel>
struct ReprojectionCost {
  ReprojectionCost(const Eigen::Vector2d& pixel, double pixel_sigma)
      : pixel_(pixel), inverse_sigma_(1.0 / pixel_sigma) {}

  template <typename T>
  bool operator()(const T* pose,
                  const T* quaternion,
                  const T* t_xy,
                  const T* t_z,
                  const T* point,
                  const T* params,
                  T* residual) const {
    using std::cos;
    using std::sin;
    // Into the odometry frame at this image.
    const T c = cos(pose[2]);
    const T s = sin(pose[2]);
    const T dx = point[0] - pose[0];
    const T dy = point[1] - pose[1];
    const Eigen::Matrix<T, 3, 1> in_odom(
        c * dx + s * dy, -s * dx + c * dy, point[2]);
    // Into the camera frame: cam_from_odom = Inverse(odom_from_cam).
    const Eigen::Map<const Eigen::Quaternion<T>> odom_from_cam_rotation(
        quaternion);
    const Eigen::Matrix<T, 3, 1> offset(t_xy[0], t_xy[1], t_z[0]);
    const Eigen::Matrix<T, 3, 1> in_cam =
        odom_from_cam_rotation.conjugate() * (in_odom - offset);
    T pixel[2];
    if (!ProjectToPixel<kModel>(params, in_cam.data(), pixel)) return false;
    residual[0] = (pixel[0] - T(pixel_[0])) * T(inverse_sigma_);
    residual[1] = (pixel[1] - T(pixel_[1])) * T(inverse_sigma_);
    return true;
  }

  Eigen::Vector2d pixel_;
  double inverse_sigma_;
};

template <ProjectionModel kModel>
ceres::CostFunction* CreateReprojectionCost(const Eigen::Vector2d& pixel,
                                            double pixel_sigma) {
  return new ceres::AutoDiffCostFunction<ReprojectionCost<kModel>,
                                         2,
                                         3,
                                         4,
                                         2,
                                         1,
                                         3,
                                         ProjectionNumParams(kModel)>(
      new ReprojectionCost<kModel>(pixel, pixel_sigma));
}

ceres::CostFunction* ReprojectionCostFor(ProjectionModel model,
                                         const Eigen::Vector2d& pixel,
                                         double pixel_sigma) {
  return VisitProjectionModel(model, [&](auto constant) {
    return CreateReprojectionCost<decltype(constant)::value>(pixel,
                                                             pixel_sigma);
  });
}

// The reprojection residual in pixels at doubles, without a cost object.
bool ReprojectionResidualFor(ProjectionModel model,
                             const Eigen::Vector2d& pixel,
                             const double* const* parameters,
                             double* residual) {
  return VisitProjectionModel(model, [&](auto constant) {
    return ReprojectionCost<decltype(constant)::value>(pixel, 1.0)(
        parameters[0],
        parameters[1],
        parameters[2],
        parameters[3],
        parameters[4],
        parameters[5],
        residual);
  });
}

// Hands each Ceres iteration to JointAdjustmentOptions::progress.
class ProgressCallback : public ceres::IterationCallback {
 public:
  ProgressCallback(
      const std::function<void(const JointAdjustmentProgress&)>& callback,
      int pass,
      std::chrono::steady_clock::time_point start)
      : callback_(callback), pass_(pass), start_(start) {}

  ceres::CallbackReturnType operator()(
      const ceres::IterationSummary& summary) override {
    JointAdjustmentProgress progress;
    progress.pass = pass_;
    progress.iteration = summary.iteration;
    progress.cost = summary.cost;
    progress.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_)
            .count();
    callback_(progress);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const std::function<void(const JointAdjustmentProgress&)>& callback_;
  int pass_;
  std::chrono::steady_clock::time_point start_;
};

// The planar motion from pose i to pose j, in pose i's frame.
template <typename T>
void PlanarMotionBetween(const T* pose_i, const T* pose_j, T* motion) {
  using std::cos;
  using std::sin;
  const T c = cos(pose_i[2]);
  const T s = sin(pose_i[2]);
  const T dx = pose_j[0] - pose_i[0];
  const T dy = pose_j[1] - pose_i[1];
  motion[0] = c * dx + s * dy;
  motion[1] = -s * dx + c * dy;
  motion[2] = WrapAngle(pose_j[2] - pose_i[2]);
}

// Whitened odometry residual of one link: the poses' planar motion minus
// the measured one.
template <typename T>
void WhitenedLinkResidual(const T* pose_i,
                          const T* pose_j,
                          const T* measured,
                          const Eigen::Matrix3d& sqrt_information,
                          T* residual) {
  T motion[3];
  PlanarMotionBetween(pose_i, pose_j, motion);
  const Eigen::Matrix<T, 3, 1> difference(motion[0] - measured[0],
                                          motion[1] - measured[1],
                                          WrapAngle(motion[2] - measured[2]));
  Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residual);
  whitened = sqrt_information.cast<T>() * difference;
}

// A link whose measurement is fixed.
struct OdometryLinkCost {
  OdometryLinkCost(const PlanarPose& measured,
                   const Eigen::Matrix3d& sqrt_information)
      : measured_(measured), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* pose_i, const T* pose_j, T* residual) const {
    const T measured[3] = {
        T(measured_.x), T(measured_.y), T(measured_.yaw_rad)};
    WhitenedLinkResidual(pose_i, pose_j, measured, sqrt_information_, residual);
    return true;
  }

  PlanarPose measured_;
  Eigen::Matrix3d sqrt_information_;
};

// A link whose measurement is the logged odometry re-integrated with the
// intrinsics and the clock offset's change being refined
// (CorrectedOdometryMotion, solver/odometry_intrinsics.h).
struct SystematicOdometryLinkCost {
  SystematicOdometryLinkCost(const OdometrySamples& samples,
                             const Eigen::Matrix3d& sqrt_information,
                             double wheel_track_m)
      : samples_(samples),
        sqrt_information_(sqrt_information),
        wheel_track_m_(wheel_track_m) {}

  template <typename T>
  bool operator()(const T* pose_i,
                  const T* pose_j,
                  const T* intrinsics,
                  const T* offset_change_s,
                  T* residual) const {
    const PlanarMotion<T> motion = CorrectedOdometryMotion(
        samples_, intrinsics, offset_change_s[0], wheel_track_m_);
    const T measured[3] = {motion.x, motion.y, motion.yaw};
    WhitenedLinkResidual(pose_i, pose_j, measured, sqrt_information_, residual);
    return true;
  }

  OdometrySamples samples_;
  Eigen::Matrix3d sqrt_information_;
  double wheel_track_m_;
};

// Upper-triangular W with W^T W = covariance^-1; false when the covariance
// is not positive definite.
bool SqrtInformation(const Eigen::Matrix3d& covariance, Eigen::Matrix3d* w) {
  const Eigen::LLT<Eigen::Matrix3d> llt(covariance);
  if (llt.info() != Eigen::Success || !covariance.allFinite()) return false;
  // covariance = L L^T, so covariance^-1 = L^-T L^-1 and W = L^-1.
  *w = llt.matrixL().solve(Eigen::Matrix3d::Identity());
  return true;
}

std::string CheckProblem(const JointAdjustmentProblem& problem) {
  if (problem.images.empty()) return "no images";
  if (problem.links.empty()) return "no odometry links";
  for (size_t c = 0; c < problem.cameras.size(); ++c) {
    const JointCamera& camera = problem.cameras[c];
    if (static_cast<int>(camera.params.size()) !=
        ProjectionNumParams(camera.model)) {
      return "camera " + std::to_string(c) + ": " +
             std::to_string(camera.params.size()) + " parameters for " +
             ProjectionModelName(camera.model);
    }
    for (const double value : camera.params) {
      if (!std::isfinite(value)) {
        return "camera " + std::to_string(c) + ": a non-finite parameter";
      }
    }
  }
  for (size_t i = 0; i < problem.images.size(); ++i) {
    const JointImage& image = problem.images[i];
    if (image.camera < 0 ||
        image.camera >= static_cast<int>(problem.cameras.size())) {
      return "image " + std::to_string(i) + ": no camera " +
             std::to_string(image.camera);
    }
  }
  const int num_images = static_cast<int>(problem.images.size());
  const int num_points = static_cast<int>(problem.points.size());
  for (const JointObservation& observation : problem.observations) {
    if (observation.image < 0 || observation.image >= num_images ||
        observation.point < 0 || observation.point >= num_points ||
        !observation.pixel.allFinite()) {
      return "an observation names a missing image or point, or a "
             "non-finite pixel";
    }
  }
  for (const OdometryLink& link : problem.links) {
    Eigen::Matrix3d unused;
    if (link.image_i < 0 || link.image_i >= num_images || link.image_j < 0 ||
        link.image_j >= num_images || link.image_i == link.image_j) {
      return "an odometry link names a missing image or one image twice";
    }
    if (!SqrtInformation(link.covariance, &unused)) {
      return "an odometry link's covariance is not positive definite";
    }
  }
  if (!IsFinite(problem.odom_from_cam)) return "a non-finite extrinsic";
  if (problem.systematics) {
    for (const OdometryLink& link : problem.links) {
      if (!link.samples) {
        return "an odometry link without the logged odometry, which the "
               "refinement of the odometry's systematics needs";
      }
    }
  }
  return "";
}

// Union-find over the images: joined by links and by shared points.
class ImageComponents {
 public:
  explicit ImageComponents(int size) : parent_(size) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int Find(int i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void Join(int a, int b) { parent_[Find(a)] = Find(b); }

 private:
  std::vector<int> parent_;
};

// Parameter storage, the Ceres problem over it and the residual statistics.
class JointProblem {
 public:
  JointProblem(const JointAdjustmentProblem& input,
               const JointAdjustmentOptions& options)
      : input_(input), options_(options) {
    poses_.reserve(input.images.size());
    for (const JointImage& image : input.images) {
      poses_.push_back({image.origin_from_odom.x,
                        image.origin_from_odom.y,
                        image.origin_from_odom.yaw_rad});
    }
    points_ = input.points;
    for (const JointCamera& camera : input.cameras) {
      params_.push_back(camera.params);
    }
    const Eigen::Quaterniond q = input.odom_from_cam.rotation.normalized();
    for (int k = 0; k < 4; ++k) quaternion_[k] = q.coeffs()[k];
    t_xy_[0] = input.odom_from_cam.translation.x();
    t_xy_[1] = input.odom_from_cam.translation.y();
    t_z_ = input.odom_from_cam.translation.z();
    used_.assign(input.observations.size(), 1);
    // A point on or behind a camera that sees it cannot be projected: the
    // observation is left out from the start (Ceres would stop at it).
    for (size_t k = 0; k < input.observations.size(); ++k) {
      Eigen::Vector2d residual;
      if (!ReprojectionResidual(k, &residual)) used_[k] = 0;
    }
    FindPointsSeenTwice();
    if (input.systematics) {
      const OdometryIntrinsics& start = input.systematics->intrinsics;
      intrinsics_[0] = start.yaw_scale;
      intrinsics_[1] = start.yaw_per_metre_rad;
      intrinsics_[2] = start.yaw_rate_bias_rad_s;
      offset_change_s_ = input.systematics->time_offset_change_s;
    }
  }

  // The images that keep their starting pose: the first of each component.
  // Empty string, or why the problem has no determined scale.
  std::string FindGauge() {
    const int num_images = static_cast<int>(input_.images.size());
    ImageComponents components(num_images);
    for (const OdometryLink& link : input_.links) {
      components.Join(link.image_i, link.image_j);
    }
    std::vector<int> first_image_of_point(input_.points.size(), -1);
    for (const JointObservation& observation : input_.observations) {
      int& first = first_image_of_point[observation.point];
      if (first < 0) {
        first = observation.image;
      } else {
        components.Join(first, observation.image);
      }
    }
    std::vector<char> linked(num_images, 0);
    for (const OdometryLink& link : input_.links) {
      linked[components.Find(link.image_i)] = 1;
    }
    held_.assign(num_images, 0);
    std::vector<char> seen(num_images, 0);
    num_components_ = 0;
    for (int i = 0; i < num_images; ++i) {
      const int root = components.Find(i);
      if (seen[root]) continue;
      seen[root] = 1;
      ++num_components_;
      if (!linked[root]) {
        return "image " + std::to_string(i) +
               " and the images it shares points with have no odometry "
               "link: their metric scale is not determined";
      }
      held_[i] = 1;
    }
    return "";
  }

  // A point seen in fewer than two images is not determined by them: it
  // and its observation stay out of the problem.
  void FindPointsSeenTwice() {
    std::vector<int> first_image(input_.points.size(), -1);
    seen_twice_.assign(input_.points.size(), 0);
    for (size_t k = 0; k < input_.observations.size(); ++k) {
      if (!used_[k]) continue;
      const JointObservation& observation = input_.observations[k];
      int& first = first_image[observation.point];
      if (first < 0) {
        first = observation.image;
      } else if (first != observation.image) {
        seen_twice_[observation.point] = 1;
      }
    }
  }

  // Builds the Ceres problem over the observations in use.
  void Build(double pixel_sigma) {
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_ = std::make_unique<ceres::Problem>(problem_options);
    residual_blocks_.clear();
    cluster_of_block_.clear();
    FindPointsSeenTwice();
    for (size_t k = 0; k < input_.observations.size(); ++k) {
      if (!used_[k] || !seen_twice_[input_.observations[k].point]) continue;
      const JointObservation& observation = input_.observations[k];
      const int camera = input_.images[observation.image].camera;
      ceres::LossFunction* loss = nullptr;
      if (options_.loss == RobustLoss::kHuber) {
        loss = new ceres::HuberLoss(options_.loss_scale);
      } else if (options_.loss == RobustLoss::kCauchy) {
        loss = new ceres::CauchyLoss(options_.loss_scale);
      }
      const ceres::ResidualBlockId id = problem_->AddResidualBlock(
          ReprojectionCostFor(
              input_.cameras[camera].model, observation.pixel, pixel_sigma),
          loss,
          poses_[observation.image].data(),
          quaternion_,
          t_xy_,
          &t_z_,
          points_[observation.point].data(),
          params_[camera].data());
      residual_blocks_.push_back(id);
      cluster_of_block_.push_back(observation.point);
    }
    for (size_t l = 0; l < input_.links.size(); ++l) {
      const OdometryLink& link = input_.links[l];
      Eigen::Matrix3d w;
      SqrtInformation(link.covariance, &w);
      w /= std::sqrt(odometry_factor_);
      ceres::ResidualBlockId id = nullptr;
      if (input_.systematics) {
        id = problem_->AddResidualBlock(
            new ceres::
                AutoDiffCostFunction<SystematicOdometryLinkCost, 3, 3, 3, 3, 1>(
                    new SystematicOdometryLinkCost(
                        *link.samples,
                        w,
                        input_.systematics->intrinsics.wheel_track_m)),
            nullptr,
            poses_[link.image_i].data(),
            poses_[link.image_j].data(),
            intrinsics_,
            &offset_change_s_);
      } else {
        id = problem_->AddResidualBlock(
            new ceres::AutoDiffCostFunction<OdometryLinkCost, 3, 3, 3>(
                new OdometryLinkCost(link.odom_i_from_odom_j, w)),
            nullptr,
            poses_[link.image_i].data(),
            poses_[link.image_j].data());
      }
      // Each link a cluster of its own.
      residual_blocks_.push_back(id);
      cluster_of_block_.push_back(static_cast<int>(input_.points.size() + l));
    }
    if (input_.systematics) {
      const JointSystematics& systematics = *input_.systematics;
      std::vector<int> held;
      for (int k = 0; k < 3; ++k) {
        if (!systematics.refine_intrinsics[k]) held.push_back(k);
      }
      if (held.size() == 3) {
        problem_->SetParameterBlockConstant(intrinsics_);
      } else if (!held.empty()) {
        intrinsics_manifold_ = std::make_unique<ceres::SubsetManifold>(3, held);
        problem_->SetManifold(intrinsics_, intrinsics_manifold_.get());
      }
      if (!systematics.refine_time_offset) {
        problem_->SetParameterBlockConstant(&offset_change_s_);
      }
    }
    if (problem_->HasParameterBlock(quaternion_)) {
      problem_->SetManifold(quaternion_, &quaternion_manifold_);
      problem_->SetParameterBlockConstant(&t_z_);
    }
    for (size_t i = 0; i < poses_.size(); ++i) {
      if (held_[i] && problem_->HasParameterBlock(poses_[i].data())) {
        problem_->SetParameterBlockConstant(poses_[i].data());
      }
    }
    for (auto& params : params_) {
      if (!options_.refine_intrinsics &&
          problem_->HasParameterBlock(params.data())) {
        problem_->SetParameterBlockConstant(params.data());
      }
    }
  }

  ceres::Solver::Summary Solve(int pass,
                               std::chrono::steady_clock::time_point start) {
    ceres::Solver::Options solver_options;
    ProgressCallback progress(options_.progress, pass, start);
    if (options_.progress) solver_options.callbacks.push_back(&progress);
    solver_options.linear_solver_type = ceres::SPARSE_SCHUR;
    std::string error;
    if (!solver_options.IsValid(&error)) {
      solver_options.linear_solver_type = ceres::ITERATIVE_SCHUR;
      solver_options.preconditioner_type = ceres::SCHUR_JACOBI;
    }
    solver_options.max_num_iterations = options_.max_num_iterations;
    solver_options.num_threads = options_.num_threads;
    solver_options.logging_type = ceres::SILENT;
    solver_options.minimizer_progress_to_stdout = false;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, problem_.get(), &summary);
    return summary;
  }

  // Reprojection residual of observation k at the current values, pixels;
  // false when the point is behind the camera.
  bool ReprojectionResidual(size_t k, Eigen::Vector2d* residual) const {
    const JointObservation& observation = input_.observations[k];
    const int camera = input_.images[observation.image].camera;
    const double* parameters[] = {poses_[observation.image].data(),
                                  quaternion_,
                                  t_xy_,
                                  &t_z_,
                                  points_[observation.point].data(),
                                  params_[camera].data()};
    return ReprojectionResidualFor(input_.cameras[camera].model,
                                   observation.pixel,
                                   parameters,
                                   residual->data());
  }

  // Estimates the pixel sigma from the observations in use (a robust scale,
  // then the inliers' mean square over their degrees of freedom), marks
  // those beyond max_sigmas unused, and returns the RMS of the inliers.
  struct PixelStatistics {
    double sigma = 0.0;
    double rms = 0.0;
    int num_inliers = 0;
    int num_marked = 0;  // observations newly left out
  };
  PixelStatistics UpdatePixelSigma(double max_sigmas, bool mark_outliers) {
    std::vector<double> norms(input_.observations.size(), -1.0);
    std::vector<double> used_norms;
    for (size_t k = 0; k < input_.observations.size(); ++k) {
      if (!used_[k] || !seen_twice_[input_.observations[k].point]) continue;
      Eigen::Vector2d residual;
      if (!ReprojectionResidual(k, &residual)) continue;
      norms[k] = residual.norm();
      used_norms.push_back(norms[k]);
    }
    PixelStatistics statistics;
    if (used_norms.empty()) return statistics;
    std::nth_element(used_norms.begin(),
                     used_norms.begin() + used_norms.size() / 2,
                     used_norms.end());
    // The median of a 2D Gaussian residual's norm is sigma sqrt(2 ln 2).
    const double robust_sigma =
        used_norms[used_norms.size() / 2] / std::sqrt(2.0 * std::log(2.0));
    const double threshold = max_sigmas * robust_sigma;
    double sum_squares = 0.0;
    std::vector<char> point_seen(input_.points.size(), 0);
    int num_points = 0;
    for (size_t k = 0; k < norms.size(); ++k) {
      if (!used_[k] || !seen_twice_[input_.observations[k].point]) continue;
      if (norms[k] < 0.0 || norms[k] > threshold) {
        if (mark_outliers) {
          used_[k] = 0;
          ++statistics.num_marked;
        }
        continue;
      }
      sum_squares += norms[k] * norms[k];
      ++statistics.num_inliers;
      const int point = input_.observations[k].point;
      if (!point_seen[point]) {
        point_seen[point] = 1;
        ++num_points;
      }
    }
    if (statistics.num_inliers == 0) return statistics;
    statistics.rms = std::sqrt(sum_squares / (2.0 * statistics.num_inliers));
    // Each point takes 3 of its observations' degrees of freedom, each free
    // pose 3 (the odometry's share of the poses is small beside the
    // images').
    int num_free_poses = 0;
    for (const char held : held_) num_free_poses += held ? 0 : 1;
    const double dof = 2.0 * statistics.num_inliers - 3.0 * num_points -
                       3.0 * num_free_poses - 5.0;
    statistics.sigma =
        dof > 0.0 ? std::sqrt(sum_squares / dof) : statistics.rms;
    return statistics;
  }

  // The odometry's variance factor against the links' covariances: their
  // whitened sum of squares over its degrees of freedom, 3 per link less
  // what the odometry alone determines (the metric scale, and the
  // extrinsic's yaw and x/y in part: 3 in all). Held (1) below 30 degrees
  // of freedom, within [kMinOdometryFactor, kMaxOdometryFactor].
  static constexpr double kMinOdometryFactor = 0.01;
  static constexpr double kMaxOdometryFactor = 100.0;
  double EstimateOdometryFactor() {
    const double dof = 3.0 * static_cast<double>(input_.links.size()) - 3.0;
    constexpr double kMinDof = 30.0;
    if (dof < kMinDof) return odometry_factor_;
    const double rms = OdometryRms();
    const double sum =
        rms * rms * 3.0 * static_cast<double>(input_.links.size());
    odometry_factor_ =
        std::clamp(sum / dof, kMinOdometryFactor, kMaxOdometryFactor);
    return odometry_factor_;
  }

  double OdometryFactor() const { return odometry_factor_; }

  double OdometryRms() const {
    double sum = 0.0;
    for (const OdometryLink& link : input_.links) {
      Eigen::Matrix3d w;
      SqrtInformation(link.covariance, &w);
      Eigen::Vector3d residual;
      if (input_.systematics) {
        const SystematicOdometryLinkCost cost(
            *link.samples, w, input_.systematics->intrinsics.wheel_track_m);
        cost(poses_[link.image_i].data(),
             poses_[link.image_j].data(),
             intrinsics_,
             &offset_change_s_,
             residual.data());
      } else {
        const OdometryLinkCost cost(link.odom_i_from_odom_j, w);
        cost(poses_[link.image_i].data(),
             poses_[link.image_j].data(),
             residual.data());
      }
      sum += residual.squaredNorm();
    }
    return std::sqrt(sum / (3.0 * input_.links.size()));
  }

  // Marginal covariance of [rotation (3), t_xy (2)] (see the header), and
  // the standard deviations of the refined systematics.
  bool ExtrinsicCovariance(JointAdjustmentResult* result) {
    std::vector<double*> blocks = {quaternion_, t_xy_};
    const auto free = [&](double* block) {
      return problem_->HasParameterBlock(block) &&
             !problem_->IsParameterBlockConstant(block);
    };
    // After the extrinsic: the offset's change, then the free intrinsics.
    int num_wanted = 5;
    const bool offset_free = free(&offset_change_s_);
    if (offset_free) {
      blocks.push_back(&offset_change_s_);
      ++num_wanted;
    }
    const bool intrinsics_free = free(intrinsics_);
    if (intrinsics_free) {
      blocks.push_back(intrinsics_);
      num_wanted += problem_->ParameterBlockTangentSize(intrinsics_);
    }
    std::vector<double*> others;
    problem_->GetParameterBlocks(&others);
    for (double* block : others) {
      if (block == quaternion_ || block == t_xy_ ||
          block == &offset_change_s_ || block == intrinsics_) {
        continue;
      }
      if (problem_->IsParameterBlockConstant(block)) continue;
      blocks.push_back(block);
    }
    ceres::Problem::EvaluateOptions evaluate_options;
    evaluate_options.parameter_blocks = blocks;
    evaluate_options.residual_blocks = residual_blocks_;
    evaluate_options.apply_loss_function = true;
    evaluate_options.num_threads = options_.num_threads;
    ceres::CRSMatrix jacobian;
    std::vector<double> residuals;
    if (!problem_->Evaluate(
            evaluate_options, nullptr, &residuals, nullptr, &jacobian)) {
      return false;
    }
    std::vector<int> cluster_of_row;
    cluster_of_row.reserve(residuals.size());
    for (size_t b = 0; b < residual_blocks_.size(); ++b) {
      const int size =
          problem_->GetCostFunctionForResidualBlock(residual_blocks_[b])
              ->num_residuals();
      cluster_of_row.insert(cluster_of_row.end(), size, cluster_of_block_[b]);
    }
    // Ceres' compressed rows (sorted columns) read in place.
    const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> sparse(
        jacobian.num_rows,
        jacobian.num_cols,
        static_cast<Eigen::Index>(jacobian.values.size()),
        jacobian.rows.data(),
        jacobian.cols.data(),
        jacobian.values.data());
    LeadingCovariances covariances;
    if (!LeadingCovariancesOf(
            sparse,
            Eigen::Map<const Eigen::VectorXd>(
                residuals.data(), static_cast<Eigen::Index>(residuals.size())),
            cluster_of_row,
            num_wanted,
            &covariances)) {
      return false;
    }
    // Widened per unknown to the cluster-robust standard deviation where
    // that is larger (correlated errors along tracks), never narrowed.
    Eigen::VectorXd widening(num_wanted);
    for (int k = 0; k < num_wanted; ++k) {
      widening[k] = std::max(
          1.0, std::sqrt(covariances.robust(k, k) / covariances.model(k, k)));
    }
    const Eigen::MatrixXd leading =
        widening.asDiagonal() * covariances.model * widening.asDiagonal();
    result->covariance_widening = widening.head<5>();
    // Ceres' quaternion tangent delta is half the rotation vector.
    Eigen::Matrix<double, 5, 5> to_reported =
        Eigen::Matrix<double, 5, 5>::Identity();
    to_reported.topLeftCorner<3, 3>() *= 2.0;
    result->covariance =
        to_reported * leading.topLeftCorner<5, 5>() * to_reported.transpose();
    int row = 5;
    if (offset_free) {
      result->time_offset_change_stddev_s = std::sqrt(leading(row, row));
      ++row;
    }
    if (intrinsics_free) {
      // The subset manifold's tangent lists the free intrinsics in order.
      for (int k = 0; k < 3; ++k) {
        if (!input_.systematics->refine_intrinsics[k]) continue;
        result->intrinsics_stddev[k] = std::sqrt(leading(row, row));
        ++row;
      }
    }
    return true;
  }

  void WriteResult(JointAdjustmentResult* result) const {
    Eigen::Quaterniond q;
    q.coeffs() << quaternion_[0], quaternion_[1], quaternion_[2],
        quaternion_[3];
    result->odom_from_cam.rotation = q.normalized();
    result->odom_from_cam.translation =
        Eigen::Vector3d(t_xy_[0], t_xy_[1], t_z_);
    result->origin_from_odom.clear();
    for (const auto& pose : poses_) {
      result->origin_from_odom.push_back({pose[0], pose[1], pose[2]});
    }
    result->points = points_;
    result->cameras = input_.cameras;
    for (size_t c = 0; c < params_.size(); ++c) {
      result->cameras[c].params = params_[c];
    }
    result->num_components = num_components_;
    if (input_.systematics) {
      result->intrinsics = input_.systematics->intrinsics;
      result->intrinsics.yaw_scale = intrinsics_[0];
      result->intrinsics.yaw_per_metre_rad = intrinsics_[1];
      result->intrinsics.yaw_rate_bias_rad_s = intrinsics_[2];
      result->time_offset_change_s = offset_change_s_;
    }
    result->observation_error_px.assign(input_.observations.size(), -1.0);
    for (size_t k = 0; k < input_.observations.size(); ++k) {
      if (!used_[k] || !seen_twice_[input_.observations[k].point]) continue;
      Eigen::Vector2d residual;
      if (ReprojectionResidual(k, &residual)) {
        result->observation_error_px[k] = residual.norm();
      }
    }
  }

  int NumPointsSeenTwice() const {
    return static_cast<int>(
        std::count(seen_twice_.begin(), seen_twice_.end(), 1));
  }

  int NumUnused() const {
    return static_cast<int>(std::count(used_.begin(), used_.end(), 0));
  }

 private:
  const JointAdjustmentProblem& input_;
  const JointAdjustmentOptions& options_;
  std::vector<std::array<double, 3>> poses_;
  std::vector<Eigen::Vector3d> points_;
  std::vector<std::vector<double>> params_;
  double quaternion_[4] = {0.0, 0.0, 0.0, 1.0};
  double t_xy_[2] = {0.0, 0.0};
  double t_z_ = 0.0;
  double odometry_factor_ = 1.0;  // variance factor on the links
  // The odometry's systematics (JointAdjustmentProblem::systematics).
  double intrinsics_[3] = {1.0, 0.0, 0.0};
  double offset_change_s_ = 0.0;
  std::unique_ptr<ceres::SubsetManifold> intrinsics_manifold_;
  std::vector<char> used_;
  std::vector<char> seen_twice_;  // per point, among the used observations
  // The residual blocks of the built problem and their clusters (the
  // observations of a point, or one link), for the robust covariance.
  std::vector<ceres::ResidualBlockId> residual_blocks_;
  std::vector<int> cluster_of_block_;
  std::vector<char> held_;
  int num_components_ = 0;
  std::unique_ptr<ceres::Problem> problem_;
  ceres::EigenQuaternionManifold quaternion_manifold_;
};

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

void JointAdjustmentOptions::Check() const {
  const auto positive = [](double value, const char* name) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(std::string(name) + " must be positive");
    }
  };
  positive(pixel_sigma, "pixel_sigma");
  positive(loss_scale, "loss_scale");
  positive(max_reprojection_sigmas, "max_reprojection_sigmas");
  if (max_num_iterations < 1) {
    throw std::invalid_argument("max_num_iterations must be at least 1");
  }
  if (num_threads < 1) {
    throw std::invalid_argument("num_threads must be at least 1");
  }
}

const char* ToString(JointAdjustmentStatus status) {
  switch (status) {
    case JointAdjustmentStatus::kSuccess:
      return "success";
    case JointAdjustmentStatus::kInvalidInput:
      return "invalid_input";
    case JointAdjustmentStatus::kNoConvergence:
      return "no_convergence";
    case JointAdjustmentStatus::kSingular:
      return "singular";
  }
  return "unknown";
}

JointAdjustmentResult AdjustJointly(const JointAdjustmentProblem& problem,
                                    const JointAdjustmentOptions& options) {
  options.Check();
  JointAdjustmentResult result;
  if (const std::string why = CheckProblem(problem); !why.empty()) {
    result.message = why;
    return result;
  }
  const auto start = std::chrono::steady_clock::now();
  JointProblem joint(problem, options);
  if (const std::string why = joint.FindGauge(); !why.empty()) {
    result.message = why;
    return result;
  }
  if (joint.NumPointsSeenTwice() == 0) {
    result.message = "no point is seen in two images";
    return result;
  }
  // Pass 0 measures the start; each pass estimates the pixel sigma (and the
  // odometry's level) from its solution and drops the outliers for the
  // next.
  double pixel_sigma = options.pixel_sigma;
  const auto before =
      joint.UpdatePixelSigma(std::numeric_limits<double>::infinity(), false);
  result.reprojection_rms_px_before = before.rms;
  result.odometry_rms_sigma_before = joint.OdometryRms();
  constexpr int kMaxPasses = 4;
  constexpr double kSigmaTolerance = 0.05;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    joint.Build(pixel_sigma);
    const ceres::Solver::Summary summary = joint.Solve(pass + 1, start);
    result.num_iterations += static_cast<int>(summary.iterations.size());
    if (summary.termination_type != ceres::CONVERGENCE) {
      result.status = JointAdjustmentStatus::kNoConvergence;
      result.message = summary.message;
      joint.WriteResult(&result);
      result.solve_time_s = SecondsSince(start);
      return result;
    }
    const bool last = pass + 1 == kMaxPasses;
    const auto statistics =
        joint.UpdatePixelSigma(options.max_reprojection_sigmas, !last);
    if (!(statistics.sigma > 0.0)) {
      result.status = JointAdjustmentStatus::kInvalidInput;
      result.message = "no observation fits its projection";
      return result;
    }
    result.reprojection_rms_px_after = statistics.rms;
    result.num_observations_used = statistics.num_inliers;
    double change = std::abs(statistics.sigma / pixel_sigma - 1.0);
    pixel_sigma = statistics.sigma;
    if (options.estimate_odometry_noise) {
      const double factor = joint.OdometryFactor();
      change = std::max(
          change,
          std::abs(std::sqrt(joint.EstimateOdometryFactor() / factor) - 1.0));
    }
    if (change < kSigmaTolerance && statistics.num_marked == 0) break;
  }
  // The final problem at the estimated sigma, for the covariance.
  joint.Build(pixel_sigma);
  result.pixel_sigma = pixel_sigma;
  result.odometry_sigma_ratio = std::sqrt(joint.OdometryFactor());
  result.num_observations_left_out = joint.NumUnused();
  result.odometry_rms_sigma_after = joint.OdometryRms();
  joint.WriteResult(&result);
  result.solve_time_s = SecondsSince(start);
  if (!options.compute_covariance) {
    result.status = JointAdjustmentStatus::kSuccess;
    return result;
  }
  const auto covariance_start = std::chrono::steady_clock::now();
  if (!joint.ExtrinsicCovariance(&result)) {
    result.status = JointAdjustmentStatus::kSingular;
    result.message =
        "the information matrix is singular: the images and the odometry "
        "do not determine every unknown";
    return result;
  }
  result.covariance_time_s = SecondsSince(covariance_start);
  result.status = JointAdjustmentStatus::kSuccess;
  return result;
}

}  // namespace odomcal
