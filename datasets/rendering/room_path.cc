// Planning is a random walk over manoeuvres with rejection (see the header):
// propose, simulate exactly, check every 50 ms, accept or propose again. All
// randomness comes from one std::mt19937_64 seeded with options.seed, and
// manoeuvre durations are rounded to whole nanoseconds before the poses are
// integrated, so evaluation and planning agree exactly.

#include "odomcal/datasets/rendering/room_path.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/solver/angles.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <utility>

namespace odomcal {
namespace {

constexpr int64_t kCheckStepNs = 50000000;  // 50 ms between clearance checks
constexpr int kMaxAttemptsPerManoeuvre = 40;
constexpr int kMaxAttemptsPerLeg = 20;

class Planner {
 public:
  Planner(const RoomLayout& layout, const RoomPathOptions& options)
      : layout_(layout), options_(options), rng_(options.seed) {}

  UnicyclePath Plan() {
    pose_ = options_.start;
    if (!Valid(pose_, &options_.legs.front(), /*relaxed=*/false)) {
      throw std::invalid_argument(
          "RoomPathOptions.start violates the clearances or lies outside the "
          "first leg's region");
    }
    Append(0.0, 0.0, SecondsToNs(options_.initial_stop_s));
    for (const PathLeg& leg : options_.legs) {
      const size_t saved_size = out_.size();
      const PlanarPose saved_pose = pose_;
      const int64_t saved_t = t_ns_;
      bool done = false;
      for (int attempt = 0; attempt < kMaxAttemptsPerLeg && !done; ++attempt) {
        out_.resize(saved_size);
        pose_ = saved_pose;
        t_ns_ = saved_t;
        Wander(leg, t_ns_ + SecondsToNs(leg.wander_duration_s));
        done = true;
        for (const Eigen::Vector2d& waypoint : leg.waypoints) {
          if (!DriveTo(waypoint)) {
            done = false;
            break;
          }
        }
      }
      if (!done) {
        throw std::runtime_error(
            "PlanRoomPath: cannot reach a leg's waypoints without violating "
            "the clearances");
      }
    }
    Wander(options_.legs.back(), SecondsToNs(options_.duration_s));
    return UnicyclePath(std::move(out_));
  }

 private:
  // Pose checks of the header; `relaxed` (waypoint drives through narrow
  // passages) checks only the clearances, the robot's at 80 %.
  bool Valid(const PlanarPose& p, const PathLeg* region, bool relaxed) const {
    const Eigen::Vector2d centre(p.x, p.y);
    if (region != nullptr &&
        ((centre.array() < region->region_min.array()).any() ||
         (centre.array() > region->region_max.array()).any())) {
      return false;
    }
    const double robot_clearance =
        relaxed ? 0.8 * options_.robot_clearance_m : options_.robot_clearance_m;
    if (layout_.DistanceToObstacles(centre) < robot_clearance) return false;
    const Eigen::Rotation2Dd yaw(p.yaw_rad);
    const Eigen::Vector2d camera =
        centre + yaw * options_.camera_position_in_odom.head<2>();
    if (layout_.DistanceToObstacles(camera) < options_.camera_clearance_m) {
      return false;
    }
    if (relaxed) return true;
    const Eigen::Vector2d axis = yaw * options_.camera_axis_in_odom.head<2>();
    // Cameras looking nearly straight up or down have no horizontal view.
    if (axis.norm() > 0.3 && layout_.RayDistance(camera, axis.normalized()) <
                                 options_.min_view_depth_m) {
      return false;
    }
    return true;
  }

  bool ManoeuvreValid(double v,
                      double w,
                      int64_t duration_ns,
                      const PathLeg* region,
                      bool relaxed) const {
    for (int64_t t = kCheckStepNs;; t += kCheckStepNs) {
      const int64_t step = std::min(t, duration_ns);
      if (!Valid(UnicycleStep(pose_, v, w, 1e-9 * step), region, relaxed)) {
        return false;
      }
      if (step == duration_ns) return true;
    }
  }

  void Append(double v, double w, int64_t duration_ns) {
    if (duration_ns <= 0) return;
    out_.push_back({t_ns_, duration_ns, v, w, pose_});
    pose_ = UnicycleStep(pose_, v, w, 1e-9 * duration_ns);
    t_ns_ += duration_ns;
  }

  double Uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng_);
  }

  void Wander(const PathLeg& leg, int64_t end_ns) {
    while (t_ns_ < end_ns) {
      bool accepted = false;
      for (int attempt = 0; attempt < kMaxAttemptsPerManoeuvre && !accepted;
           ++attempt) {
        // Kinds cycle so that every stretch mixes them; after some rejections
        // any kind is tried, with shorter manoeuvres.
        // (With more_turns_when_stuck a stop is no way out: the handling of
        // being stuck below is.)
        int kind = attempt < 10
                       ? kind_ % 5
                       : std::uniform_int_distribution<int>(
                             0, options_.more_turns_when_stuck ? 3 : 4)(rng_);
        if (options_.straight_only) kind = (kind == 4) ? 4 : 0;
        double duration =
            Uniform(options_.min_manoeuvre_s, options_.max_manoeuvre_s);
        if (attempt >= 10) duration *= 0.5;
        const double speed =
            Uniform(options_.min_speed_mps, options_.max_speed_mps);
        const double rate = turn_sign_ * Uniform(options_.min_yaw_rate_radps,
                                                 options_.max_yaw_rate_radps);
        double v = 0.0, w = 0.0;
        switch (kind) {
          case 0:
            v = speed;
            break;
          case 1:
          case 3:
            v = speed;
            w = rate;
            break;
          case 2:
            w = rate;
            break;
          default:
            duration = Uniform(0.5, 1.0);
            break;  // stop
        }
        const int64_t duration_ns = SecondsToNs(duration);
        if (ManoeuvreValid(v, w, duration_ns, &leg, false)) {
          Append(v, w, duration_ns);
          accepted = true;
          ++kind_;
          if (w != 0.0) turn_sign_ = -turn_sign_;  // both directions
        } else if (attempt % 2 == 1) {
          turn_sign_ = -turn_sign_;
        }
      }
      if (accepted) continue;
      // Stuck (facing a wall, region border): turn towards the centre.
      const Eigen::Vector2d to_centre =
          0.5 * (leg.region_min + leg.region_max) -
          Eigen::Vector2d(pose_.x, pose_.y);
      double angle =
          WrapAngle(std::atan2(to_centre.y(), to_centre.x()) - pose_.yaw_rad);
      if (std::abs(angle) < 0.3) angle = turn_sign_ * 0.5 * kPi;
      // With more_turns_when_stuck, else a quarter or half turn: measured
      // on the `long` preset (seed 1), the robot otherwise stood still for
      // the last 26 s of a 36 s drive, no turn to the centre being valid.
      bool turned = false;
      std::vector<double> turns = {angle};
      if (options_.more_turns_when_stuck) {
        turns.insert(
            turns.end(),
            {0.5 * kPi, -0.5 * kPi, kPi, -kPi, 0.25 * kPi, -0.25 * kPi});
      }
      for (const double turn : turns) {
        const double w = std::copysign(options_.max_yaw_rate_radps, turn);
        const int64_t duration_ns =
            SecondsToNs(std::abs(turn) / options_.max_yaw_rate_radps);
        if (!options_.straight_only &&
            ManoeuvreValid(0.0, w, duration_ns, &leg, false)) {
          Append(0.0, w, duration_ns);
          turned = true;
          break;
        }
      }
      // Backing away (a turn in place can sweep the camera too close to a
      // wall or box): measured on `long`, seeds 1 and 2, the robot still
      // stood for 50 s beside a box without it.
      for (int k = 0; k < 6 && !turned && options_.more_turns_when_stuck; ++k) {
        const double w = (k % 3 - 1) * 0.3;  // -0.3, 0, 0.3 rad/s
        const int64_t duration_ns = SecondsToNs(k < 3 ? 1.0 : 2.0);
        if (ManoeuvreValid(
                -options_.min_speed_mps, w, duration_ns, &leg, false)) {
          Append(-options_.min_speed_mps, w, duration_ns);
          turned = true;
        }
      }
      if (!turned) Append(0.0, 0.0, SecondsToNs(1.0));  // stop; always valid
    }
  }

  bool DriveTo(const Eigen::Vector2d& waypoint) {
    const Eigen::Vector2d delta = waypoint - Eigen::Vector2d(pose_.x, pose_.y);
    const double angle =
        WrapAngle(std::atan2(delta.y(), delta.x()) - pose_.yaw_rad);
    // Transit at full speed: these stretches only connect places.
    const double rate = options_.max_yaw_rate_radps;
    const int64_t turn_ns = SecondsToNs(std::abs(angle) / rate);
    const double w = std::copysign(rate, angle);
    if (!ManoeuvreValid(0.0, w, turn_ns, nullptr, true)) return false;
    Append(0.0, w, turn_ns);
    const double speed = options_.max_speed_mps;
    const int64_t drive_ns = SecondsToNs(delta.norm() / speed);
    if (!ManoeuvreValid(speed, 0.0, drive_ns, nullptr, true)) return false;
    Append(speed, 0.0, drive_ns);
    return true;
  }

  const RoomLayout& layout_;
  const RoomPathOptions& options_;
  std::mt19937_64 rng_;
  std::vector<PathManoeuvre> out_;
  PlanarPose pose_;
  int64_t t_ns_ = 0;
  int kind_ = 0;
  double turn_sign_ = 1.0;
};

}  // namespace

void RoomPathOptions::Check() const {
  if (legs.empty())
    throw std::invalid_argument("RoomPathOptions.legs is empty");
  for (const PathLeg& leg : legs) {
    if (!((leg.region_max - leg.region_min).minCoeff() > 0.0)) {
      throw std::invalid_argument("RoomPathOptions.legs: empty region");
    }
    if (!(leg.wander_duration_s >= 0.0)) {
      throw std::invalid_argument(
          "RoomPathOptions.legs: negative wander_duration_s");
    }
  }
  if (!(duration_s > 0.0) || !(initial_stop_s >= 0.0)) {
    throw std::invalid_argument("RoomPathOptions.duration_s must be > 0");
  }
  if (!(min_speed_mps > 0.0) || !(max_speed_mps >= min_speed_mps)) {
    throw std::invalid_argument(
        "RoomPathOptions: need 0 < min_speed_mps <= max_speed_mps");
  }
  if (!(min_yaw_rate_radps > 0.0) ||
      !(max_yaw_rate_radps >= min_yaw_rate_radps)) {
    throw std::invalid_argument(
        "RoomPathOptions: need 0 < min_yaw_rate_radps <= max_yaw_rate_radps");
  }
  if (!(min_manoeuvre_s > 0.0) || !(max_manoeuvre_s >= min_manoeuvre_s)) {
    throw std::invalid_argument(
        "RoomPathOptions: need 0 < min_manoeuvre_s <= max_manoeuvre_s");
  }
  // Turning in place must always be allowed where standing is.
  if (!(camera_clearance_m >= 0.0) ||
      camera_clearance_m >
          robot_clearance_m - camera_position_in_odom.head<2>().norm() + 1e-9) {
    throw std::invalid_argument(
        "RoomPathOptions.camera_clearance_m must be in [0, robot_clearance_m - "
        "|camera offset|]");
  }
}

UnicyclePath PlanRoomPath(const RoomLayout& layout,
                          const RoomPathOptions& options) {
  layout.Check();
  options.Check();
  return Planner(layout, options).Plan();
}

}  // namespace odomcal
