// A drive past random points for the joint adjustment
// (solver/joint_adjustment.h): a forward camera sees the points, wheel
// odometry links consecutive images, and the starting values carry a
// COLMAP-like scale drift (the model's size grows along the drive). Used by
// the solver's tests and benchmarks/joint_adjustment_benchmark.cc.
#pragma once

#include "odomcal/solver/joint_adjustment.h"
#include "odomcal/solver/planar_pose.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <vector>

namespace odomcal {

struct JointSceneOptions {
  int num_images = 80;        // 0.25 m apart, turning both ways
  int points_per_image = 12;  // 2-8 m to the sides and ahead of each pose
  double pixel_sigma = 0.5;   // independent per observation
  // Common to every feature of one image (as a timing or rolling shutter
  // error moves them together), per axis.
  double image_shift_px = 0.0;
  double outlier_fraction = 0.0;  // observations moved by 40 px sigma
  // The starting values' size grows by this much from the drive's start to
  // its end; the extrinsic starts 0.5 deg and 2 cm off.
  double drift = 0.05;
  // A rig: a second camera (mount 1) at the robot's rear, looking back and
  // 5 deg down, its images halfway in time between the first camera's (not
  // synchronised); the odometry links the images of both in time order. It
  // sees the same points as the first camera when rear_shares_points (one
  // model of both), else copies of its own (a model of its own).
  bool rear_camera = false;
  bool rear_shares_points = true;
  // Ground that pitches and banks (slopes up to this many degrees along x
  // and y, 20 m waves whose phases vary with the seed), on which the robot
  // rides: its poses are SE(3). 0: a level floor.
  double ground_slope_deg = 0.0;
  // The odometry measures the whole motion (RobotMotionModel::kSE3, its
  // tilt to 0.05 deg + 1 % of the turn per link); else its planar part.
  bool se3_odometry = false;
  unsigned seed = 1;
};

struct JointScene {
  JointAdjustmentProblem problem;
  Rigid3d odom_from_cam;                // the truth
  Rigid3d rear_odom_from_cam;           // the truth, with rear_camera
  std::vector<Rigid3d> poses;           // the truth, per image
  std::vector<Eigen::Vector3d> points;  // the truth
};

// A 640 x 480 SIMPLE_RADIAL camera (COLMAP's pixel convention) sees points
// 0.5-12 m ahead; the odometry between consecutive images has 2 mm + 1 %
// per axis and 0.2 deg + 1 % of the turn, as its link covariance says.
// With rear_camera, the problem's images are the first camera's, then the
// rear camera's (one fewer), and `poses` holds the rear images' poses after
// the first camera's.
JointScene SimulateJointScene(const JointSceneOptions& options);

}  // namespace odomcal
