// JointProblem's parameters, gauge, Ceres problem, solve and result
// (joint_adjustment_internal.h).
#include "odomcal/solver/angles.h"
#include "odomcal/solver/camera_intrinsics_manifold.h"
#include "odomcal/solver/joint_adjustment_cost.h"
#include "odomcal/solver/joint_adjustment_internal.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace odomcal::internal {
namespace {

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

}  // namespace

JointProblem::JointProblem(const JointAdjustmentProblem& input,
                           const JointAdjustmentOptions& options)
    : input_(input),
      options_(options),
      tilted_(input.motion_model != RobotMotionModel::kPlanar),
      se3_(input.motion_model == RobotMotionModel::kSE3),
      on_ground_(input.motion_model == RobotMotionModel::kOnGround),
      ground_rate_(options.ground_tilt_rate_deg_per_m * kDegToRad) {
  poses_.reserve(input.images.size());
  tilts_.reserve(input.images.size());
  for (const JointImage& image : input.images) {
    // A 3-D log's poses start whole; level poses and a planar log's start
    // level (the planar part of the start), the tilts found by the solve.
    if (se3_) {
      // origin_from_odom = (x, y, z), Rz(yaw) Ry(pitch) Rx(roll).
      const Eigen::Matrix3d r =
          image.origin_from_odom.rotation.normalized().toRotationMatrix();
      const Eigen::Vector3d& t = image.origin_from_odom.translation;
      poses_.push_back({t.x(), t.y(), std::atan2(r(1, 0), r(0, 0))});
      tilts_.push_back({t.z(),
                        std::atan2(r(2, 1), r(2, 2)),
                        std::asin(std::clamp(-r(2, 0), -1.0, 1.0))});
    } else {
      const PlanarPose planar = PlanarFromRigid(image.origin_from_odom);
      poses_.push_back({planar.x, planar.y, planar.yaw_rad});
      tilts_.push_back({0.0, 0.0, 0.0});
    }
  }
  points_ = input.points;
  for (const JointCamera& camera : input.cameras) {
    params_.push_back(camera.params);
  }
  mounts_.resize(1 + input.other_mounts.size());
  for (size_t m = 0; m < mounts_.size(); ++m) {
    const Rigid3d& start =
        m == 0 ? input.odom_from_cam : input.other_mounts[m - 1];
    const Eigen::Quaterniond q = start.rotation.normalized();
    for (int k = 0; k < 4; ++k) mounts_[m].quaternion[k] = q.coeffs()[k];
    mounts_[m].t_xy[0] = start.translation.x();
    mounts_[m].t_xy[1] = start.translation.y();
    mounts_[m].t_z = start.translation.z();
  }
  used_.assign(input.observations.size(), 1);
  // A point on or behind a camera that sees it cannot be projected: the
  // observation is left out from the start (Ceres would stop at it).
  for (size_t k = 0; k < input.observations.size(); ++k) {
    Eigen::Vector2d residual;
    if (!ReprojectionResidual(k, &residual)) used_[k] = 0;
  }
  start_rays_.reserve(input.observations.size());
  for (const JointObservation& observation : input.observations) {
    const JointImage& image = input.images[observation.image];
    const Rigid3d& odom_from_cam = image.mount == 0
                                       ? input.odom_from_cam
                                       : input.other_mounts[image.mount - 1];
    const Eigen::Vector3d center =
        PoseOf(observation.image) * odom_from_cam.translation;
    const Eigen::Vector3d ray = input.points[observation.point] - center;
    const double norm = ray.norm();
    start_rays_.push_back(norm > 0.0 ? Eigen::Vector3d(ray / norm)
                                     : Eigen::Vector3d::Zero());
  }
  FindDeterminedPoints();
  if (input.systematics) {
    const OdometryIntrinsics& start = input.systematics->intrinsics;
    intrinsics_[0] = start.yaw_scale;
    intrinsics_[1] = start.yaw_per_metre_rad;
    intrinsics_[2] = start.yaw_rate_bias_rad_s;
    offset_change_s_ = input.systematics->time_offset_change_s;
  }
}

std::string JointProblem::FindGauge() {
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

void JointProblem::FindDeterminedPoints() {
  // Rays meet at >= the angle when their dot product is <= its cosine.
  const double max_cosine =
      std::cos(options_.min_triangulation_angle_deg * kDegToRad);
  std::vector<std::vector<size_t>> observations_of_point(input_.points.size());
  for (size_t k = 0; k < input_.observations.size(); ++k) {
    if (used_[k])
      observations_of_point[input_.observations[k].point].push_back(k);
  }
  determined_.assign(input_.points.size(), 0);
  for (size_t p = 0; p < observations_of_point.size(); ++p) {
    const std::vector<size_t>& track = observations_of_point[p];
    for (size_t a = 0; a < track.size() && !determined_[p]; ++a) {
      const JointObservation& first = input_.observations[track[a]];
      for (size_t b = a + 1; b < track.size(); ++b) {
        const JointObservation& second = input_.observations[track[b]];
        if (first.image != second.image &&
            start_rays_[track[a]].dot(start_rays_[track[b]]) <= max_cosine) {
          determined_[p] = 1;
          break;
        }
      }
    }
  }
}

void JointProblem::Build(double pixel_sigma) {
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_ = std::make_unique<ceres::Problem>(problem_options);
  residual_blocks_.clear();
  cluster_of_block_.clear();
  FindDeterminedPoints();
  for (size_t k = 0; k < input_.observations.size(); ++k) {
    if (!used_[k] || !determined_[input_.observations[k].point]) continue;
    const JointObservation& observation = input_.observations[k];
    const JointImage& image = input_.images[observation.image];
    const int camera = image.camera;
    Mount& mount = mounts_[image.mount];
    ceres::LossFunction* loss = nullptr;
    if (options_.loss == RobustLoss::kHuber) {
      loss = new ceres::HuberLoss(options_.loss_scale);
    } else if (options_.loss == RobustLoss::kCauchy) {
      loss = new ceres::CauchyLoss(options_.loss_scale);
    }
    std::vector<double*> blocks = {poses_[observation.image].data()};
    if (tilted_) blocks.push_back(tilts_[observation.image].data());
    blocks.insert(blocks.end(),
                  {mount.quaternion,
                   mount.t_xy,
                   &mount.t_z,
                   points_[observation.point].data(),
                   params_[camera].data()});
    const ceres::ResidualBlockId id = problem_->AddResidualBlock(
        ReprojectionCostFor(input_.cameras[camera].model,
                            tilted_,
                            observation.pixel,
                            pixel_sigma),
        loss,
        blocks);
    residual_blocks_.push_back(id);
    cluster_of_block_.push_back(observation.point);
  }
  for (size_t l = 0; l < input_.links.size(); ++l) {
    const OdometryLink& link = input_.links[l];
    ceres::ResidualBlockId id = nullptr;
    // The planar links' whitening (the SE(3) ones have their own).
    Eigen::Matrix3d w = Eigen::Matrix3d::Zero();
    if (!se3_) {
      SqrtInformation(link.covariance, &w);
      w /= std::sqrt(odometry_factor_);
    }
    if (se3_) {
      Eigen::Matrix<double, 6, 6> w6;
      SqrtInformation(link.motion_3d->covariance, &w6);
      w6 /= std::sqrt(odometry_factor_);
      id = problem_->AddResidualBlock(
          new ceres::AutoDiffCostFunction<Se3OdometryLinkCost, 6, 3, 3, 3, 3>(
              new Se3OdometryLinkCost(link.motion_3d->odom_i_from_odom_j, w6)),
          nullptr,
          poses_[link.image_i].data(),
          tilts_[link.image_i].data(),
          poses_[link.image_j].data(),
          tilts_[link.image_j].data());
    } else if (on_ground_) {
      const double length =
          std::hypot(link.odom_i_from_odom_j.x, link.odom_i_from_odom_j.y);
      const GroundBounds bounds = GroundBoundsOf(ground_rate_, length);
      if (input_.systematics) {
        id = problem_->AddResidualBlock(
            new ceres::AutoDiffCostFunction<GroundSystematicOdometryLinkCost,
                                            6,
                                            3,
                                            3,
                                            3,
                                            3,
                                            3,
                                            1>(
                new GroundSystematicOdometryLinkCost(
                    *link.samples,
                    w,
                    bounds,
                    input_.systematics->intrinsics.wheel_track_m)),
            nullptr,
            {poses_[link.image_i].data(),
             tilts_[link.image_i].data(),
             poses_[link.image_j].data(),
             tilts_[link.image_j].data(),
             intrinsics_,
             &offset_change_s_});
      } else {
        id = problem_->AddResidualBlock(
            new ceres::
                AutoDiffCostFunction<GroundOdometryLinkCost, 6, 3, 3, 3, 3>(
                    new GroundOdometryLinkCost(
                        link.odom_i_from_odom_j, w, bounds)),
            nullptr,
            poses_[link.image_i].data(),
            tilts_[link.image_i].data(),
            poses_[link.image_j].data(),
            tilts_[link.image_j].data());
      }
    } else if (input_.systematics) {
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
  for (Mount& mount : mounts_) {
    if (problem_->HasParameterBlock(mount.quaternion)) {
      problem_->SetManifold(mount.quaternion, &quaternion_manifold_);
      problem_->SetParameterBlockConstant(&mount.t_z);
    }
  }
  for (size_t i = 0; i < poses_.size(); ++i) {
    if (!held_[i]) continue;
    if (problem_->HasParameterBlock(poses_[i].data())) {
      problem_->SetParameterBlockConstant(poses_[i].data());
    }
    if (tilted_ && problem_->HasParameterBlock(tilts_[i].data())) {
      problem_->SetParameterBlockConstant(tilts_[i].data());
    }
  }
  params_manifolds_.clear();
  for (size_t c = 0; c < params_.size(); ++c) {
    double* params = params_[c].data();
    if (!problem_->HasParameterBlock(params)) continue;
    if (!options_.refine_intrinsics || input_.cameras[c].held) {
      problem_->SetParameterBlockConstant(params);
      continue;
    }
    params_manifolds_.push_back(
        std::make_unique<CameraIntrinsicsManifold>(input_.cameras[c].model));
    problem_->SetManifold(params, params_manifolds_.back().get());
  }
}

ceres::Solver::Summary JointProblem::Solve(
    int pass, std::chrono::steady_clock::time_point start) {
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

bool JointProblem::ReprojectionResidual(size_t k,
                                        Eigen::Vector2d* residual) const {
  const JointObservation& observation = input_.observations[k];
  const JointImage& image = input_.images[observation.image];
  const int camera = image.camera;
  const Mount& mount = mounts_[image.mount];
  // In ReprojectionCost's order, the tilt after the pose when tilted.
  std::array<const double*, 7> parameters{};
  size_t n = 0;
  parameters[n++] = poses_[observation.image].data();
  if (tilted_) parameters[n++] = tilts_[observation.image].data();
  parameters[n++] = mount.quaternion;
  parameters[n++] = mount.t_xy;
  parameters[n++] = &mount.t_z;
  parameters[n++] = points_[observation.point].data();
  parameters[n] = params_[camera].data();
  return ReprojectionResidualFor(input_.cameras[camera].model,
                                 tilted_,
                                 observation.pixel,
                                 parameters.data(),
                                 residual->data());
}

Rigid3d JointProblem::PoseOf(size_t i) const {
  const std::array<double, 3>& pose = poses_[i];
  const std::array<double, 3>& tilt = tilts_[i];
  const Eigen::Matrix3d rotation =
      OriginFromOdomRotation(pose.data(), tilt.data());
  return {Eigen::Quaterniond(rotation), {pose[0], pose[1], tilt[0]}};
}

void JointProblem::WriteResult(JointAdjustmentResult* result) const {
  const auto odom_from_cam = [](const Mount& mount) {
    Eigen::Quaterniond q;
    q.coeffs() << mount.quaternion[0], mount.quaternion[1], mount.quaternion[2],
        mount.quaternion[3];
    return Rigid3d{q.normalized(),
                   Eigen::Vector3d(mount.t_xy[0], mount.t_xy[1], mount.t_z)};
  };
  result->odom_from_cam = odom_from_cam(mounts_[0]);
  result->other_mounts.clear();
  for (size_t m = 1; m < mounts_.size(); ++m) {
    result->other_mounts.push_back(odom_from_cam(mounts_[m]));
  }
  result->motion_model = input_.motion_model;
  result->origin_from_odom.clear();
  result->max_robot_tilt_deg = 0.0;
  for (size_t i = 0; i < poses_.size(); ++i) {
    result->origin_from_odom.push_back(PoseOf(i));
    const double up =
        (result->origin_from_odom.back().rotation * Eigen::Vector3d::UnitZ())
            .z();
    result->max_robot_tilt_deg =
        std::max(result->max_robot_tilt_deg,
                 std::acos(std::clamp(up, -1.0, 1.0)) / kDegToRad);
  }
  if (on_ground_) result->ground_tilt_rate_deg_per_m = ground_rate_ / kDegToRad;
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
    if (!used_[k] || !determined_[input_.observations[k].point]) continue;
    Eigen::Vector2d residual;
    if (ReprojectionResidual(k, &residual)) {
      result->observation_error_px[k] = residual.norm();
    }
  }
}

}  // namespace odomcal::internal
