// Does the motion fit the planar model? Planar wheel odometry (x, y, yaw)
// cannot see roll, pitch or height: on a slope or a ramp the camera's true
// motion leaves the plane, the extrinsic's roll/pitch absorb part of it, and
// a covariance computed under the planar model is 10-30x too small
// (docs/robustness.md, "Modelling assumptions").
//
// Under the estimate X = odom_from_cam (q, p) and the segment scale s, each
// pair's camera motion mapped into the odometry frame, X B(s) X^-1, must turn
// about the odometry z axis and stay in its plane, as the planar odometry A
// does. Per pair, from the hand-eye residual of hand_eye_residual.h:
//   tilt     = [x, y] of Log(R_A^T R R_B R^T)  (radians; the out-of-plane
//              rotation of the camera motion relative to the odometry's)
//   height   = -(R_A p + t_A - s R t_B - p)_z   (metres; for planar A this is
//              (s R t_B)_z, the camera's displacement along odometry z)
// Their covariance under the noise model (or the pairs' covariances) gives a
// chi-square over the used pairs with 3 n - 2 degrees of freedom (roll and
// pitch were fitted to the same components). Above its 99.9 % point the
// motion is not planar (or the camera noise exceeds the noise model): the
// caller warns and inflates the covariance by the reduced chi-square times
// the residuals' correlation length along the drive.
//
// Only planar odometry is checked: with roll/pitch/z in the odometry (SE(3)
// poses) the motion may leave the plane legitimately.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace odomcal {

struct PlanarityCheck {
  bool checked = false;  // false: odometry not planar, or no estimate
  // Per input pair (0 for pairs not used in the fit), signed height in m.
  std::vector<double> tilt_deg;
  std::vector<double> out_of_plane_m;
  // Over the used pairs.
  double tilt_rms_deg = 0.0;
  double tilt_max_deg = 0.0;
  double out_of_plane_rms_m = 0.0;
  double out_of_plane_max_m = 0.0;  // largest |height|
  double chi_square = 0.0;
  int degrees_of_freedom = 0;
  double chi_square_threshold = 0.0;  // 99.9 % point
  double reduced_chi_square = 0.0;    // chi_square / degrees_of_freedom
  bool consistent = true;             // chi_square <= chi_square_threshold
  // Whether the excess is a finding to warn of: a slope biases a run of
  // neighbouring pairs alike (correlation_length >= kMinSlopeCorrelation),
  // or the excess is too large for a noise model a little off
  // (reduced_chi_square >= kMinNamedReducedChiSquare). An excess of a few
  // per cent spread evenly along the drive is the camera's noise level,
  // not a slope: the covariance is inflated all the same, without a
  // warning.
  bool named = false;
  // Integrated autocorrelation time of the whitened out-of-plane residuals
  // along the drive, in pairs (1: independent, as noise is).
  double correlation_length = 1.0;
  // Factor applied to the covariance (1 when consistent): the reduced
  // chi-square times the correlation length, since a slope biases a run of
  // neighbouring pairs alike; standard deviations grow by its square root.
  double covariance_inflation = 1.0;
  // The stretch of consecutive used pairs of one segment with the largest
  // chi-square (about a tenth of the drive, at least 3 pairs, at most the
  // segment's): where the ground tilts most.
  int64_t worst_first_stamp_ns = 0;
  int64_t worst_last_stamp_ns = 0;
  double worst_tilt_rms_deg = 0.0;
  double worst_out_of_plane_rms_m = 0.0;

  // The ground's tilt seen in the camera's rotation axes. On ground rolled
  // by r and pitched by p (about odometry x and y) a turn by yaw d turns
  // about the ground's normal, and the camera's rotation, mapped into the
  // odometry frame, tilts by d (-p, r) against the planar odometry's: a
  // signature proportional to the turn that no camera noise has. Per window
  // of kGroundWindowPairs consecutive used pairs the tilt is fitted to it;
  // the F statistic compares the tilt variance it explains with the rest,
  // so it holds whatever the noise level (the estimated camera rotation
  // noise absorbs the ground's tilt into its level, and a chi-square under
  // it does not see the ground).
  bool ground_tested = false;       // enough windows and pairs to test
  int ground_windows = 0;           // windows with a turn to fit the tilt
  double ground_f_statistic = 0.0;  // explained over residual tilt variance
  double ground_f_threshold = 0.0;  // its 99.9 % point
  bool ground_tilt_seen = false;    // ground_f_statistic > threshold
  // RMS over the windows of the ground's fitted roll (about odometry x) and
  // pitch (about y) against the level the estimate took as the odometry
  // plane, their fitting noise subtracted (0 when the noise explains them).
  double ground_roll_rms_deg = 0.0;
  double ground_pitch_rms_deg = 0.0;
  // Seen, and the ground's tilt variation above the stated standard
  // deviation of roll or pitch (set by the caller, who adds its covariance:
  // GroundTiltCovariance): the result carries GroundTiltWarning.
  bool ground_named = false;
};

// Consecutive used pairs per window of the ground-tilt fit: a road's grade
// and banking change over tens of metres; a window of 25 pairs keeps most
// of that variation and averages the camera noise.
inline constexpr int kGroundWindowPairs = 25;

// Measured on simulated 2-minute drives (scripts/warning_rates.sh, 30 seeds
// each): flat ground gives a correlation length of 1.00 and a reduced
// chi-square of 1.03-1.19 (the camera noise a little above the model);
// ground tilted +-3 deg gives 11-47 and 1.20-1.29.
inline constexpr double kMinSlopeCorrelation = 2.0;
inline constexpr double kMinNamedReducedChiSquare = 1.5;

// Largest out-of-plane rotation (radians; |qx|, |qy| of a pose) and height
// (metres) of an odometry motion or pose that still counts as planar: the
// one tolerance for "planar odometry" everywhere. Not zero, since a planar
// log read back through quaternions or another tool carries rounding errors
// (1e-16 to 1e-12); far below any real slope (1e-3 rad) or noise model.
constexpr double kPlanarTolerance = 1e-9;

// True when an odometry motion is a rotation about z and a translation in
// the x-y plane (to kPlanarTolerance).
bool IsPlanarMotion(const Rigid3d& odom_i_from_odom_j);

// True when every pair's odometry motion is planar (IsPlanarMotion): a
// planar log.
bool IsPlanarOdometry(const MotionPairs& pairs);

// Measures the above for `used` pairs under the estimate; checked = false
// when the odometry is not planar or fewer than 2 pairs are used.
PlanarityCheck CheckPlanarity(const MotionPairs& pairs,
                              const std::vector<int>& used,
                              const Rigid3d& odom_from_cam,
                              const std::vector<double>& metric_scales,
                              const NoiseModel& noise);

// The warning for an inconsistent check: the measured tilt, height, the
// excess over the noise and where along the drive (seconds since
// first_stamp_ns), e.g. "the motion is not planar: per motion pair the
// camera tilts 0.14 deg RMS (max 0.38 deg) and moves 1.22 mm RMS (max 3.81
// mm) out of the odometry plane, 2.60x the noise model's variance,
// correlated over 20.3 pairs; worst at 56.2-68.8 s (tilt 0.21 deg RMS).
// Planar odometry cannot see slopes or ramps (or the camera is noisier than
// the noise model): standard deviations inflated 7.25x".
std::string PlanarityWarning(const PlanarityCheck& check,
                             int64_t first_stamp_ns);

// Where the ground's tilt is seen: planar odometry sees neither it nor its
// mean over the drive, and a constant tilt G of the ground is exactly a
// different extrinsic G * odom_from_cam (rotation error the tilt, x and y
// error the camera's height times it). Its mean is taken to be as large as
// its variation along the drive: the covariance of (rx, ry, tx, ty) under
// a tilt of standard deviation ground_roll_rms_deg about x and
// ground_pitch_rms_deg about y, for a camera height of mean height_m and
// second moment height_m2 (calibrate.cc: the held z, and the square of its
// prior's 2 sigma bound). Zero when not seen.
Eigen::Matrix4d GroundTiltCovariance(const PlanarityCheck& check,
                                     double height_m,
                                     double height_m2);

// The warning for a named ground tilt, with the standard deviations of
// roll and pitch before and after its covariance, e.g. "the ground is not
// level: the camera's rotation axes show its roll varying by 1.1 deg RMS
// and its pitch by 0.88 deg RMS along the drive (F = 45, threshold 1.6),
// which planar odometry cannot see; a mean tilt of that size moves roll and
// pitch by as much and x, y by the camera's height times it: their standard
// deviations include it (roll 0.03 -> 1.1 deg, pitch 0.03 -> 0.88 deg)".
std::string GroundTiltWarning(const PlanarityCheck& check,
                              const Eigen::Vector2d& stddev_before_deg,
                              const Eigen::Vector2d& stddev_after_deg);

}  // namespace odomcal
