// RANSAC over motion pairs around the analytical least-squares solution.
//
// A hypothesis is the closed form (hand_eye_linear.h) on a minimal sample of
// two pairs from one segment; the other segments' scales follow as the median
// of the per-pair one-dimensional least-squares scales. A pair is an inlier
// when both its rotation residual angle and its translation residual norm
// (hand_eye_residual.h) are below the thresholds of CalibrationOptions; the
// translation threshold grows with the odometry step length. Each new best
// hypothesis is re-estimated on its inliers (local optimisation). The number
// of iterations adapts to the inlier ratio for the requested confidence.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <vector>

namespace odomcal {

struct PairError {
  double rotation_deg = 0.0;
  double translation_m = 0.0;
};

// Rotation residual angle and translation residual norm of one pair.
PairError EvaluatePair(const MotionPair& pair,
                       const Rigid3d& odom_from_cam,
                       double metric_scale);

// Inlier test of RANSAC, see above.
bool IsInlier(const MotionPair& pair,
              const Rigid3d& odom_from_cam,
              double metric_scale,
              const CalibrationOptions& options);

// Fills every NaN entry of `metric_scales` (resized to num_segments) whose
// segment has pairs among `indices` with the median of the pairs' own
// least-squares scales under `odom_from_cam`.
void CompleteMetricScales(const MotionPairs& pairs,
                          const std::vector<int>& indices,
                          int num_segments,
                          const Rigid3d& odom_from_cam,
                          std::vector<double>* metric_scales);

// MSAC score of a model over pairs[indices] (lower is better): each inlier
// adds its squared normalised error, each outlier 1. Fills `inliers`.
double RansacScore(const MotionPairs& pairs,
                   const std::vector<int>& indices,
                   const Rigid3d& odom_from_cam,
                   const std::vector<double>& metric_scales,
                   const CalibrationOptions& options,
                   std::vector<int>* inliers);

struct RansacResult {
  bool success = false;
  std::vector<char> inlier_mask;  // per pair
  int num_inliers = 0;
  int num_iterations = 0;
  Rigid3d odom_from_cam;              // best model, re-fitted on inliers
  std::vector<double> metric_scales;  // per segment
};

// Candidates are pairs[indices]; the mask covers all of `pairs`.
RansacResult RansacOdomFromCam(const MotionPairs& pairs,
                               const std::vector<int>& indices,
                               const CalibrationOptions& options);

}  // namespace odomcal
