// The floor the robot drives on, from the metric model: the sixth degree of
// freedom of the extrinsic (the camera's height, translation z), which
// planar motion cannot observe (Guo et al., Section IV-B).
//
// Input: the model's 3D points and camera poses in metres in the odometry's
// origin frame (z up, REP 103), aligned with the extrinsic whose z is held.
// Candidates are the points below the lowest camera within
// max_path_distance_m (horizontally) of a camera centre. RANSAC (MSAC
// scores) over planes within max_tilt_deg of level finds the floor; a
// weighted least-squares refit on its inliers (weights 1 / sigma_i^2, the
// points' triangulation uncertainty, with iterated 3-sigma rejection) gives
// the plane z = c + a (x - x0) + b (y - y0). Its covariance is the larger
// of the fit's (scaled by the a-posteriori variance factor) and a
// delete-a-block jackknife over blocks of the drive (points share their
// cameras' errors, so the fit alone would be overconfident); the plane's
// tilt also takes a jackknife over parts near and far from the cameras
// (FloorPlane::tilt_parts).
//
// The camera height H is the mean perpendicular distance of the camera
// centres above the plane; z = H - odometry_height_m (the odometry frame's
// origin above the floor: 0 for REP 120's base_footprint). The floor also
// measures the camera's roll and pitch: the floor's normal seen from each
// camera (the model's camera orientations, no odometry), rotated into the
// odometry frame by the motion's extrinsic, should be up. The small left
// rotation phi (about the odometry's x and y axes) that makes it up is the
// floor's correction to the motion's roll and pitch; its chi-square against
// the motion's covariance and the floor's is the cross-check. A floor whose
// tilt is too uncertain for these checks to catch a max_slope_deg error
// does not give z (kTiltUncertain).
#pragma once

#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace odomcal {

// What the floor is used for.
enum class FloorPlaneUse {
  kOff,        // not fitted
  kCheck,      // fitted and cross-checked; z stays held at its given value
  kEstimateZ,  // z from the floor where the floor is seen well enough
};

std::string ToString(FloorPlaneUse use);  // "off", "check", "estimate"
// Throws std::invalid_argument naming the valid values.
FloorPlaneUse FloorPlaneUseFromString(const std::string& name);

struct FloorPlaneOptions {
  FloorPlaneUse use = FloorPlaneUse::kEstimateZ;
  // Height of the odometry frame's origin above the floor (REP 120's
  // base_footprint: 0; base_link: the wheel radius, typically).
  double odometry_height_m = 0.0;
  // Candidate points: at most this far (horizontally) from a camera centre
  // and at least min_depth_below_cameras_m below the lowest camera.
  double max_path_distance_m = 3.0;
  double min_depth_below_cameras_m = 0.05;
  // Planes more tilted than this in the odometry frame are not the floor.
  double max_tilt_deg = 10.0;
  double ransac_inlier_distance_m = 0.02;
  int ransac_iterations = 1000;
  uint64_t ransac_seed = 1;
  // Fewer inliers than this: the floor is not seen well enough.
  int min_inliers = 50;
  // More candidates beside the plane than this times its inliers: no plane
  // stands out (kNotDistinct).
  double max_beside_ratio = 0.5;
  // A floor tilted against the plane the robot drives in (the origin
  // frame's x-y plane) by more than this, beyond the tilt's chi-square
  // test, is sloped: z stays held. The floor's tilt must also be known well
  // enough that a slope or a roll/pitch contradiction of this size fails
  // its chi-square test (a standard deviation up to max_slope_deg /
  // sqrt(threshold), 0.13 deg at the defaults); else z stays held.
  double max_slope_deg = 0.5;
  // The model's camera orientations against its own floor, common to every
  // part of it (so neither the fit nor the parts' jackknife and spread see
  // it): a standard deviation per axis added to the roll/pitch correction's.
  // Corrections of 0.015-0.020 deg RMS per axis on the rendered level scenes
  // (docs/floor_plane.md).
  double common_orientation_sigma_deg = 0.02;
  // The chi-square tests (2 dof: the floor's tilt, and its roll/pitch
  // against the motion's) at this false-alarm probability.
  double disagreement_alpha = 0.001;
  // Throws std::invalid_argument naming the field.
  void Check() const;
};

// A 3D point of the metric model, in metres in the origin frame.
struct FloorCandidatePoint {
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  double sigma_m = 0.01;  // standard deviation of its position (isotropic)
  // The nearest camera that observed it (an index into the cameras; -1:
  // unknown, then the camera nearest to it horizontally) and its distance
  // from that camera (0: unknown, then the distance to that camera's
  // centre).
  int camera = -1;
  double distance_m = 0.0;
};

// A camera of the metric model and the calibration segment whose scale
// placed it.
struct FloorCamera {
  Rigid3d origin_from_cam;
  int segment = 0;
};

enum class FloorPlaneStatus {
  kNotRun,               // use == kOff or no model
  kFitted,               // a level plane, consistent with the motion
  kTooFewPoints,         // fewer than min_inliers on the best plane
  kNotLevel,             // no plane within max_tilt_deg of level
  kNotDistinct,          // as many points beside the plane as on it
  kSloped,               // tilted against the plane driven in
  kDisagreesWithMotion,  // its roll/pitch contradict the motion's
  kTiltUncertain,        // its tilt too uncertain to tell a max_slope_deg
                         // slope or roll/pitch error
};
std::string ToString(FloorPlaneStatus status);

struct FloorPlane {
  FloorPlaneStatus status = FloorPlaneStatus::kNotRun;
  // Why the floor does not give z (empty when it is fitted).
  std::string reason;
  int num_candidates = 0;
  int num_inliers = 0;
  // Candidates in the bands beside the plane (between one and two inlier
  // distances from it, both sides): a floor is a peak of the points'
  // heights; a level slice through vertical surfaces has as many beside it.
  int num_beside = 0;
  double inlier_rms_m = 0.0;
  // The plane n . x = offset in the origin frame, n up (unit).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset_m = 0.0;
  // Its tilt from level in the origin frame (against the plane the robot
  // drives in) and the tilt's chi-square (2 dof) under the plane's
  // covariance.
  double tilt_deg = 0.0;
  double tilt_chi_square = 0.0;
  // The plane's parameters z = c + a (x - x0) + b (y - y0) and their
  // covariance (order a, b, c).
  Eigen::Vector2d reference_xy = Eigen::Vector2d::Zero();
  Eigen::Vector3d parameters = Eigen::Vector3d::Zero();
  Eigen::Matrix3d parameter_covariance = Eigen::Matrix3d::Zero();

  // Mean perpendicular height of the camera centres above the plane, its
  // standard deviation from the plane (scale excluded) and the spread (RMS
  // about the mean) over the cameras.
  double camera_height_m = 0.0;
  // options.odometry_height_m, for the writers: z = camera_height_m - it.
  double odometry_height_m = 0.0;
  double camera_height_stddev_m = 0.0;
  double camera_height_spread_m = 0.0;
  // Set by the caller that fitted the same floor on a second model of the
  // same images (the joint adjustment's, where the check kept the
  // two-step's): that model's camera height minus this one's. The two
  // models share the images and the points' tracks but not their shape, so
  // the difference measures what neither fit's own variance holds (a road
  // model's ground sitting a few millimetres high); camera_height_stddev_m
  // then includes its square. NaN: not compared.
  double camera_height_model_difference_m =
      std::numeric_limits<double>::quiet_NaN();
  // Set by the caller whose model's cameras have two focal lengths: the
  // camera height times |pixel_aspect_change - 1|. Motion in a plane fixes
  // the focal length across it (fx of a level camera) but not the one along
  // its normal: a bundle adjustment that moved fy against fx stretched the
  // model's vertical, and the camera height with it, by about that change.
  // camera_height_stddev_m then includes its square. 0: no change.
  double camera_height_pixel_aspect_m = 0.0;
  // fx / fy of the model's camera over its value before the bundle
  // adjustment (the database's, else square pixels), furthest from 1.
  double pixel_aspect_change = 1.0;
  // Per segment: d camera_height_m / d metric_scale (metres per (metre per
  // unit)): the height in reconstruction units times the segment's share of
  // the cameras.
  std::vector<double> height_per_scale;

  // The floor's own tilt error, measured on this run from parts of the
  // inliers: thirds by their distance from the camera that saw them (near,
  // middle, far bands) times four stretches of the drive (by that camera).
  // The tilt's and the roll/pitch correction's covariances are the larger
  // (by trace) of the fit's, the drive's jackknife and a delete-a-part
  // jackknife over these parts, plus tau^2 per axis: triangulation error
  // growing with distance, grazing views and a model that bends tilt the
  // bands differently, and tau (tilt_band_sigma_rad) is the standard
  // deviation of the bands' roll/pitch corrections (each band fitted alone)
  // beyond their fits' (Paule-Mandel, the larger of the two axes). It is
  // not divided by the number of bands: such errors are shared.
  // tilt_parts_sigma_rad: the part jackknife's largest standard deviation
  // of the roll/pitch correction.
  int tilt_parts = 0;  // parts refitted (0: not measured)
  double tilt_parts_sigma_rad = 0.0;
  double tilt_band_sigma_rad = 0.0;

  // The floor's correction to the motion's roll and pitch: odom_from_cam's
  // rotation as the floor sees it is Exp(phi) * R (left perturbation about
  // the odometry axes), phi = (phi_x, phi_y, 0) in radians, with its
  // covariance from the floor alone; the floor's roll and pitch (degrees,
  // R = Rz(yaw) Ry(pitch) Rx(roll)); the chi-square of phi against the sum
  // of both covariances (2 dof).
  Eigen::Vector2d roll_pitch_correction_rad = Eigen::Vector2d::Zero();
  Eigen::Matrix2d roll_pitch_correction_covariance = Eigen::Matrix2d::Zero();
  double floor_roll_deg = 0.0;
  double floor_pitch_deg = 0.0;
  double disagreement_chi_square = 0.0;
  double disagreement_threshold = 0.0;

  bool Fitted() const { return status == FloorPlaneStatus::kFitted; }
};

// Fits the floor under `cameras` among `points`. `odom_from_cam` is the
// motion's extrinsic (its rotation for the cross-check), `roll_pitch_
// covariance` the motion's covariance of (rx, ry) (the first two rotation
// rows of CalibrationResult::covariance), `metric_scales` the segments'
// scales. Throws std::invalid_argument for bad options; never throws for
// data: a floor it cannot see gets a status and a reason.
FloorPlane FitFloorPlane(const std::vector<FloorCandidatePoint>& points,
                         const std::vector<FloorCamera>& cameras,
                         const Rigid3d& odom_from_cam,
                         const Eigen::Matrix2d& roll_pitch_covariance,
                         const std::vector<double>& metric_scales,
                         const FloorPlaneOptions& options);

}  // namespace odomcal
