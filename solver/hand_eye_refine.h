// Batch refinement of the odometer-camera extrinsic and the metric scales
// (Guo et al. ICRA 2012, eq. 24) with Ceres, and its covariance.
//
// Minimises sum_i rho(|W_i r_i|^2) over the rotation q (on the unit
// quaternion manifold), p_x, p_y and one log-scale per segment, with p_z held
// at options.fixed_translation_z_m (unobservable under planar motion) or,
// with TranslationZ::kEstimate, estimated too (SE(3) odometry whose
// rotation axes are not all parallel), or, with TranslationZ::kPrior,
// estimated under the prior N(options.fixed_translation_z_m,
// options.translation_z_prior_sigma_m^2) (SE(3) odometry that carries too
// little information on z to determine it).
// r_i and W_i are defined in hand_eye_residual.h; W_i is evaluated once at the
// initial estimate. rho is the identity or the robust loss of the options.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace odomcal {

// Translation z: held at options.fixed_translation_z_m, a free parameter
// starting from the initial estimate's z, or a free parameter under its prior
// (the cost gets ((p_z - fixed_translation_z_m) /
// translation_z_prior_sigma_m)^2; the information stays the data's alone, the
// caller adds the prior's).
enum class TranslationZ { kHold, kEstimate, kPrior };

// Whether RefineOdomFromCam evaluates the information at its solution; a
// caller that refines in rounds and keeps one of them asks for it later
// (RefinementInformation), at the cost of one Jacobian evaluation instead of
// one per round.
enum class InformationAtSolution { kCompute, kSkip };

// The solver's parameter blocks at the solution, as they are (Rigid3d and the
// scales are their normalised / exponentiated images).
struct RefinementParameters {
  double quaternion[4] = {0.0, 0.0, 0.0, 1.0};  // x, y, z, w
  double p_xy[2] = {0.0, 0.0};
  double p_z = 0.0;
  std::vector<std::pair<int, double>> log_scales;  // (segment, log s)
};

struct RefinementResult {
  bool usable = false;  // Ceres' IsSolutionUsable()
  Rigid3d odom_from_cam;
  std::vector<double> metric_scales;  // NaN for segments without pairs
  int num_iterations = 0;
  double initial_cost = 0.0;  // Ceres cost, 1/2 sum rho(|W r|^2)
  double final_cost = 0.0;
  std::string report;  // Ceres BriefReport()

  // Fisher information J^T J at the solution in the order
  // [rx, ry, rz, tx, ty, s_k for each segment with pairs] and, with
  // TranslationZ::kEstimate or kPrior only, tz last (the data's information
  // alone, without the prior's): rotation as a left perturbation in
  // radians (Ceres' quaternion tangent is half of it), translation in metres,
  // scales in metres per reconstruction unit.
  Eigen::MatrixXd information;  // empty with InformationAtSolution::kSkip
  std::vector<int> information_segments;  // segment of each scale column
  RefinementParameters parameters;
};

// Refines from `initial` / `initial_scales` (indexed by segment) using
// pairs[indices]. Segments without pairs among `indices` are left out.
RefinementResult RefineOdomFromCam(
    const MotionPairs& pairs,
    const std::vector<int>& indices,
    const Rigid3d& initial,
    const std::vector<double>& initial_scales,
    const CalibrationOptions& options,
    TranslationZ z = TranslationZ::kHold,
    InformationAtSolution information = InformationAtSolution::kCompute);

// The information RefineOdomFromCam would have computed for `refined`, the
// result of a call with the same pairs, indices, starting point, options and
// z: the same weights (evaluated at the starting point) at the same
// parameters, so the same bits.
Eigen::MatrixXd RefinementInformation(const MotionPairs& pairs,
                                      const std::vector<int>& indices,
                                      const Rigid3d& initial,
                                      const std::vector<double>& initial_scales,
                                      const CalibrationOptions& options,
                                      TranslationZ z,
                                      const RefinementResult& refined,
                                      std::vector<int>* information_segments);

// Information matrix only, at a fixed estimate (no optimisation); same order
// and conventions as RefinementResult::information.
Eigen::MatrixXd HandEyeInformation(const MotionPairs& pairs,
                                   const std::vector<int>& indices,
                                   const Rigid3d& odom_from_cam,
                                   const std::vector<double>& metric_scales,
                                   const CalibrationOptions& options,
                                   std::vector<int>* information_segments,
                                   TranslationZ z = TranslationZ::kHold);

// The information and, per pair of `indices`, the change of the fit's
// gradient J^T r per relative change of that pair's camera translation alone
// (its scale): column p of `scale_sensitivity` is J_p^T dr_p/d(log s), J_p
// the pair's whitened Jacobian, in the information's order and coordinates.
// Relative scale errors e of the pairs move the estimate by -H^-1 B e to
// first order (scale_drift_covariance.h). Both empty where the starting point
// is not valid (a pair without a positive scale).
struct HandEyeSensitivity {
  Eigen::MatrixXd information;
  Eigen::MatrixXd scale_sensitivity;
  std::vector<int> information_segments;
};
HandEyeSensitivity HandEyeScaleSensitivity(
    const MotionPairs& pairs,
    const std::vector<int>& indices,
    const Rigid3d& odom_from_cam,
    const std::vector<double>& metric_scales,
    const CalibrationOptions& options,
    TranslationZ z = TranslationZ::kHold);

}  // namespace odomcal
