// One bundle adjustment of the images, the wheel odometry and the extrinsic,
// in metres in the odometry's origin frame.
//
// Unknowns:
//   - per image, the robot's pose origin_from_odom_i: with kPlanar its
//     (x, y, yaw), the planar-motion model of the two-step calibration, in
//     which the odometry frame moves in the origin's x-y plane; with kSE3
//     (a 3-D log) and kOnGround (a planar log on ground that may pitch and
//     bank) the whole pose, (x, y, z) and yaw, pitch, roll
//     (R = Rz(yaw) Ry(pitch) Rx(roll)), so that the robot follows the road;
//   - the shared odom_from_cam, its translation z held (unobservable under
//     planar motion); on a rig, one odom_from_cam per mount (a camera's
//     place on the robot), each image that of its mount, all tied to the
//     one robot trajectory;
//   - the 3D points, in metres in the origin frame;
//   - the camera intrinsics when options.refine_intrinsics (else held):
//     one scale on the focal length(s) and the distortion, the principal
//     point held (camera_intrinsics_manifold.h).
// A point enters when two of its images' rays meet at
// options.min_triangulation_angle_deg or more.
// Residuals:
//   - reprojection: observed pixel minus the projection of the point through
//     cam_from_odom * Inverse(origin_from_odom_i), divided by the pixel
//     sigma, under a robust loss;
//   - odometry: for each link, the motion the poses imply minus the
//     measured one, whitened by the link's covariance: planar (x, y in the
//     first pose's frame, yaw), or with kSE3 the rotation's and the
//     translation's difference (OdometryLink::motion_3d); with kOnGround
//     the planar part as measured, and the tilt change and the height
//     between the link's poses, which a planar log does not measure, over
//     the ground's bounds (GroundBoundsOf, joint_adjustment_cost.h): the
//     robot moves in its own x-y plane, the ground's tilt rate (deg per
//     metre) estimated from the residuals as the odometry's level is.
// The images tie the long spans (COLMAP's model has no drift within the
// images' overlap) and the odometry fixes the metric scale and what the
// images leave weak; each fixes what the other cannot, so the metric model
// carries neither COLMAP's scale drift nor the odometry's.
//
// Gauge: the problem is invariant to one planar motion (kSE3: one rigid
// motion) of everything per connected component (images joined by links or
// shared points); the first image of each component keeps its starting
// pose. The extrinsic does not depend on that choice.
//
// Covariance of the extrinsic: the inverse of the Gauss-Newton information
// J^T J at the solution, over all unknowns (poses, points, intrinsics when
// refined), restricted to the extrinsic's rows: the marginal covariance
// over poses and points, each standard deviation widened to the
// cluster-robust one (a point's observations, or a link, one cluster) where
// that is larger, as where a feature's errors are correlated along its
// track. The pixel sigma is estimated from the residuals
// (a robust scale of the inliers), and the odometry's level from its
// residuals (one factor on the links' covariances), and the problem solved
// again at them, so that the images and the odometry weigh as their noise
// says and the covariance states the noise the data show.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/camera_projection.h"
#include "odomcal/solver/odometry_intrinsics.h"
#include "odomcal/solver/planar_pose.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct JointCamera {
  ProjectionModel model = ProjectionModel::kPinhole;
  // ProjectionNumParams(model) values in COLMAP's order and pixel
  // convention (camera_projection.h).
  std::vector<double> params;
  // Held even with JointAdjustmentOptions::refine_intrinsics (intrinsics
  // known: given and kept fixed).
  bool held = false;
};

// The robot's poses and the odometry's links (see the top).
enum class RobotMotionModel {
  kPlanar,    // (x, y, yaw); links OdometryLink::odom_i_from_odom_j
  kSE3,       // the whole pose; links OdometryLink::motion_3d
  kOnGround,  // the whole pose; links OdometryLink::odom_i_from_odom_j
};
const char* ToString(RobotMotionModel model);

struct JointImage {
  int camera = 0;  // index into JointAdjustmentProblem::cameras
  // Starting value; with RobotMotionModel::kPlanar only its x, y and yaw
  // (PlanarFromRigid) are used.
  Rigid3d origin_from_odom;
  // Which odom_from_cam the image was taken through: 0 is
  // JointAdjustmentProblem::odom_from_cam, k > 0 other_mounts[k - 1].
  int mount = 0;
};

struct JointObservation {
  int image = 0;                                    // index into images
  int point = 0;                                    // index into points
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // the camera's convention
};

// The odometry's whole motion between two images' times (kSE3 links) and
// its covariance, order [rotation (3), translation (3)], the rotation as a
// left perturbation R = Exp(phi) R_hat in radians, the translation in
// metres (MotionCovariance, motion_pair.h).
struct OdometryMotion3d {
  Rigid3d odom_i_from_odom_j;
  Eigen::Matrix<double, 6, 6> covariance =
      Eigen::Matrix<double, 6, 6>::Identity();
};

// The odometry's planar motion from image_i's time to image_j's, and its
// covariance, order (x, y, yaw), metres and radians.
struct OdometryLink {
  int image_i = 0;
  int image_j = 0;
  PlanarPose odom_i_from_odom_j;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  // The logged odometry between the two images' times (as the log holds
  // it, before any intrinsics correction): required with
  // JointAdjustmentProblem::systematics, which then measures the link by
  // re-integrating it (odom_i_from_odom_j is not used).
  std::optional<OdometrySamples> samples;
  // The whole motion: required with RobotMotionModel::kSE3, which measures
  // the link by it (the planar fields are not used).
  std::optional<OdometryMotion3d> motion_3d;
};

// The odometry's systematic errors refined with everything else: its
// intrinsics (odometry_intrinsics.h) and a change of the clock offset (s,
// the odometry's times at the images later by it), started from the
// two-step estimate.
struct JointSystematics {
  OdometryIntrinsics intrinsics;  // start; wheel_track_m is given, held
  // [yaw_scale, yaw_per_metre_rad, yaw_rate_bias_rad_s]: refined or held.
  std::array<bool, 3> refine_intrinsics{};
  bool refine_time_offset = false;
  double time_offset_change_s = 0.0;  // start of the offset's change
};

struct JointAdjustmentProblem {
  std::vector<JointCamera> cameras;
  std::vector<JointImage> images;
  std::vector<Eigen::Vector3d> points;  // starting values, metres, origin
  std::vector<JointObservation> observations;
  std::vector<OdometryLink> links;
  // kSE3 where the odometry measures the whole motion (a 3-D log), not
  // with systematics (a planar log's); kOnGround where a planar log's robot
  // may tilt with the ground.
  RobotMotionModel motion_model = RobotMotionModel::kPlanar;
  Rigid3d odom_from_cam;  // starting value; its translation z is held
  // A rig's further cameras: the starting odom_from_cam of mounts 1, 2, ...
  // (JointImage::mount), each with its translation z held. Every mount
  // needs images. Their robot poses share one trajectory: the odometry
  // links join images of any mounts (unsynchronised cameras: each image at
  // its own time).
  std::vector<Rigid3d> other_mounts;
  // When set, the links are re-integrated from their samples with refined
  // systematics, whose uncertainty then enters the extrinsic's covariance.
  std::optional<JointSystematics> systematics;
};

// Where the adjustment is, for a caller's progress display.
struct JointAdjustmentProgress {
  int pass = 0;          // 1-based solve pass (of at most 4)
  int iteration = 0;     // Ceres iteration within the pass
  double cost = 0.0;     // Ceres' cost after it
  double seconds = 0.0;  // since the adjustment (or jackknife) started
  // The jackknife's re-solves (joint_adjustment_jackknife.h): which one of
  // how many; 0 of 0 for the adjustment itself.
  int replicate = 0;
  int num_replicates = 0;
};

struct JointAdjustmentOptions {
  // Starting pixel sigma; the adjustment estimates it (see the top).
  double pixel_sigma = 1.0;
  // Robust loss on the reprojection residuals, in pixel sigmas.
  RobustLoss loss = RobustLoss::kHuber;
  double loss_scale = 3.0;
  // Observations whose residual exceeds this many pixel sigmas after the
  // first solve are left out of the second (and reported).
  double max_reprojection_sigmas = 5.0;
  // A point whose rays (from the starting poses of the images that see it)
  // meet at less than this angle, degrees, stays out of the problem: its
  // depth rests on the pixel noise alone, and a track seen from one place
  // (a camera turning on the spot) leaves it undetermined. COLMAP's
  // mapper filters at the same angle (Mapper.filter_min_tri_angle).
  double min_triangulation_angle_deg = 1.5;
  bool refine_intrinsics = false;
  // Scale the links' covariances by one factor estimated from their
  // residuals (the images tie the poses, so the odometry's residuals show
  // its real level); held at the given covariances otherwise.
  bool estimate_odometry_noise = true;
  // RobotMotionModel::kOnGround: the ground's tilt rate, degrees of tilt
  // change per metre of travel, at the start; estimated from the links'
  // out-of-plane residuals (within [0.001, 20]) unless held.
  double ground_tilt_rate_deg_per_m = 1.0;
  bool estimate_ground_tilt_rate = true;
  int max_num_iterations = 100;
  int num_threads = 1;
  // The extrinsic's covariance at the solution (off for re-solves whose
  // point estimate alone is wanted, as the jackknife's).
  bool compute_covariance = true;
  // Called after every solver iteration (on the calling thread), when set.
  // It must not throw.
  std::function<void(const JointAdjustmentProgress&)> progress;
  // Throws std::invalid_argument naming the option.
  void Check() const;
};

enum class JointAdjustmentStatus {
  kSuccess,
  kInvalidInput,   // indices out of range, too few links, ...
  kNoConvergence,  // Ceres did not converge
  kSingular,       // the information matrix is singular (not observable)
};
const char* ToString(JointAdjustmentStatus status);

struct JointAdjustmentResult {
  JointAdjustmentStatus status = JointAdjustmentStatus::kInvalidInput;
  std::string message;  // why, when not kSuccess

  Rigid3d odom_from_cam;
  // Order [rx, ry, rz, tx, ty]: rotation as a left perturbation
  // R = Exp(phi) R_hat in radians about the odometry axes, translation in
  // metres (z held), as CalibrationResult::covariance.
  Eigen::Matrix<double, 5, 5> covariance = Eigen::Matrix<double, 5, 5>::Zero();
  // Per [rx, ry, rz, tx, ty], the factor (>= 1) on the model's standard
  // deviation that `covariance` holds: the cluster-robust one over the
  // model's where larger (joint_adjustment_covariance.h); the jackknife
  // (joint_adjustment_jackknife.h) widens both further where its spread is
  // larger.
  Eigen::Matrix<double, 5, 1> covariance_widening =
      Eigen::Matrix<double, 5, 1>::Ones();
  // The other mounts' odom_from_cam (JointAdjustmentProblem::other_mounts).
  std::vector<Rigid3d> other_mounts;
  // Every mount's [rx, ry, rz, tx, ty], mount by mount (mount 0 first:
  // `covariance` is its top-left block), with the cross terms between
  // mounts (one trajectory and, where they share points, one scene);
  // widened per row as `covariance`, by `mounts_covariance_widening`.
  Eigen::MatrixXd mounts_covariance;
  Eigen::VectorXd mounts_covariance_widening;
  // The problem's model of the robot's poses.
  RobotMotionModel motion_model = RobotMotionModel::kPlanar;
  // Per image; level (z, roll and pitch 0) with RobotMotionModel::kPlanar.
  std::vector<Rigid3d> origin_from_odom;
  // With whole poses: the largest angle between an image's odometry z axis
  // and the origin's (the gauge image's start), degrees: how far the
  // ground pitched and banked along the drive.
  double max_robot_tilt_deg = 0.0;
  // kOnGround: the ground's tilt rate at the solution (estimated or held).
  double ground_tilt_rate_deg_per_m = 0.0;
  std::vector<Eigen::Vector3d> points;  // metres, origin frame
  std::vector<JointCamera> cameras;     // refined or as given
  // With systematics: the refined intrinsics, the clock offset's change
  // (odometry_time = camera_time + the given offset + this) and their
  // standard deviations (0 where held).
  OdometryIntrinsics intrinsics;
  double time_offset_change_s = 0.0;
  std::array<double, 3> intrinsics_stddev{};
  double time_offset_change_stddev_s = 0.0;
  // Per observation: the norm of its reprojection residual at the solution
  // in pixels, or -1 where it was not used (its point seen in fewer than
  // two images, or beyond max_reprojection_sigmas).
  std::vector<double> observation_error_px;

  double pixel_sigma = 0.0;  // estimated
  // sqrt of the odometry's variance factor against the links' covariances
  // (1 when not estimated); bounded to [0.1, 10].
  double odometry_sigma_ratio = 1.0;
  // Root mean square of the reprojection residuals of the inliers, pixels,
  // at the start and at the solution.
  double reprojection_rms_px_before = 0.0;
  double reprojection_rms_px_after = 0.0;
  // Root mean square of the odometry residuals whitened by the links' given
  // covariances (1 when they fit), at the start and at the solution.
  double odometry_rms_sigma_before = 0.0;
  double odometry_rms_sigma_after = 0.0;
  int num_observations_used = 0;
  int num_observations_left_out = 0;  // beyond max_reprojection_sigmas
  int num_components = 0;             // gauge components (see the top)
  int num_iterations = 0;
  double solve_time_s = 0.0;
  double covariance_time_s = 0.0;

  bool IsSuccess() const { return status == JointAdjustmentStatus::kSuccess; }
  // Mount `mount`'s odom_from_cam (0: odom_from_cam, k > 0:
  // other_mounts[k - 1]) and its [rx, ry, rz, tx, ty] block of
  // mounts_covariance.
  const Rigid3d& MountOdomFromCam(int mount) const {
    return mount == 0 ? odom_from_cam : other_mounts.at(mount - 1);
  }
  Eigen::Matrix<double, 5, 5> MountCovariance(int mount) const {
    const Eigen::Index row = Eigen::Index{5} * mount;
    return mounts_covariance.block<5, 5>(row, row);
  }
};

// Throws std::invalid_argument for invalid options; invalid problems give
// kInvalidInput with the reason.
JointAdjustmentResult AdjustJointly(const JointAdjustmentProblem& problem,
                                    const JointAdjustmentOptions& options);

}  // namespace odomcal
