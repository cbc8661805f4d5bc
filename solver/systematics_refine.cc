// Ceres problem over [q (4, EigenQuaternionManifold), p_xy (2), log s_k (1),
// p_z (1, constant), d (1), intrinsics (3, SubsetManifold for held ones)]; one
// 6-dimensional residual per pair as in hand_eye_cost.h, with the odometry
// motion computed from the pair's samples (planar odometry) or shifted by its
// endpoint twists (3-D odometry, whose intrinsics are held). The information
// is mapped from Ceres' tangent coordinates like hand_eye_refine.cc does.

#include "odomcal/solver/systematics_refine.h"

#include "odomcal/solver/format_number.h"
#include "odomcal/solver/hand_eye_cost.h"
#include "odomcal/solver/hand_eye_residual.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <cmath>
#include <limits>
#include <map>
#include <memory>

namespace odomcal {

const std::array<const char*, kNumSystematics> kSystematicsNames = {
    "camera_time_offset_s",
    "yaw_scale",
    "yaw_per_metre_rad",
    "yaw_rate_bias_rad_s"};

namespace {

// The whitened hand-eye residual (hand_eye_cost.h) of odometry motion
// (q_a, t_a) at the problem's extrinsic and scale parameters; false where
// it is not finite (ResidualsFinite).
template <typename T>
bool WhitenedResidual(const Eigen::Quaternion<T>& q_a,
                      const Eigen::Matrix<T, 3, 1>& t_a,
                      const T* q_xyzw,
                      const T* p_xy,
                      const T* log_scale,
                      const T* p_z,
                      const Eigen::Quaterniond& q_b,
                      const Eigen::Vector3d& t_b,
                      const Matrix6d& sqrt_information,
                      T* residuals) {
  using std::exp;
  const Eigen::Map<const Eigen::Quaternion<T>> q(q_xyzw);
  const Eigen::Matrix<T, 3, 1> p(p_xy[0], p_xy[1], p_z[0]);
  const T scale = exp(log_scale[0]);
  const Eigen::Quaternion<T> error =
      q_a.conjugate() * q * q_b.cast<T>() * q.conjugate();
  const T error_wxyz[4] = {error.w(), error.x(), error.y(), error.z()};
  Eigen::Matrix<T, 6, 1> raw;
  ceres::QuaternionToAngleAxis(error_wxyz, raw.data());
  raw.template tail<3>() = q_a * p + t_a - scale * (q * t_b.cast<T>()) - p;
  Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residuals);
  out = sqrt_information.cast<T>() * raw;
  return ResidualsFinite<T, 6>(out);
}

// Exp of the twist d xi (SE(3)): the rotation from its angle-axis, the
// translation V(w) v with V = I + b [w]x + c [w]x^2, b = (1 - cos th) / th^2,
// c = (th - sin th) / th^3 (their series below th^2 = 1e-8, which also keeps
// the derivative at d = 0 finite).
template <typename T>
void TwistExp(const Eigen::Matrix<double, 6, 1>& xi,
              const T& d,
              Eigen::Quaternion<T>* rotation,
              Eigen::Matrix<T, 3, 1>* translation) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const Eigen::Matrix<T, 3, 1> w = xi.head<3>().cast<T>() * d;
  const Eigen::Matrix<T, 3, 1> v = xi.tail<3>().cast<T>() * d;
  const T angle_axis[3] = {w(0), w(1), w(2)};
  T wxyz[4];
  ceres::AngleAxisToQuaternion(angle_axis, wxyz);
  *rotation = Eigen::Quaternion<T>(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
  const T theta2 = w.squaredNorm();
  T b, c;
  if (theta2 < 1e-8) {
    b = T(0.5) - theta2 / 24.0;
    c = T(1.0 / 6.0) - theta2 / 120.0;
  } else {
    const T theta = sqrt(theta2);
    b = (T(1.0) - cos(theta)) / theta2;
    c = (theta - sin(theta)) / (theta2 * theta);
  }
  const Eigen::Matrix<T, 3, 1> wv = w.cross(v);
  *translation = v + b * wv + c * w.cross(wv);
}

// 3-D odometry: the logged motion A moved to a clock offset changed by d
// through its endpoint twists, Exp(-d xi_i) A Exp(d xi_j) (first order in
// d, as the planar re-integration). The intrinsics block is unused: they are
// held for 3-D odometry.
class Se3OffsetCost {
 public:
  Se3OffsetCost(const MotionPair& pair, const Matrix6d& sqrt_information)
      : q_a_(pair.odom_i_from_odom_j.rotation),
        t_a_(pair.odom_i_from_odom_j.translation),
        twists_(*pair.odometry_twists),
        q_b_(pair.cam_i_from_cam_j.rotation),
        t_b_(pair.cam_i_from_cam_j.translation),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* q_xyzw,
                  const T* p_xy,
                  const T* log_scale,
                  const T* p_z,
                  const T* offset_change,
                  const T* /*intrinsics*/,
                  T* residuals) const {
    Eigen::Quaternion<T> q_i, q_j;
    Eigen::Matrix<T, 3, 1> t_i, t_j;
    TwistExp(twists_.at_i, T(-offset_change[0]), &q_i, &t_i);
    TwistExp(twists_.at_j, offset_change[0], &q_j, &t_j);
    const Eigen::Quaternion<T> q_logged = q_a_.cast<T>();
    const Eigen::Quaternion<T> q_a = q_i * q_logged * q_j;
    const Eigen::Matrix<T, 3, 1> t_a =
        t_i + q_i * (t_a_.cast<T>() + q_logged * t_j);
    return WhitenedResidual(q_a,
                            t_a,
                            q_xyzw,
                            p_xy,
                            log_scale,
                            p_z,
                            q_b_,
                            t_b_,
                            sqrt_information_,
                            residuals);
  }

 private:
  Eigen::Quaterniond q_a_;
  Eigen::Vector3d t_a_;
  OdometryEndpointTwists twists_;
  Eigen::Quaterniond q_b_;
  Eigen::Vector3d t_b_;
  Matrix6d sqrt_information_;
};

class SystematicsCost {
 public:
  SystematicsCost(const MotionPair& pair,
                  const Matrix6d& sqrt_information,
                  double wheel_track_m)
      : samples_(*pair.odometry_samples),
        wheel_track_m_(wheel_track_m),
        z_a_(pair.odom_i_from_odom_j.translation.z()),
        q_b_(pair.cam_i_from_cam_j.rotation),
        t_b_(pair.cam_i_from_cam_j.translation),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* q_xyzw,
                  const T* p_xy,
                  const T* log_scale,
                  const T* p_z,
                  const T* offset_change,
                  const T* intrinsics,
                  T* residuals) const {
    using std::cos;
    using std::sin;
    const PlanarMotion<T> a = CorrectedOdometryMotion(
        samples_, intrinsics, offset_change[0], wheel_track_m_);
    const Eigen::Quaternion<T> q_a(
        cos(0.5 * a.yaw), T(0.0), T(0.0), sin(0.5 * a.yaw));
    const Eigen::Matrix<T, 3, 1> t_a(a.x, a.y, T(z_a_));
    return WhitenedResidual(q_a,
                            t_a,
                            q_xyzw,
                            p_xy,
                            log_scale,
                            p_z,
                            q_b_,
                            t_b_,
                            sqrt_information_,
                            residuals);
  }

 private:
  OdometrySamples samples_;
  double wheel_track_m_;
  double z_a_;
  Eigen::Quaterniond q_b_;
  Eigen::Vector3d t_b_;
  Matrix6d sqrt_information_;
};

struct Solved {
  bool usable = false;
  std::string report;
  Eigen::MatrixXd information;  // [extrinsic, scales, free systematics]
  std::vector<int> segments;
  std::vector<int> free_systematics;  // column order after the scales
};

class SystematicsProblem {
 public:
  SystematicsProblem(const MotionPairs& pairs,
                     const std::vector<int>& indices,
                     const Rigid3d& initial,
                     const std::vector<double>& initial_scales,
                     const OdometryIntrinsics& intrinsics,
                     double offset_change_s,
                     const std::array<bool, kNumSystematics>& free,
                     const CalibrationOptions& options)
      : free_(free), wheel_track_m_(intrinsics.wheel_track_m) {
    const Eigen::Quaterniond q0 = initial.rotation.normalized();
    for (int k = 0; k < 4; ++k) quaternion_[k] = q0.coeffs()[k];
    p_xy_[0] = initial.translation.x();
    p_xy_[1] = initial.translation.y();
    p_z_ = initial.translation.z();
    offset_ = offset_change_s;
    intrinsics_[0] = intrinsics.yaw_scale;
    intrinsics_[1] = intrinsics.yaw_per_metre_rad;
    intrinsics_[2] = intrinsics.yaw_rate_bias_rad_s;
    for (const int index : indices) {
      const int segment = pairs[index].segment;
      log_scales_.emplace(segment, std::log(initial_scales.at(segment)));
    }
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_ = std::make_unique<ceres::Problem>(problem_options);
    for (const int index : indices) {
      const MotionPair& pair = pairs[index];
      const Matrix6d sqrt_information = HandEyeSqrtInformation(
          pair, initial, initial_scales.at(pair.segment), options.noise);
      ceres::CostFunction* cost =
          pair.odometry_samples
              ? static_cast<ceres::CostFunction*>(
                    new ceres::AutoDiffCostFunction<SystematicsCost,
                                                    6,
                                                    4,
                                                    2,
                                                    1,
                                                    1,
                                                    1,
                                                    3>(new SystematicsCost(
                        pair, sqrt_information, intrinsics.wheel_track_m)))
              : new ceres::
                    AutoDiffCostFunction<Se3OffsetCost, 6, 4, 2, 1, 1, 1, 3>(
                        new Se3OffsetCost(pair, sqrt_information));
      problem_->AddResidualBlock(cost,
                                 nullptr,
                                 quaternion_,
                                 p_xy_,
                                 &log_scales_.at(pair.segment),
                                 &p_z_,
                                 &offset_,
                                 intrinsics_);
    }
    problem_->SetManifold(quaternion_, &quaternion_manifold_);
    problem_->SetParameterBlockConstant(&p_z_);
    if (!free_[0]) problem_->SetParameterBlockConstant(&offset_);
    std::vector<int> held;
    for (int k = 0; k < 3; ++k) {
      if (!free_[1 + k]) held.push_back(k);
    }
    if (held.size() == 3) {
      problem_->SetParameterBlockConstant(intrinsics_);
    } else if (!held.empty()) {
      subset_ = std::make_unique<ceres::SubsetManifold>(3, held);
      problem_->SetManifold(intrinsics_, subset_.get());
    }
  }

  Solved Solve(int max_num_iterations) {
    ceres::Solver::Options solver_options;
    solver_options.linear_solver_type = ceres::DENSE_QR;
    solver_options.max_num_iterations = max_num_iterations;
    solver_options.function_tolerance = 1e-15;
    solver_options.gradient_tolerance = 1e-15;
    solver_options.parameter_tolerance = 1e-15;
    solver_options.logging_type = ceres::SILENT;
    solver_options.num_threads = 1;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, problem_.get(), &summary);
    Solved solved;
    solved.usable = summary.IsSolutionUsable();
    solved.report = summary.BriefReport();
    if (solved.usable) solved.information = Information(&solved);
    return solved;
  }

  Rigid3d OdomFromCam() const {
    return OdomFromCamParameters(quaternion_, p_xy_, p_z_);
  }
  std::vector<double> Scales(size_t num_segments) const {
    return ScalesFromLogScales(log_scales_, num_segments);
  }
  double offset() const { return offset_; }
  OdometryIntrinsics Intrinsics() const {
    return {intrinsics_[0], intrinsics_[1], intrinsics_[2], wheel_track_m_};
  }

 private:
  // J^T J in reported coordinates: phi = 2 delta for the quaternion, ds =
  // s d(log s) for the scales, the others as they are.
  Eigen::MatrixXd Information(Solved* solved) {
    ceres::Problem::EvaluateOptions evaluate_options;
    evaluate_options.apply_loss_function = false;
    evaluate_options.parameter_blocks = {quaternion_, p_xy_};
    for (auto& [segment, log_scale] : log_scales_) {
      evaluate_options.parameter_blocks.push_back(&log_scale);
      solved->segments.push_back(segment);
    }
    if (free_[0]) {
      evaluate_options.parameter_blocks.push_back(&offset_);
      solved->free_systematics.push_back(0);
    }
    bool any_intrinsic = false;
    for (int k = 1; k < kNumSystematics; ++k) {
      if (free_[k]) {
        solved->free_systematics.push_back(k);
        any_intrinsic = true;
      }
    }
    if (any_intrinsic) evaluate_options.parameter_blocks.push_back(intrinsics_);
    ceres::CRSMatrix crs;
    double cost = 0.0;
    problem_->Evaluate(evaluate_options, &cost, nullptr, nullptr, &crs);
    Eigen::MatrixXd jacobian =
        Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
    for (int row = 0; row < crs.num_rows; ++row) {
      for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) {
        jacobian(row, crs.cols[k]) = crs.values[k];
      }
    }
    Eigen::VectorXd chain = Eigen::VectorXd::Ones(crs.num_cols);
    chain.head<3>().setConstant(0.5);
    for (size_t k = 0; k < solved->segments.size(); ++k) {
      chain(5 + k) = 1.0 / std::exp(log_scales_.at(solved->segments[k]));
    }
    const Eigen::MatrixXd scaled = jacobian * chain.asDiagonal();
    return scaled.transpose() * scaled;
  }

  std::array<bool, kNumSystematics> free_;
  double wheel_track_m_;
  std::unique_ptr<ceres::Problem> problem_;
  ceres::EigenQuaternionManifold quaternion_manifold_;
  std::unique_ptr<ceres::SubsetManifold> subset_;
  double quaternion_[4];
  double p_xy_[2];
  double p_z_;
  double offset_;
  double intrinsics_[3];
  std::map<int, double> log_scales_;
};

// Covariance of a diagonally normalised information, or an empty matrix and
// the most undetermined column among `candidates` when it is singular.
Eigen::MatrixXd Covariance(const Eigen::MatrixXd& information,
                           const std::vector<int>& candidates,
                           int* null_column) {
  *null_column = -1;
  const int n = static_cast<int>(information.rows());
  if (n == 0 || !information.allFinite()) return Eigen::MatrixXd();
  const Eigen::VectorXd diag = information.diagonal();
  Eigen::VectorXd inv_sqrt(n);
  for (int k = 0; k < n; ++k) {
    inv_sqrt(k) = diag(k) > 0.0 ? 1.0 / std::sqrt(diag(k)) : 0.0;
  }
  const Eigen::MatrixXd normalised =
      inv_sqrt.asDiagonal() * information * inv_sqrt.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(normalised);
  const double max_eigenvalue = eig.eigenvalues().maxCoeff();
  if (!(eig.eigenvalues().minCoeff() > 1e-10 * max_eigenvalue)) {
    const Eigen::VectorXd null = eig.eigenvectors().col(0);
    double largest = -1.0;
    for (const int column : candidates) {
      if (std::abs(null(column)) > largest) {
        largest = std::abs(null(column));
        *null_column = column;
      }
    }
    return Eigen::MatrixXd();
  }
  return inv_sqrt.asDiagonal() * eig.eigenvectors() *
         eig.eigenvalues().cwiseInverse().asDiagonal() *
         eig.eigenvectors().transpose() * inv_sqrt.asDiagonal();
}

std::string Held(int parameter, const std::string& why) {
  return std::string(kSystematicsNames[parameter]) + " " + why;
}

}  // namespace

SystematicsRefinement RefineSystematics(
    const MotionPairs& pairs,
    const std::vector<int>& indices,
    const Rigid3d& initial,
    const std::vector<double>& initial_scales,
    const OdometryIntrinsics& initial_intrinsics,
    const CalibrationOptions& options,
    const SystematicsOptions& systematics) {
  SystematicsRefinement result;
  result.odom_from_cam = initial;
  result.metric_scales = initial_scales;
  result.intrinsics = initial_intrinsics;
  bool any_twists = false;
  for (const int index : indices) {
    const MotionPair& pair = pairs[index];
    const int segment = pair.segment;
    if (!(pair.odometry_samples || pair.odometry_twists) || segment < 0 ||
        static_cast<size_t>(segment) >= initial_scales.size() ||
        !(initial_scales[segment] > 0.0)) {
      result.report = "a pair without odometry samples or scale";
      return result;
    }
    any_twists = any_twists || !pair.odometry_samples;
  }
  if (indices.empty()) {
    result.report = "no pairs";
    return result;
  }
  // The intrinsics re-integrate planar samples: held for 3-D odometry.
  const bool intrinsics = systematics.estimate_intrinsics && !any_twists;
  std::array<bool, kNumSystematics> free = {
      systematics.estimate_time_offset, intrinsics, intrinsics, intrinsics};
  for (int k = 0; k < kNumSystematics; ++k) {
    if (free[k]) continue;
    result.held_reason[k] = k > 0 && systematics.estimate_intrinsics
                                ? Held(k, "not estimated (3-D odometry)")
                                : Held(k, "not estimated (option off)");
  }
  const std::array<double, kNumSystematics> limits = {
      systematics.max_time_offset_stddev_s,
      systematics.max_yaw_scale_stddev,
      systematics.max_yaw_per_metre_stddev_rad,
      systematics.max_yaw_rate_bias_stddev_rad_s};
  // Each round either accepts every free parameter or holds one more.
  for (int round = 0; round <= kNumSystematics; ++round) {
    SystematicsProblem problem(pairs,
                               indices,
                               initial,
                               initial_scales,
                               initial_intrinsics,
                               0.0,
                               free,
                               options);
    const Solved solved = problem.Solve(options.max_num_iterations);
    result.report = solved.report;
    if (!solved.usable) return result;
    const int first = 5 + static_cast<int>(solved.segments.size());
    std::vector<int> candidates;
    for (size_t k = 0; k < solved.free_systematics.size(); ++k) {
      candidates.push_back(first + static_cast<int>(k));
    }
    int null_column = -1;
    const Eigen::MatrixXd covariance =
        Covariance(solved.information, candidates, &null_column);
    int hold = -1;
    std::string why;
    if (covariance.size() == 0) {
      if (null_column < 0) return result;  // the extrinsic itself is singular
      hold = solved.free_systematics[null_column - first];
      why = "not determined by this motion (singular information)";
    } else {
      double worst = 1.0;
      for (size_t k = 0; k < solved.free_systematics.size(); ++k) {
        const int parameter = solved.free_systematics[k];
        const double stddev = std::sqrt(covariance(first + k, first + k));
        if (stddev / limits[parameter] > worst) {
          worst = stddev / limits[parameter];
          hold = parameter;
          why = "not determined by this motion (standard deviation " +
                FormatNumber(stddev) + " > " + FormatNumber(limits[parameter]) +
                ")";
        }
      }
    }
    if (hold >= 0) {
      free[hold] = false;
      result.held_reason[hold] = Held(hold, why);
      continue;
    }
    result.usable = true;
    result.odom_from_cam = problem.OdomFromCam();
    result.metric_scales = problem.Scales(initial_scales.size());
    result.time_offset_change_s = problem.offset();
    result.intrinsics = problem.Intrinsics();
    result.information_segments = solved.segments;
    result.extrinsic_covariance = covariance.topLeftCorner(first, first);
    const Eigen::LDLT<Eigen::MatrixXd> held(
        solved.information.topLeftCorner(first, first));
    if (held.info() == Eigen::Success && held.isPositive()) {
      result.extrinsic_conditional_covariance =
          held.solve(Eigen::MatrixXd::Identity(first, first));
    }
    for (size_t k = 0; k < solved.free_systematics.size(); ++k) {
      const int parameter = solved.free_systematics[k];
      result.estimated[parameter] = true;
      result.stddev[parameter] = std::sqrt(covariance(first + k, first + k));
    }
    return result;
  }
  return result;
}

}  // namespace odomcal
