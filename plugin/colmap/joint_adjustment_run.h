// The joint adjustment of a project calibration (`--joint_adjustment`):
// its settings and what it did. The stage itself is
// joint_adjustment_stage.h.
#pragma once

#include "odomcal/solver/joint_adjustment.h"
#include "odomcal/solver/joint_adjustment_jackknife.h"
#include "odomcal/solver/joint_extrinsic.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace odomcal {

// kCheck: the adjustment runs after the two-step calibration and checks
// it; the two-step estimate is reported unless the adjustment contradicts it
// (a difference in roll, pitch, yaw, x or y beyond kJointContradictionSigmas
// standard deviations of the difference, ExtrinsicDisagreement: the
// two-step's model of the reconstruction failed), then the adjustment's is,
// as with kOn.
enum class JointAdjustmentUse { kOn, kOff, kCheck };
std::string ToString(JointAdjustmentUse use);  // "on", "off", "check"
// Throws std::invalid_argument naming the value.
JointAdjustmentUse JointAdjustmentUseFromString(const std::string& name);

// The camera intrinsics in the adjustment (`--joint_intrinsics`): held;
// refined (focal scale and distortion, camera_intrinsics_manifold.h); or
// kAuto: refined where COLMAP's bundle adjustment changed them from the
// database's camera (their error is then unknown, and held it biases the
// extrinsic at a sigma that does not contain it), held where the model's are
// the database's (given and kept fixed) or no database is given.
enum class JointIntrinsics { kHeld, kRefined, kAuto };
std::string ToString(JointIntrinsics intrinsics);  // "held", "refined", "auto"
// Throws std::invalid_argument naming the value.
JointIntrinsics JointIntrinsicsFromString(const std::string& name);

struct JointAdjustmentSettings {
  JointAdjustmentUse use = JointAdjustmentUse::kCheck;
  JointIntrinsics intrinsics = JointIntrinsics::kAuto;
  // Its refine_intrinsics is set from `intrinsics` when the adjustment runs.
  JointAdjustmentOptions options;
  JointJackknifeOptions jackknife;
  void Check() const {
    options.Check();
    jackknife.Check();
  }
};

// A stretch of the drive: the metric scale the two-step model gave it and
// the one the adjustment's model has there (its camera path in metres over
// the same path in COLMAP's units). Their ratio is the COLMAP scale drift
// the adjustment took out.
struct JointStretchScale {
  std::string metric_model;    // the two-step model's part it lies in
  int64_t first_stamp_ns = 0;  // odometry clock
  int64_t last_stamp_ns = 0;
  int num_images = 0;
  double path_length_m = 0.0;   // in the adjusted model
  double two_step_scale = 0.0;  // metres per reconstruction unit
  double joint_scale = 0.0;
};

// kCheck: beyond this many standard deviations of their difference the
// adjustment contradicts the two-step estimate: the adjustment lies outside
// the interval the two-step's 3 sigma promised. Honest sigmas leave such a
// difference in about 1 % of runs (five quantities); the adjustment's
// estimate, the more accurate, is then reported with its own covariance.
constexpr double kJointContradictionSigmas = 3.0;

struct JointAdjustmentRun {
  bool requested = false;  // --joint_adjustment on or check
  JointAdjustmentUse use = JointAdjustmentUse::kOff;
  JointIntrinsics intrinsics = JointIntrinsics::kAuto;  // as asked
  bool ran = false;  // the adjustment was attempted
  // The adjustment's extrinsic and model are the result's (kOn, or kCheck
  // with a contradiction); false: the two-step's stay.
  bool adopted = false;
  // The largest |joint - two-step| over the standard deviation of the
  // difference in roll, pitch, yaw, x, y (when it succeeded).
  double max_disagreement_sigmas = 0.0;
  // kCheck beyond kJointContradictionSigmas: the same with the adjustment's
  // covariance after its jackknife (negative when not measured). Within
  // kJointContradictionSigmas the adjustment's own uncertainty covers the
  // difference, and the two-step estimate stands.
  double max_disagreement_sigmas_jackknifed = -1.0;
  std::string skipped;  // why it was not (empty when it ran or was off)
  JointAdjustmentResult result;
  // The jackknife over stretches of the drive that widened result's
  // covariance where its spread was larger.
  JointJackknife jackknife;
  // The two-step estimate it started from ([rx, ry, rz, tx, ty] covariance).
  Rigid3d two_step_odom_from_cam;
  Eigen::Matrix<double, 5, 5> two_step_covariance =
      Eigen::Matrix<double, 5, 5>::Zero();
  std::vector<ExtrinsicDisagreement> disagreements;
  int num_images = 0;
  int num_points = 0;
  int num_links = 0;
  int num_joining_links = 0;  // links added between the two-step's pieces
  // The odometry's systematics (clock offset, intrinsics) were refined in
  // the adjustment (planar odometry whose systematics the two-step
  // estimated).
  bool refined_systematics = false;
  // The cameras as the adjustment started (JointCamera::held set by
  // --joint_intrinsics) and its option: a camera's intrinsics were refined
  // where refine_intrinsics and not held.
  std::vector<JointCamera> cameras_before;
  bool refine_intrinsics = false;
  std::vector<JointStretchScale> stretches;
  // The largest |joint_scale / two_step_scale - 1| over the stretches.
  double max_scale_change = 0.0;
};

}  // namespace odomcal
