// Motion pairs of a car driving a winding road that climbs, with SE(3)
// odometry (an INS: roll and pitch against gravity) and a camera high above
// the odometry frame: the case where a held translation z biases x and y.
//
// The road's grade varies smoothly between 0 and max_grade_deg along the
// drive while the car turns: the odometry's rotation axes tilt by the grade,
// so a turn moves the camera by its height times the grade across the
// direction of travel, and x and z of the extrinsic share that signature.
// How well the motion separates them depends on how much the grade varies
// between turns: with a grade of a few degrees, z is informed to tens of
// centimetres, not determined.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <cstdint>

namespace odomcal {

struct ClimbingRoadOptions {
  int num_keyframes = 150;
  double step_m = 0.5;           // along the car's x axis
  double max_turn_deg = 30.0;    // yaw increments uniform in +-max_turn_deg
  double max_grade_deg = 2.5;    // pitch (nose up) within [0, max_grade_deg]
  double grade_period_m = 40.0;  // the grade's period along the road
  double roll_sigma_deg = 0.3;   // road camber and roughness, per keyframe
  // Banking: the roll (right side down) varies smoothly within
  // [0, max_bank_deg] with this period, as a road's camber and its banked
  // curves do; 0: none.
  double max_bank_deg = 0.0;
  double bank_period_m = 60.0;
  // Planar odometry, as wheel odometry gives: each pose's x, y and yaw, its
  // roll, pitch and z dropped; noise drawn for yaw, x and y only.
  bool planar_odometry = false;
  double metric_scale = 0.7;  // metres per reconstruction unit
  // A forward-looking camera this high above the odometry frame.
  Rigid3d odom_from_cam;
  ClimbingRoadOptions();
};

// Consecutive keyframe pairs with noise drawn from `noise` as the solver
// models it (NoiseModel at the true steps); no noise when `noise` is null.
// Deterministic for a seed.
MotionPairs ClimbingRoadPairs(const ClimbingRoadOptions& options,
                              const NoiseModel* noise,
                              uint64_t seed);

}  // namespace odomcal
