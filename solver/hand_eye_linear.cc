// Closed form of Guo, Mirzaei & Roumeliotis (ICRA 2012) for Hamilton
// quaternions. Step 1 builds the 4x4 normal matrix of (L(q_A) - R(q_B)) q_yz
// = 0, takes its two-dimensional near-null space and intersects it with the
// cone w x = y z. Quaternion signs are made consistent per pair first (a
// camera rotation near pi can flip sign under noise); after a first solve each
// q_B keeps the sign that agrees with q_yz and the eigenproblem is redone.
// Step 2 solves for p_x, p_y, alpha and the scales, see the header.

#include "odomcal/solver/hand_eye_linear.h"

#include "odomcal/solver/angles.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace odomcal {
namespace {

// Grid over alpha for the multi-segment profile; the profile has at most a
// few minima per turn, so half a degree brackets every one of them.
constexpr int kAlphaGridSize = 720;
constexpr int kMaxGaussNewtonIterations = 20;

Eigen::Vector4d WFirst(const Eigen::Quaterniond& q) {
  return Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
}

Eigen::Quaterniond FromWFirst(const Eigen::Vector4d& v) {
  return Eigen::Quaterniond(v(0), v(1), v(2), v(3));
}

Eigen::Matrix4d RotationBlock(const Eigen::Quaterniond& q_a,
                              const Eigen::Quaterniond& q_b) {
  return QuaternionLeftMatrix(q_a) - QuaternionRightMatrix(q_b);
}

Eigen::Matrix2d Rot2(double alpha) {
  Eigen::Matrix2d r;
  r << std::cos(alpha), -std::sin(alpha), std::sin(alpha), std::cos(alpha);
  return r;
}

// One row block of step 2: J p - s Rz(alpha) v + t = residual.
struct Step2Row {
  Eigen::Matrix2d j;
  Eigen::Vector2d v;
  Eigen::Vector2d t;
  int segment = 0;  // local (compacted) index
};

// The parts of a MotionPair the closed form reads, packed densely: a
// MotionPair carries optional covariances and is ~10x larger, which made
// large problems memory bound.
struct CompactMotion {
  Eigen::Quaterniond q_a;  // unit, non-negative scalar part
  Eigen::Quaterniond q_b;  // unit, non-negative scalar part
  Eigen::Vector3d t_a;
  Eigen::Vector3d t_b;
  int segment = 0;
};

std::vector<CompactMotion> Compact(const MotionPairs& pairs,
                                   const std::vector<int>& indices) {
  std::vector<CompactMotion> motions;
  motions.reserve(indices.size());
  for (const int index : indices) {
    const MotionPair& pair = pairs[index];
    CompactMotion motion;
    motion.q_a =
        WithPositiveScalar(pair.odom_i_from_odom_j.rotation.normalized());
    motion.q_b =
        WithPositiveScalar(pair.cam_i_from_cam_j.rotation.normalized());
    motion.t_a = pair.odom_i_from_odom_j.translation;
    motion.t_b = pair.cam_i_from_cam_j.translation;
    motion.segment = pair.segment;
    motions.push_back(motion);
  }
  return motions;
}

// Eigen's SelfAdjointEigenSolver sorts eigenvalues in increasing order.
Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> SolveNormalMatrix(
    const std::vector<CompactMotion>& motions,
    const std::vector<double>& q_b_signs) {
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  for (size_t n = 0; n < motions.size(); ++n) {
    const Eigen::Quaterniond q_b(q_b_signs[n] * motions[n].q_b.coeffs());
    const Eigen::Matrix4d block = RotationBlock(motions[n].q_a, q_b);
    normal.noalias() += block.transpose() * block;
  }
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(normal);
}

// Unit vectors v = a t1 + b t2 with v_w v_x - v_y v_z = 0.
std::vector<Eigen::Vector4d> ConstraintRoots(const Eigen::Vector4d& t1,
                                             const Eigen::Vector4d& t2,
                                             bool* gimbal) {
  auto bilinear = [](const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
    return 0.5 * (a(0) * b(1) + b(0) * a(1) - a(2) * b(3) - b(2) * a(3));
  };
  Eigen::Matrix2d quadric;
  quadric << bilinear(t1, t1), bilinear(t1, t2), bilinear(t1, t2),
      bilinear(t2, t2);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(quadric);
  const double lambda_neg = std::min(eig.eigenvalues()(0), 0.0);
  const double lambda_pos = std::max(eig.eigenvalues()(1), 0.0);
  // The quadric is (1/2) sin(beta) sin(alpha') on the span; it vanishes
  // identically when the camera's z axis is parallel to the odometry's.
  constexpr double kGimbalTolerance = 1e-10;
  *gimbal = std::max(lambda_pos, -lambda_neg) < kGimbalTolerance;
  if (*gimbal) {
    return {t1};
  }
  // quadric = lambda_neg e1 e1^T + lambda_pos e2 e2^T; its zero set in the
  // (a, b) plane is the pair of lines sqrt(lambda_pos) e1 +- sqrt(-lambda_neg)
  // e2 (they coincide when noise pushes lambda_neg to zero).
  const Eigen::Vector2d e1 = eig.eigenvectors().col(0);
  const Eigen::Vector2d e2 = eig.eigenvectors().col(1);
  std::vector<Eigen::Vector4d> roots;
  for (const double sign : {1.0, -1.0}) {
    const Eigen::Vector2d ab =
        (std::sqrt(lambda_pos) * e1 + sign * std::sqrt(-lambda_neg) * e2)
            .normalized();
    roots.push_back((ab(0) * t1 + ab(1) * t2).normalized());
  }
  return roots;
}

// Camera translation mapped into the q_yz frame, first two components.
Eigen::Vector2d PlanarCameraTranslation(const Eigen::Vector3d& t_cam,
                                        const Eigen::Matrix3d& r_yz,
                                        const LinearOptions& options) {
  const Eigen::Vector3d rotated = r_yz * t_cam;
  if (options.method == LinearMethod::kAls ||
      options.alsp_projection == PlaneProjection::kOrthogonal) {
    // Orthogonal projection onto the plane only removes rotated.z().
    return rotated.head<2>();
  }
  const double in_plane = rotated.head<2>().norm();
  if (in_plane < std::numeric_limits<double>::min()) {
    return rotated.head<2>();
  }
  return rotated.head<2>() * (rotated.norm() / in_plane);
}

// Condition number of a symmetric positive semi-definite normal matrix after
// scaling its diagonal to one, as the square root of the eigenvalue ratio.
double NormalizedConditionNumber(const Eigen::MatrixXd& normal) {
  const Eigen::VectorXd diag = normal.diagonal();
  if ((diag.array() <= 0.0).any()) {
    return std::numeric_limits<double>::infinity();
  }
  const Eigen::VectorXd inv_sqrt = diag.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled =
      inv_sqrt.asDiagonal() * normal * inv_sqrt.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled);
  const double lo = eig.eigenvalues().minCoeff();
  const double hi = eig.eigenvalues().maxCoeff();
  if (lo <= hi * 1e-300) {
    return std::numeric_limits<double>::infinity();
  }
  return std::sqrt(hi / lo);
}

// Profile of the step-2 cost over alpha: the linear unknowns y = [p; s] are
// eliminated through the normal equations of x = [p; w_0 ..] with w_k = s_k u.
class AlphaProfile {
 public:
  AlphaProfile(const std::vector<Step2Row>& rows, int num_segments)
      : num_segments_(num_segments) {
    const int n = 2 + 2 * num_segments;
    normal_ = Eigen::MatrixXd::Zero(n, n);
    gradient_ = Eigen::VectorXd::Zero(n);
    // Blocks of D^T D and D^T t for the row design D = [J, 0.., W_k, 0..],
    // W_k = -[v1 -v2; v2 v1] so that W_k [cos; sin] = -Rz(alpha) v.
    for (const Step2Row& row : rows) {
      Eigen::Matrix2d w;
      w << -row.v(0), row.v(1), -row.v(1), -row.v(0);
      const int k = 2 + 2 * row.segment;
      normal_.topLeftCorner<2, 2>().noalias() += row.j.transpose() * row.j;
      normal_.block<2, 2>(0, k).noalias() += row.j.transpose() * w;
      normal_.block<2, 2>(k, k).noalias() += w.transpose() * w;
      gradient_.head<2>().noalias() += row.j.transpose() * row.t;
      gradient_.segment<2>(k).noalias() += w.transpose() * row.t;
      constant_ += row.t.squaredNorm();
    }
    for (int segment = 0; segment < num_segments; ++segment) {
      const int k = 2 + 2 * segment;
      normal_.block<2, 2>(k, 0) = normal_.block<2, 2>(0, k).transpose();
    }
  }

  // Reduced normal matrix E^T H E for u = (cos alpha, sin alpha), where
  // x = E y maps y = [p; s_0 ..] to x = [p; s_0 u; ..].
  Eigen::MatrixXd Reduced(double alpha, Eigen::VectorXd* rhs) const {
    const Eigen::Vector2d u(std::cos(alpha), std::sin(alpha));
    const int m = 2 + num_segments_;
    Eigen::MatrixXd reduced(m, m);
    rhs->resize(m);
    reduced.topLeftCorner<2, 2>() = normal_.topLeftCorner<2, 2>();
    rhs->head<2>() = gradient_.head<2>();
    for (int a = 0; a < num_segments_; ++a) {
      const int ka = 2 + 2 * a;
      reduced.block<2, 1>(0, 2 + a) = normal_.block<2, 2>(0, ka) * u;
      reduced.block<1, 2>(2 + a, 0) = reduced.block<2, 1>(0, 2 + a).transpose();
      (*rhs)(2 + a) = gradient_.segment<2>(ka).dot(u);
      for (int b = 0; b < num_segments_; ++b) {
        const int kb = 2 + 2 * b;
        reduced(2 + a, 2 + b) = u.dot(normal_.block<2, 2>(ka, kb) * u);
      }
    }
    return reduced;
  }

  // Minimum over y of the cost at alpha; y = [p_x, p_y, s_0, ...].
  double Cost(double alpha, Eigen::VectorXd* y) const {
    Eigen::VectorXd rhs;
    const Eigen::MatrixXd reduced = Reduced(alpha, &rhs);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(reduced);
    if (ldlt.info() == Eigen::Success && ldlt.isPositive()) {
      *y = -ldlt.solve(rhs);
    } else {
      *y = -reduced.completeOrthogonalDecomposition().solve(rhs);
    }
    return constant_ + rhs.dot(*y);
  }

 private:
  int num_segments_;
  Eigen::MatrixXd normal_;
  Eigen::VectorXd gradient_;
  double constant_ = 0.0;
};

// Gauss-Newton on the exact residuals r_i = J_i p - s_k R(alpha) v_i + t_i,
// unknowns [p_x, p_y, s_0 .. s_{K-1}, alpha].
void PolishStep2(const std::vector<Step2Row>& rows,
                 int num_segments,
                 Eigen::VectorXd* y,
                 double* alpha) {
  const int num_unknowns = 3 + num_segments;
  Eigen::MatrixXd jacobian(2 * rows.size(), num_unknowns);
  Eigen::VectorXd residual(2 * rows.size());
  for (int iteration = 0; iteration < kMaxGaussNewtonIterations; ++iteration) {
    jacobian.setZero();
    const Eigen::Matrix2d rot = Rot2(*alpha);
    Eigen::Matrix2d rot_derivative;
    rot_derivative << -std::sin(*alpha), -std::cos(*alpha), std::cos(*alpha),
        -std::sin(*alpha);
    for (size_t i = 0; i < rows.size(); ++i) {
      const Step2Row& row = rows[i];
      const double scale = (*y)(2 + row.segment);
      residual.segment<2>(2 * i) =
          row.j * y->head<2>() - scale * rot * row.v + row.t;
      jacobian.block<2, 2>(2 * i, 0) = row.j;
      jacobian.block<2, 1>(2 * i, 2 + row.segment) = -rot * row.v;
      jacobian.block<2, 1>(2 * i, 2 + num_segments) =
          -scale * rot_derivative * row.v;
    }
    const Eigen::VectorXd step =
        -jacobian.colPivHouseholderQr().solve(residual);
    y->head(2 + num_segments) += step.head(2 + num_segments);
    *alpha += step(2 + num_segments);
    if (step.lpNorm<Eigen::Infinity>() < 1e-15 * (1.0 + y->norm())) {
      break;
    }
  }
}

}  // namespace

Eigen::Matrix4d QuaternionLeftMatrix(const Eigen::Quaterniond& p) {
  Eigen::Matrix4d l;
  l << p.w(), -p.x(), -p.y(), -p.z(),  //
      p.x(), p.w(), -p.z(), p.y(),     //
      p.y(), p.z(), p.w(), -p.x(),     //
      p.z(), -p.y(), p.x(), p.w();
  return l;
}

Eigen::Matrix4d QuaternionRightMatrix(const Eigen::Quaterniond& q) {
  Eigen::Matrix4d r;
  r << q.w(), -q.x(), -q.y(), -q.z(),  //
      q.x(), q.w(), q.z(), -q.y(),     //
      q.y(), -q.z(), q.w(), q.x(),     //
      q.z(), q.y(), -q.x(), q.w();
  return r;
}

namespace {

std::vector<Eigen::Quaterniond> SolveRotationYZ(
    const std::vector<CompactMotion>& motions, LinearEstimate* estimate) {
  // Scalar parts of the same sign within a pair: both non-negative first.
  std::vector<double> q_b_signs(motions.size(), 1.0);
  auto eig = SolveNormalMatrix(motions, q_b_signs);

  // Near a rotation of pi, w ~ 0 and noise can give q_A and q_B opposite
  // signs; keep for q_B the sign that fits the first estimate of q_yz.
  const Eigen::Quaterniond first_guess = FromWFirst(eig.eigenvectors().col(0));
  bool flipped = false;
  for (size_t n = 0; n < motions.size(); ++n) {
    const Eigen::Quaterniond& q_a = motions[n].q_a;
    const Eigen::Quaterniond q_b(q_b_signs[n] * motions[n].q_b.coeffs());
    const Eigen::Quaterniond minus_q_b(-q_b.coeffs());
    const double keep =
        (RotationBlock(q_a, q_b) * WFirst(first_guess)).squaredNorm();
    const double flip =
        (RotationBlock(q_a, minus_q_b) * WFirst(first_guess)).squaredNorm();
    if (flip < keep) {
      q_b_signs[n] = -q_b_signs[n];
      flipped = true;
    }
  }
  if (flipped) {
    eig = SolveNormalMatrix(motions, q_b_signs);
  }

  estimate->rotation_step_eigenvalues = eig.eigenvalues();
  const double third = eig.eigenvalues()(2);
  estimate->rotation_step_ratio =
      third > 0.0 ? eig.eigenvalues()(1) / third : 1.0;
  std::vector<Eigen::Quaterniond> candidates;
  for (const Eigen::Vector4d& root :
       ConstraintRoots(eig.eigenvectors().col(0),
                       eig.eigenvectors().col(1),
                       &estimate->rotation_step_gimbal)) {
    candidates.push_back(WithPositiveScalar(FromWFirst(root)));
  }
  estimate->num_constraint_roots = static_cast<int>(candidates.size());
  return candidates;
}

bool SolveYawTranslationScale(const std::vector<CompactMotion>& motions,
                              const Eigen::Quaterniond& q_yz,
                              const LinearOptions& options,
                              LinearEstimate* estimate) {
  const Eigen::Matrix3d r_yz = q_yz.toRotationMatrix();
  std::map<int, int> local_of_segment;
  for (const CompactMotion& motion : motions) {
    local_of_segment.emplace(motion.segment, 0);
  }
  int num_segments = 0;
  for (auto& [segment, local] : local_of_segment) {
    local = num_segments++;
  }

  std::vector<Step2Row> rows;
  rows.reserve(motions.size());
  for (const CompactMotion& motion : motions) {
    const Eigen::Matrix3d r_a_minus_i =
        motion.q_a.toRotationMatrix() - Eigen::Matrix3d::Identity();
    Step2Row row;
    row.j = r_a_minus_i.topLeftCorner<2, 2>();
    row.v = PlanarCameraTranslation(motion.t_b, r_yz, options);
    // The fixed z offset enters only through a tilted odometry rotation.
    row.t = motion.t_a.head<2>() +
            r_a_minus_i.block<2, 1>(0, 2) * options.fixed_translation_z_m;
    row.segment = local_of_segment.at(motion.segment);
    rows.push_back(row);
  }

  double alpha = 0.0;
  Eigen::VectorXd y;  // [p_x, p_y, s_0 ..]
  const AlphaProfile profile(rows, num_segments);
  if (num_segments == 1) {
    // The paper's linear least squares in m = [p_x, p_y, s cos, s sin].
    Eigen::MatrixXd design(2 * rows.size(), 4);
    Eigen::VectorXd rhs(2 * rows.size());
    for (size_t i = 0; i < rows.size(); ++i) {
      design.block<2, 2>(2 * i, 0) = rows[i].j;
      design.block<2, 2>(2 * i, 2) << -rows[i].v(0), rows[i].v(1),
          -rows[i].v(1), -rows[i].v(0);
      rhs.segment<2>(2 * i) = -rows[i].t;
    }
    const auto qr = design.colPivHouseholderQr();
    if (qr.rank() < 4) {
      estimate->failure = "the translation step is rank deficient (rank " +
                          std::to_string(qr.rank()) + " of 4)";
      return false;
    }
    const Eigen::Vector4d m = qr.solve(rhs);
    alpha = std::atan2(m(3), m(2));
    y = Eigen::Vector3d(m(0), m(1), m.tail<2>().norm());
  } else {
    // Bracket the global minimum over alpha, then polish.
    double best_cost = std::numeric_limits<double>::infinity();
    for (int k = 0; k < kAlphaGridSize; ++k) {
      const double candidate = 2.0 * kPi * k / kAlphaGridSize;
      Eigen::VectorXd candidate_y;
      const double cost = profile.Cost(candidate, &candidate_y);
      if (cost < best_cost) {
        best_cost = cost;
        alpha = candidate;
        y = candidate_y;
      }
    }
    PolishStep2(rows, num_segments, &y, &alpha);
    // alpha and alpha + pi with all scales negated fit equally well.
    if (y.tail(num_segments).sum() < 0.0) {
      alpha += kPi;
      y.tail(num_segments) *= -1.0;
    }
  }

  Eigen::VectorXd unused_rhs;
  estimate->translation_step_condition_number =
      NormalizedConditionNumber(profile.Reduced(alpha, &unused_rhs));
  if (!std::isfinite(estimate->translation_step_condition_number)) {
    estimate->failure = "the translation step is singular";
    return false;
  }

  estimate->odom_from_cam.rotation = (YawRotation(alpha) * q_yz).normalized();
  estimate->odom_from_cam.translation =
      Eigen::Vector3d(y(0), y(1), options.fixed_translation_z_m);
  const int num_all_segments = local_of_segment.rbegin()->first + 1;
  estimate->metric_scales.assign(num_all_segments,
                                 std::numeric_limits<double>::quiet_NaN());
  for (const auto& [segment, local] : local_of_segment) {
    estimate->metric_scales[segment] = y(2 + local);
  }
  double cost = 0.0;
  const Eigen::Matrix2d rot = Rot2(alpha);
  for (const Step2Row& row : rows) {
    cost += (row.j * y.head<2>() - y(2 + row.segment) * rot * row.v + row.t)
                .squaredNorm();
  }
  estimate->step2_cost = cost;
  return true;
}

}  // namespace

LinearEstimate SolveTranslationScale3d(const MotionPairs& pairs,
                                       const std::vector<int>& indices,
                                       const Eigen::Quaterniond& rotation) {
  LinearEstimate estimate;
  std::map<int, int> local_of_segment;
  for (const int index : indices) {
    local_of_segment.emplace(pairs[index].segment, 0);
  }
  int num_segments = 0;
  for (auto& [segment, local] : local_of_segment) local = num_segments++;
  if (indices.empty()) {
    estimate.failure = "no motion pair";
    return estimate;
  }
  // Rows (R_A - I) p - s_k R t_B = -t_A, unknowns [p_x, p_y, p_z, s_k..].
  const Eigen::Matrix3d r = rotation.toRotationMatrix();
  Eigen::MatrixXd design =
      Eigen::MatrixXd::Zero(3 * indices.size(), 3 + num_segments);
  Eigen::VectorXd rhs(3 * indices.size());
  for (size_t i = 0; i < indices.size(); ++i) {
    const MotionPair& pair = pairs[indices[i]];
    const Rigid3d& a = pair.odom_i_from_odom_j;
    design.block<3, 3>(3 * i, 0) =
        a.rotation.toRotationMatrix() - Eigen::Matrix3d::Identity();
    design.block<3, 1>(3 * i, 3 + local_of_segment.at(pair.segment)) =
        -(r * pair.cam_i_from_cam_j.translation);
    rhs.segment<3>(3 * i) = -a.translation;
  }
  estimate.translation_step_condition_number =
      NormalizedConditionNumber(design.transpose() * design);
  if (!std::isfinite(estimate.translation_step_condition_number) ||
      estimate.translation_step_condition_number > 1e8) {
    estimate.failure = "the 3-D translation step is singular";
    return estimate;
  }
  const Eigen::VectorXd y = design.colPivHouseholderQr().solve(rhs);
  estimate.odom_from_cam = Rigid3d(rotation, y.head<3>());
  estimate.metric_scales.assign(local_of_segment.rbegin()->first + 1,
                                std::numeric_limits<double>::quiet_NaN());
  for (const auto& [segment, local] : local_of_segment) {
    estimate.metric_scales[segment] = y(3 + local);
  }
  estimate.step2_cost = (design * y - rhs).squaredNorm();
  estimate.success = true;
  return estimate;
}

std::vector<Eigen::Quaterniond> SolveRotationYZ(const MotionPairs& pairs,
                                                const std::vector<int>& indices,
                                                LinearEstimate* estimate) {
  return SolveRotationYZ(Compact(pairs, indices), estimate);
}

bool SolveYawTranslationScale(const MotionPairs& pairs,
                              const std::vector<int>& indices,
                              const Eigen::Quaterniond& q_yz,
                              const LinearOptions& options,
                              LinearEstimate* estimate) {
  return SolveYawTranslationScale(
      Compact(pairs, indices), q_yz, options, estimate);
}

LinearEstimate EstimateOdomFromCamLinear(const MotionPairs& pairs,
                                         const std::vector<int>& indices,
                                         const LinearOptions& options) {
  LinearEstimate estimate;
  if (indices.size() < 2) {
    estimate.failure = "at least 2 motion pairs are needed, got " +
                       std::to_string(indices.size());
    return estimate;
  }
  const std::vector<CompactMotion> motions = Compact(pairs, indices);
  const std::vector<Eigen::Quaterniond> candidates =
      SolveRotationYZ(motions, &estimate);
  // Rotation is observable only if the near-null space is two-dimensional:
  // the third eigenvalue must stand clear of zero.
  const double third = estimate.rotation_step_eigenvalues(2);
  if (!(third > 1e-14 * static_cast<double>(indices.size()))) {
    estimate.failure =
        "the rotation step has a null space of dimension > 2 (no rotation)";
    return estimate;
  }

  LinearEstimate best;
  bool found = false;
  std::string failure;
  for (const Eigen::Quaterniond& q_yz : candidates) {
    LinearEstimate trial = estimate;
    if (!SolveYawTranslationScale(motions, q_yz, options, &trial)) {
      failure = trial.failure;
      continue;
    }
    if (!found || trial.step2_cost < best.step2_cost) {
      best = trial;
      found = true;
    }
  }
  if (!found) {
    estimate.failure = failure;
    return estimate;
  }
  best.success = true;
  return best;
}

LinearEstimate EstimateOdomFromCamLinear(const MotionPairs& pairs,
                                         const LinearOptions& options) {
  std::vector<int> indices(pairs.size());
  for (size_t i = 0; i < pairs.size(); ++i) {
    indices[i] = static_cast<int>(i);
  }
  return EstimateOdomFromCamLinear(pairs, indices, options);
}

}  // namespace odomcal
