// Result of the odometer-camera calibration (see calibrate.h).
#pragma once

#include "odomcal/solver/floor_plane.h"
#include "odomcal/solver/noise_estimation.h"
#include "odomcal/solver/observability.h"
#include "odomcal/solver/planarity_check.h"
#include "odomcal/solver/rigid3.h"
#include "odomcal/solver/scale_drift_covariance.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace odomcal {

enum class CalibrationStatus {
  kNotRun,            // the solver was not called
  kSuccess,           // every observable quantity is determined
  kNotEnoughMotion,   // too few pairs or too little rotation to start
  kUnobservable,      // some quantity is undetermined: see `observability`
  kInconsistentData,  // the data contradict the model (association, pose
                      // convention, negative scale, too many outliers)
  kRefinementFailed,  // Ceres failed; the closed-form estimate is kept
};

// "success", "not_enough_motion", ... (stable: part of the JSON schema).
std::string ToString(CalibrationStatus status);

struct CalibrationDiagnostics {
  int num_pairs_in = 0;
  int num_pairs_used = 0;
  std::vector<char> inlier_mask;  // per input pair: used in the final fit
  std::vector<int> num_pairs_per_segment;  // used pairs

  // Rotation excitation: yaw increments of the odometry motions.
  double yaw_increment_min_deg = 0.0;
  double yaw_increment_max_deg = 0.0;
  double yaw_increment_stddev_deg = 0.0;
  int num_rotating_pairs = 0;  // |yaw| >= min_rotation_deg
  int num_left_turns = 0;      // yaw >= min_rotation_deg
  int num_right_turns = 0;     // yaw <= -min_rotation_deg

  // Per pair | |angle(A_i)| - |angle(B_i)| |, degrees, and how many exceed
  // max_angle_mismatch_deg (an extrinsic cannot explain them).
  std::vector<double> angle_mismatch_deg;
  int num_angle_mismatches = 0;

  // Conditioning of the closed form. Step 1: eigenvalues of M^T M in
  // ascending order; they come in equal pairs (M^T M commutes with left
  // multiplication by z rotations), so the null-space quality is
  // eigenvalue[1] / eigenvalue[2] (0 noise-free, 1 undetermined).
  Eigen::Vector4d rotation_step_eigenvalues = Eigen::Vector4d::Zero();
  double rotation_step_ratio = 0.0;
  bool rotation_step_gimbal = false;  // camera z axis parallel to odometry z
  // Step 2: condition number of the column-normalised design matrix.
  double translation_step_condition_number = 0.0;

  // Post-fit residuals over the used pairs: rotation angle of
  // A_i^-1 X B_i X^-1 and norm of A_i X - X B_i translation.
  std::vector<double> rotation_residual_deg;   // per input pair
  std::vector<double> translation_residual_m;  // per input pair
  double rms_rotation_residual_deg = 0.0;
  double max_rotation_residual_deg = 0.0;
  double rms_translation_residual_m = 0.0;
  double max_translation_residual_m = 0.0;
  double relative_translation_residual = 0.0;  // RMS residual / RMS step
  // Weighted cost per degree of freedom (about 1 when the noise model fits).
  double reduced_chi_square = 0.0;

  // Out-of-plane motion under the estimate (planar odometry only).
  PlanarityCheck planarity;

  // The reconstruction's scale wandering inside the segments, and its term
  // in the covariance (scale_drift_covariance.h).
  ScaleDriftTerm scale_drift;

  // Closed-form estimate before refinement.
  Rigid3d linear_odom_from_cam;
  std::vector<double> linear_metric_scales;

  int ransac_num_iterations = 0;
  bool refined = false;
  int refinement_num_iterations = 0;
  std::string refinement_report;  // Ceres BriefReport()
};

// Translation z as a prior (options.translation_z_prior_sigma_m > 0): what
// the calibration held and what the data made of it. Not used when z is
// estimated (from SE(3) odometry or the floor) or held exactly (prior sigma
// 0).
struct TranslationZPrior {
  bool used = false;
  double held_m = 0.0;          // the prior's mean, fixed_translation_z_m
  double prior_stddev_m = 0.0;  // translation_z_prior_sigma_m
  // The data's own standard deviation of z (the others free; without the
  // scale drift term of CalibrationDiagnostics::scale_drift); infinite
  // where the data carry no information on z (planar odometry).
  double data_stddev_m = 0.0;
  // z and its standard deviation under the prior and the data: the held
  // value and the prior's sigma where the data carry no information.
  double estimate_m = 0.0;
  double stddev_m = 0.0;
  // The data's information on z is more than kMovedInformationRatio of the
  // prior's: z (and x, y with it) were estimated under the prior, and z is
  // the last row of the covariance.
  bool moved_by_data = false;
  static constexpr double kMovedInformationRatio = 0.01;
};

struct CalibrationResult {
  CalibrationStatus status = CalibrationStatus::kNotRun;
  std::string message = "CalibrateOdomCam() was not called.";

  // True when odom_from_cam and metric_scales hold an estimate (also for
  // kUnobservable / kInconsistentData, where it must not be trusted as a
  // whole: the CLI withholds the quantities `observability` does not
  // call estimated).
  bool has_estimate = false;
  // x_in_odom = odom_from_cam * x_in_cam; translation z is held at
  // options.fixed_translation_z_m unless observability.translation_z is
  // kEstimated (SE(3) odometry whose rotation axes are not all parallel).
  Rigid3d odom_from_cam;
  // Metres per reconstruction unit, one per segment.
  std::vector<double> metric_scales;

  // What the data determine; z is held under planar motion. The JSON
  // `unobservable` list is UnobservableNames(observability).
  Observability observability;
  std::vector<std::string> warnings;

  // Covariance, order [rx, ry, rz, tx, ty, one scale per segment with used
  // pairs (covariance_segments)] and, only when
  // translation z is estimated or moved by the data under its prior
  // (translation_z_prior.moved_by_data), tz last: rotation as a left
  // perturbation R = Exp(phi) R_hat in radians about the odometry axes,
  // translation in metres, scales in metres per reconstruction unit. A z
  // held exactly, or under a prior the data do not move, is excluded.
  std::optional<Eigen::MatrixXd> covariance;
  // Standard deviations derived from it.
  Eigen::Vector3d stddev_roll_pitch_yaw_deg = Eigen::Vector3d::Zero();
  Eigen::Vector3d stddev_rotation_axes_deg = Eigen::Vector3d::Zero();
  Eigen::Vector2d stddev_translation_xy_m = Eigen::Vector2d::Zero();
  double stddev_translation_z_m = 0.0;           // 0 unless z is estimated
  std::vector<double> stddev_metric_scales_rel;  // sigma_s / s

  CalibrationDiagnostics diagnostics;

  // The segment of each scale row of `covariance` (s_k is
  // metric_scales[covariance_segments[k]]): segments without used pairs
  // have no row.
  std::vector<int> covariance_segments;

  // The noise estimated from the data (options.estimate_noise), which the
  // covariance above uses; absent when not estimated.
  std::optional<NoiseEstimate> noise_estimate;

  // The floor under a COLMAP project's metric model (floor_plane.h), when
  // fitted, and why translation z is not taken from it (empty when it is).
  std::optional<FloorPlane> floor_plane;
  std::string floor_z_held_reason;

  // The held z as a prior and what the data made of it.
  TranslationZPrior translation_z_prior;

  bool IsSuccess() const { return status == CalibrationStatus::kSuccess; }
};

}  // namespace odomcal
