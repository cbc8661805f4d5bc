// A delete-a-group jackknife of the joint adjustment's extrinsic: the drive
// is cut into contiguous blocks of images, the adjustment solved again
// without each block (its images, their feature observations and the
// odometry links that touch them), and the spread of the re-solved
// extrinsics gives a covariance that does not rest on the noise model
// (Efron & Stein; Shao & Tu, "The Jackknife and Bootstrap", 1995, ch. 5.3
// for groups):
//
//   V = (g - 1) / g * sum_b (theta_b - mean)(theta_b - mean)^T
//
// over the g re-solved extrinsics theta_b. It counts errors the model's
// covariance and the per-track sandwich miss: image errors correlated over
// many features and images of one stretch of the drive (texture, lighting,
// a systematic feature bias), which average out only between stretches.
// Errors common to the whole drive stay out of any within-drive estimate.
//
// The stated covariance keeps the model's correlations and widens each
// standard deviation to the largest of the model's, the sandwich's and the
// jackknife's. On a rig (several mounts) the positive part of the
// jackknife's covariance minus that is added too, so that every combination,
// a camera-to-camera difference among them, is at least the jackknife's
// spread of it.
#pragma once

#include "odomcal/solver/joint_adjustment.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace odomcal {

struct JointJackknifeOptions {
  // Blocks of consecutive images; 0 turns the jackknife off. With g blocks
  // the estimate has g - 1 degrees of freedom (its standard deviation
  // scatters by about 1 / sqrt(2 (g - 1)) relative).
  int num_blocks = 8;
  // Throws std::invalid_argument naming the option.
  void Check() const;
};

struct JointJackknife {
  bool ran = false;
  std::string reason;  // why not, when !ran
  int num_blocks = 0;  // re-solves that succeeded and entered the estimate
  // The jackknife covariance of [rx, ry, rz, tx, ty] (order and units of
  // JointAdjustmentResult::covariance).
  Eigen::Matrix<double, 5, 5> covariance = Eigen::Matrix<double, 5, 5>::Zero();
  // Per component, the jackknife standard deviation over the model's.
  Eigen::Matrix<double, 5, 1> ratio = Eigen::Matrix<double, 5, 1>::Zero();
  // On a rig: the same over every mount (mount 0 first, as
  // JointAdjustmentResult::mounts_covariance); covariance and ratio are
  // mount 0's.
  Eigen::MatrixXd mounts_covariance;
  Eigen::VectorXd mounts_ratio;
  double time_s = 0.0;
};

// Every mount's extrinsic in `estimate` as a deviation from `reference`'s,
// in the covariance's coordinates (JointAdjustmentResult::
// mounts_covariance): per mount, the left rotation perturbation, then
// translation x, y. Both results must have the same mounts.
Eigen::VectorXd MountDeviations(const JointAdjustmentResult& reference,
                                const JointAdjustmentResult& estimate);

// `image_order`: the problem's image indices in time order (the blocks are
// runs of it). `result`: AdjustJointly(problem, options)'s successful
// result; its covariances (mount 0's and every mount's) and their widening
// are widened in place where the jackknife's is larger. A block whose re-solve
// fails is left out; with fewer than 3 blocks left the jackknife does not run
// (`reason`) and `result` is unchanged.
JointJackknife JackknifeJointExtrinsic(const JointAdjustmentProblem& problem,
                                       const JointAdjustmentOptions& options,
                                       const std::vector<int>& image_order,
                                       const JointJackknifeOptions& jackknife,
                                       JointAdjustmentResult* result);

}  // namespace odomcal
