// Ceres cost functor of one motion pair (internal: not installed; Ceres types
// stay out of the public headers).
#pragma once

#include "odomcal/solver/hand_eye_residual.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <type_traits>
#include <vector>

namespace odomcal {

// Whether the value part of every residual is finite. A cost functor
// returns false where it is not (a trust-region step to a log-scale whose
// exp overflows, far from any minimum): Ceres then rejects the step
// quietly, where NaN residuals returned as a success make it log a warning
// to stderr.
template <typename T, int N>
bool ResidualsFinite(const Eigen::Matrix<T, N, 1>& residuals) {
  for (int i = 0; i < N; ++i) {
    if constexpr (std::is_same_v<T, double>) {
      if (!std::isfinite(residuals(i))) return false;
    } else {
      if (!std::isfinite(residuals(i).a)) return false;
    }
  }
  return true;
}

// Residual, whitened:  W [ Log(q_A^-1 q q_B q^-1) ; R_A p + t_A - s R t_B - p ]
// with p = [p_xy, p_z] and s = exp(log_scale). Parameters:
// q (4, Eigen x,y,z,w order, on EigenQuaternionManifold), p_xy (2),
// log_scale (1), p_z (1; a constant block where z is held). See
// hand_eye_residual.h for the model and W.
//
// W is either fixed, or W(s) with W^T W = Cov(r)(s)^-1 from a
// ResidualCovarianceInScale: the camera's translation noise grows with the
// scale tried, which is the errors-in-variables likelihood with the true
// motions profiled out (not attenuated towards a smaller scale).
class HandEyeCost {
 public:
  HandEyeCost(const MotionPair& pair, const Matrix6d& sqrt_information)
      : q_a_inverse_(pair.odom_i_from_odom_j.rotation.conjugate()),
        r_a_(pair.odom_i_from_odom_j.rotation.toRotationMatrix()),
        t_a_(pair.odom_i_from_odom_j.translation),
        q_b_(pair.cam_i_from_cam_j.rotation),
        t_b_(pair.cam_i_from_cam_j.translation),
        sqrt_information_(sqrt_information) {}
  HandEyeCost(const MotionPair& pair,
              const ResidualCovarianceInScale& covariance)
      : HandEyeCost(pair, Matrix6d::Identity()) {
    covariance_in_scale_ = true;
    covariance_ = covariance;
    // The diagonal load of HandEyeSqrtInformation, at the evaluated scale.
    const Matrix6d at_scale =
        covariance.fixed + covariance.cross + covariance.quadratic;
    load_ = 1e-12 * at_scale.trace() + 1e-300;
  }

  static ceres::CostFunction* Create(const MotionPair& pair,
                                     const Matrix6d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<HandEyeCost, 6, 4, 2, 1, 1>(
        new HandEyeCost(pair, sqrt_information));
  }
  static ceres::CostFunction* Create(
      const MotionPair& pair, const ResidualCovarianceInScale& covariance) {
    return new ceres::AutoDiffCostFunction<HandEyeCost, 6, 4, 2, 1, 1>(
        new HandEyeCost(pair, covariance));
  }

  template <typename T>
  bool operator()(const T* q_xyzw,
                  const T* p_xy,
                  const T* log_scale,
                  const T* p_z,
                  T* residuals) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(q_xyzw);
    const Eigen::Matrix<T, 3, 1> p(p_xy[0], p_xy[1], p_z[0]);
    const T scale = exp(log_scale[0]);

    const Eigen::Quaternion<T> error =
        q_a_inverse_.cast<T>() * q * q_b_.cast<T>() * q.conjugate();
    const T error_wxyz[4] = {error.w(), error.x(), error.y(), error.z()};
    Eigen::Matrix<T, 6, 1> raw;
    ceres::QuaternionToAngleAxis(error_wxyz, raw.data());
    raw.template tail<3>() =
        r_a_.cast<T>() * p + t_a_.cast<T>() - scale * (q * t_b_.cast<T>()) - p;

    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residuals);
    if (!covariance_in_scale_) {
      out = sqrt_information_.cast<T>() * raw;
      return ResidualsFinite<T, 6>(out);
    }
    const T ratio = scale / covariance_.scale;
    // Cov = L L^T: W = L^-1, so W r = L^-1 r.
    if constexpr (std::is_same_v<T, double>) {
      Eigen::Matrix<double, 6, 6> l;
      if (!CholeskyAt(ratio, &l)) return false;
      out = l.triangularView<Eigen::Lower>().solve(raw);
    } else {
      // Cov(r) depends on the scale alone: its factor is taken on a dual
      // number in the ratio and carried into the Jet's parameters by the
      // chain rule. A Cholesky on Jets of all eight parameters took most of
      // the refinement's time.
      using Dual = ceres::Jet<double, 1>;
      Eigen::Matrix<Dual, 6, 6> l_dual;
      if (!CholeskyAt(Dual(ratio.a, 0), &l_dual)) return false;
      Eigen::Matrix<T, 6, 6> l = Eigen::Matrix<T, 6, 6>::Zero();
      for (int i = 0; i < 6; ++i) {
        for (int k = 0; k <= i; ++k) {
          l(i, k) = T(l_dual(i, k).a, l_dual(i, k).v[0] * ratio.v);
        }
      }
      out = l.template triangularView<Eigen::Lower>().solve(raw);
    }
    return ResidualsFinite<T, 6>(out);
  }

 private:
  // The lower Cholesky factor of Cov(r) at `ratio` = s / covariance_.scale
  // (a double or a dual number in it).
  template <typename S>
  bool CholeskyAt(const S& ratio, Eigen::Matrix<S, 6, 6>* l) const {
    Eigen::Matrix<S, 6, 6> covariance =
        covariance_.fixed.cast<S>() + ratio * covariance_.cross.cast<S>() +
        ratio * ratio * covariance_.quadratic.cast<S>();
    covariance.diagonal().array() += S(load_);
    const Eigen::LLT<Eigen::Matrix<S, 6, 6>> llt(covariance);
    if (llt.info() != Eigen::Success) return false;
    *l = llt.matrixL();
    return true;
  }

  Eigen::Quaterniond q_a_inverse_;
  Eigen::Matrix3d r_a_;
  Eigen::Vector3d t_a_;
  Eigen::Quaterniond q_b_;
  Eigen::Vector3d t_b_;
  Matrix6d sqrt_information_;
  bool covariance_in_scale_ = false;
  ResidualCovarianceInScale covariance_;
  double load_ = 0.0;
};

// odom_from_cam from the refinement's parameter blocks above.
inline Rigid3d OdomFromCamParameters(const double quaternion[4],
                                     const double p_xy[2],
                                     double p_z) {
  return Rigid3d(Eigen::Quaterniond(
                     quaternion[3], quaternion[0], quaternion[1], quaternion[2])
                     .normalized(),
                 Eigen::Vector3d(p_xy[0], p_xy[1], p_z));
}

// Metric scales by segment from the log-scale blocks; NaN for segments
// without a block.
inline std::vector<double> ScalesFromLogScales(
    const std::map<int, double>& log_scales, size_t num_segments) {
  std::vector<double> scales(num_segments,
                             std::numeric_limits<double>::quiet_NaN());
  for (const auto& [segment, log_scale] : log_scales) {
    if (segment >= 0 && static_cast<size_t>(segment) < num_segments) {
      scales[segment] = std::exp(log_scale);
    }
  }
  return scales;
}

}  // namespace odomcal
