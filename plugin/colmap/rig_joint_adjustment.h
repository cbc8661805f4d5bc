// One joint adjustment of a rig's cameras (`--joint_adjustment on` with two
// or more calibrated cameras): every camera's images, points and extrinsic
// (a mount of solver/joint_adjustment.h each) with the one odometry, the
// robot's poses at every camera's image times on one trajectory.
//
// Each camera is first calibrated on its own (colmap_rig_calibration.h); its
// metric models (metres, the odometry's frame) and extrinsic start the
// adjustment. The cameras are not synchronised in general: the odometry
// links every image to the next in time, whichever camera took it, so that
// each stretch of the odometry is one link (links between a camera's own
// images would count the odometry between them twice). Cameras in models of
// their own meet through that trajectory; cameras whose images share points
// of one reconstruction (a COLMAP project of several cameras: one point3D
// id in one model folder) meet through them too: each such point is one
// point of the adjustment, seen by every camera's images that observe it.
//
// Each camera's clock offset stays its own calibration's estimate; its
// uncertainty, which moves that camera's robot poses along the drive, is
// propagated into the covariance (a re-solve per camera with its offset
// moved). After the jackknife, which widens per row.
//
// What it adds to the cameras calibrated apart: the cross covariance of the
// extrinsics (the trajectory's errors are common to all), so that each
// camera-to-camera transform carries the uncertainty of the rig, not of two
// independent estimates; and each camera's extrinsic adjusted with the
// images of all.
//
// `--joint_adjustment check` (the default) runs it as a check of every
// camera's own estimate, as one camera's check (joint_adjustment_stage.h):
// without its jackknife, each mount compared with its camera's estimate per
// roll, pitch, yaw, x and y against the sigma of their difference. Within
// kJointContradictionSigmas everywhere, each camera's own estimate stands
// (and the camera pairs are those of independent estimates); beyond, the
// jackknife and the clock offsets' re-solves run and the difference is
// measured again: where the widened adjustment covers it and is the less
// precise in every quantity that contradicted, the cameras' own estimates
// stand; else the adjustment is reported for every camera (adopted).
#pragma once

#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/plugin/colmap/joint_adjustment_run.h"
#include "odomcal/solver/joint_adjustment.h"
#include "odomcal/solver/joint_adjustment_jackknife.h"
#include "odomcal/solver/joint_extrinsic.h"

#include <string>
#include <vector>

namespace odomcal {

// One quantity of one camera on which the rig's adjustment and the
// camera's own estimate differ (check).
struct RigDisagreement {
  int camera = 0;  // index among the runs
  ExtrinsicDisagreement quantity;
};

struct RigJointAdjustment {
  // kOn: its estimate is reported; kCheck: only where adopted (above).
  JointAdjustmentUse use = JointAdjustmentUse::kOff;
  bool ran = false;     // the adjustment was attempted
  std::string skipped;  // why not (fewer than two calibrated cameras, ...)
  // Per mount (mount 0 first), the index of its camera among the runs.
  std::vector<int> cameras;
  // Success, or why not (result.status, result.message).
  JointAdjustmentResult result;
  JointJackknife jackknife;
  int num_images = 0;
  int num_points = 0;
  // Points observed by images of two or more cameras.
  int num_points_across_cameras = 0;
  int num_links = 0;
  // Links between images of two different cameras.
  int num_links_across_cameras = 0;
  // Cameras whose clock offset's uncertainty (held at each camera's own
  // estimate in the adjustment) was propagated into the covariance.
  int num_clock_offsets_propagated = 0;
  // The adjustment's cameras as it started (JointCamera::held by
  // --joint_intrinsics; result.cameras: after), the mount each belongs to,
  // and its option (refined where set and not held).
  std::vector<JointCamera> cameras_before;
  std::vector<int> mount_of_camera;
  bool refine_intrinsics = false;
  // Its estimate (every mount's rotation, x and y and the cross terms) is
  // the one reported: kOn, or a check the cameras' own estimates failed.
  bool adopted = false;
  // Check: the largest difference between a mount and its camera's own
  // estimate over the difference's sigma, with the adjustment's covariance
  // before and after its jackknife (-1: not measured), and the quantities
  // beyond kJointContradictionSigmas before it.
  double max_disagreement_sigmas = -1.0;
  double max_disagreement_sigmas_jackknifed = -1.0;
  std::vector<RigDisagreement> disagreements;

  bool Succeeded() const { return ran && result.IsSuccess(); }
  bool Adopted() const { return Succeeded() && adopted; }
  // The check's last measured disagreement: after the jackknife where it
  // ran, else before (-1: not measured).
  double FinalDisagreementSigmas() const {
    return max_disagreement_sigmas_jackknifed >= 0.0
               ? max_disagreement_sigmas_jackknifed
               : max_disagreement_sigmas;
  }
  // Mount of camera `camera` (index among the runs), or -1.
  int MountOf(int camera) const;
};

// `runs`: per camera of the rig (`names`: theirs, for the messages), its
// calibration, or null where it has
// none; a camera takes part when its calibration succeeded with rotation, x
// and y estimated and it has metric models, unless SE(3) odometry's tilts
// determined its z (the adjustment holds z). `inputs`: the
// project's (odometry noise model, joint adjustment settings and limits;
// inputs.joint_adjustment.use kOn or kCheck, else it does not run).
// `progress`, when set, hears the adjustment's iterations.
RigJointAdjustment AdjustRigJointly(
    const std::vector<const ColmapCalibrationRun*>& runs,
    const std::vector<std::string>& names,
    const ColmapCalibrationInputs& inputs,
    const CalibrationProgress& progress = {});

}  // namespace odomcal
