// Wheel odometry of a differential-drive robot following a UnicyclePath, as its
// wheel encoders would report it.
//
// Over each sample period [t_k, t_k+1] the true wheel travels are
//   l = s - w_b / 2 * h,  r = s + w_b / 2 * h
// (s, h: distance and heading change of the path, w_b: wheel base). The
// measured travels are l' = l (1 + e_l)(1 + n_l), r' = r (1 + e_r)(1 + n_r)
// with fixed scale errors e (wrong wheel radii) and slip n ~ N(0, slip_stddev)
// drawn per wheel and period; the heading change also gains a constant
// yaw_rate_bias_radps * dt (gyro-like drift). The pose is integrated as an
// arc of constant curvature: exact when the noise is zero and the twist is
// constant over the period.
//
// Output is origin_from_odom, planar, with the first sample at identity (the
// odometry's origin is where the robot starts). Deterministic for the seed.
#pragma once

#include "odomcal/adapters/trajectory.h"
#include "odomcal/datasets/simulation/unicycle_path.h"

#include <cstdint>
#include <vector>

namespace odomcal {

struct WheelOdometryNoise {
  double wheel_base_m = 0.4;
  double wheel_scale_error_left = 0.0;  // fraction, e.g. 0.003 = +0.3 %
  double wheel_scale_error_right = 0.0;
  double wheel_slip_stddev = 0.0;  // relative, per wheel and period
  double yaw_rate_bias_radps = 0.0;
  uint64_t seed = 0;
  void Check() const;  // throws std::invalid_argument naming the field
};

// Sample times are ns from the path start, strictly increasing, the first
// one at 0 or later; stamps are sample time + stamp_offset_ns. Throws
// std::invalid_argument for bad times or noise parameters.
Trajectory SimulateWheelOdometry(const UnicyclePath& path,
                                 const std::vector<int64_t>& sample_times_ns,
                                 int64_t stamp_offset_ns,
                                 const WheelOdometryNoise& noise);

// The same wheel model driven by given true steps: true_steps[k - 1] is the
// distance travelled (m) and the heading change about the body's up axis
// (rad) over [t_{k-1}, t_k], e.g. of a robot on sloped ground
// (road_scene.h), which planar wheel odometry integrates as if flat. Throws
// std::invalid_argument unless there is one step per sample period.
Trajectory SimulateWheelOdometryFromSteps(
    const std::vector<Eigen::Vector2d>& true_steps,
    const std::vector<int64_t>& sample_times_ns,
    int64_t stamp_offset_ns,
    const WheelOdometryNoise& noise);

// The exact odometry at the same times: origin_from_odom(t) =
// path_from_odom(0)^-1 * path_from_odom(t), where 0 is the first sample time.
Trajectory TrueWheelOdometry(const UnicyclePath& path,
                             const std::vector<int64_t>& sample_times_ns,
                             int64_t stamp_offset_ns);

}  // namespace odomcal
