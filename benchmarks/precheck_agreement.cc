// Does the pre-check before COLMAP (adapters/excitation_precheck.h) reach
// the calibration's verdict? Not a timed benchmark; docs/colmap_checks.md
// has the command and the table.
//
//   precheck_agreement [seeds] [noise_factor]
//
// Per drive and seed: the pre-check on the odometry at the image times, and
// `odomcal calibrate`'s pipeline (clock offset and odometry intrinsics
// estimated with the extrinsic, CalibrateOdomCam with its defaults) on
// camera poses as a reconstruction gives them. Both see the same odometry
// log. The noise is the default noise model's times noise_factor
// (datasets/simulation/model_noise.h): over each interval between images
// the odometry gets the noise the model gives a pair of that motion, and
// the camera poses (the true ones at the image captures, in reconstruction
// units) independent noise per pose whose pair noise is the model's
// (rotation 0.05 deg per axis, translation 1 % of the median image step per
// axis). The drives: the rendered presets' motion (odometry with the
// preset's errors, recorded image times; no pixels) and simulated ones:
// straight, turns in one direction, both, few turns, a low image rate, and
// road drives (10 m/s, 10 Hz images, camera 1.65 m up): 52 m with one 98 deg
// right turn, 110 m with a second turn right or left.
//
// Prints a markdown table: per drive the pre-check's verdict (status and
// undetermined quantities), the calibration's over the seeds, in how many
// seeds the two agree (both go on, or both refuse with the same status and
// the same undetermined quantities), and the largest time of each.
// Disagreements are listed on stderr with both messages.

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/excitation_precheck.h"
#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/datasets/rendering/dataset_presets.h"
#include "odomcal/datasets/rendering/rendered_dataset.h"
#include "odomcal/datasets/simulation/model_noise.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace odomcal {
namespace {

constexpr int64_t kStartNs = 1700000000000000000;
constexpr double kOdometryRateHz = 50.0;

// A drive: the measured odometry, the true one, the image times (recorded,
// camera clock) with their true capture times and the mount.
struct Drive {
  std::string name;
  Trajectory odometry;
  Trajectory true_odometry;
  std::vector<int64_t> image_stamps_ns;
  std::vector<int64_t> capture_ns;
  Rigid3d odom_from_cam;
  double metric_scale = 1.0;  // metres per reconstruction unit
};

// The yaw rate (rad/s) at time t of a turn of angle_deg that starts at
// begin_s, ramps up to peak_radps in 0.5 s, holds it and ramps down in 0.5 s.
double TurnRate(double t, double begin_s, double angle_deg, double peak_radps) {
  const double ramp = 0.5;
  const double end = begin_s + angle_deg * kDegToRad / peak_radps + ramp;
  if (t < begin_s || t >= end) return 0.0;
  if (t < begin_s + ramp) return peak_radps * (t - begin_s) / ramp;
  if (t >= end - ramp) return peak_radps * (end - t) / ramp;
  return peak_radps;
}

// A planar drive integrated from speed (m/s) and yaw rate (rad/s) at time
// t (50 Hz odometry, exact: the noise is added per drive), images every
// 1 / image_rate_hz from 0.5 s on.
Drive Integrate(const std::string& name,
                const std::function<Eigen::Vector2d(double)>& speed_and_yaw,
                double duration_s,
                double image_rate_hz,
                const Rigid3d& odom_from_cam) {
  Drive drive;
  drive.name = name;
  drive.odom_from_cam = odom_from_cam;
  drive.metric_scale = 0.37;
  drive.true_odometry.planar = true;
  const double step_s = 1.0 / kOdometryRateHz;
  const auto step_ns = static_cast<int64_t>(std::llround(1e9 * step_s));
  const int num_steps = static_cast<int>(std::lround(duration_s / step_s));
  double x = 0.0, y = 0.0, yaw = 0.0;
  for (int k = 0; k <= num_steps; ++k) {
    const int64_t stamp = kStartNs + k * step_ns;
    drive.true_odometry.poses.push_back(
        {stamp, Rigid3d(YawRotation(yaw), Eigen::Vector3d(x, y, 0.0))});
    const Eigen::Vector2d v_w = speed_and_yaw(k * step_s);
    const double mid_yaw = yaw + 0.5 * v_w(1) * step_s;
    x += v_w(0) * step_s * std::cos(mid_yaw);
    y += v_w(0) * step_s * std::sin(mid_yaw);
    yaw += v_w(1) * step_s;
  }
  drive.odometry = drive.true_odometry;
  for (double t = 0.5; t <= duration_s - 0.5 + 1e-9; t += 1.0 / image_rate_hz) {
    const int64_t stamp =
        kStartNs + static_cast<int64_t>(std::llround(1e9 * t));
    drive.image_stamps_ns.push_back(stamp);
    drive.capture_ns.push_back(stamp);
  }
  return drive;
}

// The rendered preset's motion: odometry, true odometry, recorded and
// capture times (no scene, no pixels).
Drive Preset(const std::string& name, uint64_t seed, int num_images) {
  RenderedDatasetOptions options = MakeDatasetPreset(name, seed);
  if (num_images > 0) options.num_images = num_images;
  const RenderedDataset dataset = SimulateDatasetMotion(options);
  Drive drive;
  drive.name =
      "`" + name + "` preset" +
      (num_images > 0 ? " (" + std::to_string(num_images) + " images)" : "");
  drive.odometry = dataset.odometry;
  drive.true_odometry = dataset.true_odometry;
  drive.odom_from_cam = options.odom_from_cam;
  for (const RenderedFrame& frame : dataset.frames) {
    drive.image_stamps_ns.push_back(frame.stamp_ns);
    drive.capture_ns.push_back(frame.capture_ns);
  }
  return drive;
}

struct Verdict {
  CalibrationStatus status = CalibrationStatus::kSuccess;
  std::string undetermined;  // comma-separated, of a refusal
  std::string message;
  double seconds = 0.0;
  int left = 0, right = 0;
};

bool Refusal(CalibrationStatus status) {
  return status == CalibrationStatus::kUnobservable ||
         status == CalibrationStatus::kNotEnoughMotion;
}

Verdict VerdictOf(const CalibrationResult& result, double seconds) {
  Verdict verdict;
  verdict.status = result.status;
  verdict.message = result.message;
  verdict.seconds = seconds;
  verdict.left = result.diagnostics.num_left_turns;
  verdict.right = result.diagnostics.num_right_turns;
  if (!result.IsSuccess()) {
    for (const std::string& name : UndeterminedNames(result.observability)) {
      verdict.undetermined += (verdict.undetermined.empty() ? "" : ", ") + name;
    }
  }
  return verdict;
}

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

Verdict Precheck(const Drive& drive) {
  const auto start = std::chrono::steady_clock::now();
  const ExcitationPrecheck precheck =
      PrecheckExcitation(drive.image_stamps_ns,
                         drive.odometry,
                         AssociationOptions(),
                         CalibrationOptions(),
                         SystematicsEstimationOptions());
  return VerdictOf(precheck.verdict, SecondsSince(start));
}

// As `odomcal calibrate` with its defaults.
Verdict Calibrate(const Drive& drive, const Trajectory& camera) {
  const auto start = std::chrono::steady_clock::now();
  MotionPairs pairs;
  CalibrationResult result;
  AssociationResult association;
  EstimateSystematics(
      {camera},
      drive.odometry,
      AssociationOptions(),
      CalibrationOptions(),
      SystematicsEstimationOptions(),
      [&](const AssociationResult& associated) {
        pairs = associated.pairs;
        result = CalibrateOdomCam(pairs, CalibrationOptions());
        return std::make_pair(static_cast<const MotionPairs*>(&pairs), &result);
      },
      &association);
  return VerdictOf(result, SecondsSince(start));
}

// "go on", or the status of a refusal and the undetermined quantities.
std::string Label(const Verdict& verdict) {
  if (!Refusal(verdict.status)) return "go on";
  return ToString(verdict.status) +
         (verdict.undetermined.empty() ? "" : ": " + verdict.undetermined);
}

bool Agree(const Verdict& precheck, const Verdict& calibration) {
  if (!Refusal(precheck.status)) return !Refusal(calibration.status);
  return precheck.status == calibration.status &&
         precheck.undetermined == calibration.undetermined;
}

std::vector<Drive> Drives(uint64_t seed) {
  // Forward camera 25 cm ahead, 5 cm left, 40 cm up (the simulator's).
  const Rigid3d robot(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5),
                      Eigen::Vector3d(0.25, 0.05, 0.40));
  // A car's: 1.5 m ahead of the rear axle, 1.65 m up.
  const Rigid3d car(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5),
                    Eigen::Vector3d(1.5, 0.0, 1.65));
  const double phase = 0.7 * static_cast<double>(seed);
  std::vector<Drive> drives;
  drives.push_back(Integrate(
      "straight, 60 s, 2 Hz",
      [](double) { return Eigen::Vector2d(0.4, 0.0); },
      60.0,
      2.0,
      robot));
  for (const double sign : {-1.0, 1.0}) {
    drives.push_back(Integrate(
        sign < 0 ? "right turns of varying size, 60 s, 2 Hz"
                 : "left turns of varying size, 60 s, 2 Hz",
        [sign, phase](double t) {
          return Eigen::Vector2d(
              0.4, sign * (0.25 + 0.2 * std::sin(0.3 * t + phase)));
        },
        60.0,
        2.0,
        robot));
  }
  drives.push_back(Integrate(
      "turns both ways, 60 s, 2 Hz",
      [phase](double t) {
        return Eigen::Vector2d(0.4, 0.5 * std::sin(0.4 * t + phase));
      },
      60.0,
      2.0,
      robot));
  // Two 30 deg turns, one each way, in 60 s of straight driving.
  drives.push_back(Integrate(
      "one turn each way, 60 s, 2 Hz",
      [](double t) {
        const double rate = 30.0 * kDegToRad / 3.0;
        return Eigen::Vector2d(0.4,
                               t >= 15.0 && t < 18.0 ? rate
                               : t >= 40 && t < 43   ? -rate
                                                     : 0);
      },
      60.0,
      2.0,
      robot));
  drives.push_back(Integrate(
      "turns both ways, 60 s, 0.25 Hz",
      [phase](double t) {
        return Eigen::Vector2d(0.4, 0.5 * std::sin(0.4 * t + phase));
      },
      60.0,
      0.25,
      robot));
  // A robot's single 90 deg right turn (0.3 rad/s) in 30 s.
  drives.push_back(Integrate(
      "one 90 deg right turn, 30 s, 2 Hz",
      [](double t) {
        return Eigen::Vector2d(
            0.4, t >= 10.0 && t < 10.0 + 0.5 * kPi / 0.3 ? -0.3 : 0.0);
      },
      30.0,
      2.0,
      robot));
  // 10 m/s: 9.25 m straight, a 98 deg right turn at 0.6 rad/s with 0.5 s
  // ramps (33.5 m), 9.25 m straight: 52 m, 10 Hz images.
  drives.push_back(Integrate(
      "road: 52 m, one 98 deg right turn, 10 Hz",
      [](double t) {
        return Eigen::Vector2d(10.0, -TurnRate(t, 1.425, 98.0, 0.6));
      },
      6.2,
      10.0,
      car));
  // Two right turns of different rates: 98 deg at 0.6 rad/s, then 60 deg
  // at 0.3 rad/s, 20 m apart: 110 m.
  drives.push_back(Integrate(
      "road: 110 m, right turns of 98 and 60 deg, 10 Hz",
      [](double t) {
        return Eigen::Vector2d(
            10.0, -TurnRate(t, 1.425, 98.0, 0.6) - TurnRate(t, 6.8, 60.0, 0.3));
      },
      12.0,
      10.0,
      car));
  // A 98 deg right turn, then a 60 deg left one: 110 m.
  drives.push_back(Integrate(
      "road: 110 m, a 98 deg right and a 60 deg left turn, 10 Hz",
      [](double t) {
        return Eigen::Vector2d(
            10.0, -TurnRate(t, 1.425, 98.0, 0.6) + TurnRate(t, 6.8, 60.0, 0.3));
      },
      12.0,
      10.0,
      car));
  for (const char* name : {"small", "default", "tilted", "hard", "straight"}) {
    drives.push_back(Preset(name, seed, 0));
  }
  drives.push_back(Preset("long", seed, 300));
  return drives;
}

int Run(int seeds, double noise_factor) {
  struct Row {
    Verdict precheck;  // of seed 1 (the label), slowest time
    std::map<std::string, int> calibration_labels;
    int agree = 0;
    int pairs = 0;
    double precheck_max_s = 0.0, calibration_max_s = 0.0;
  };
  std::vector<std::string> order;
  std::map<std::string, Row> rows;
  std::map<std::string, std::map<std::string, int>> precheck_labels;
  for (int seed = 1; seed <= seeds; ++seed) {
    for (const Drive& drive : Drives(static_cast<uint64_t>(seed))) {
      if (!rows.count(drive.name)) order.push_back(drive.name);
      Row& row = rows[drive.name];
      // The log as recorded: the model's noise over each image interval (on
      // top of a preset's own errors); the odometry clock's image times.
      Drive recorded = drive;
      std::vector<int64_t> odometry_clock = drive.capture_ns;
      std::sort(odometry_clock.begin(), odometry_clock.end());
      recorded.odometry = WithModelOdometryNoise(
          drive.odometry, odometry_clock, NoiseModel(), noise_factor, seed);
      const Verdict precheck = Precheck(recorded);
      const Verdict calibration =
          Calibrate(recorded,
                    ModelNoisyReconstruction(drive.true_odometry,
                                             drive.capture_ns,
                                             drive.image_stamps_ns,
                                             drive.odom_from_cam,
                                             drive.metric_scale,
                                             NoiseModel(),
                                             noise_factor,
                                             1000 + seed));
      if (seed == 1) row.precheck = precheck;
      ++precheck_labels[drive.name][Label(precheck)];
      ++row.calibration_labels[Label(calibration)];
      row.agree += Agree(precheck, calibration);
      row.pairs = static_cast<int>(drive.image_stamps_ns.size());
      row.precheck_max_s = std::max(row.precheck_max_s, precheck.seconds);
      row.calibration_max_s =
          std::max(row.calibration_max_s, calibration.seconds);
      if (!Agree(precheck, calibration)) {
        std::fprintf(stderr,
                     "seed %d, %s: pre-check %s (%s); calibration %s (%s)\n",
                     seed,
                     drive.name.c_str(),
                     Label(precheck).c_str(),
                     precheck.message.c_str(),
                     Label(calibration).c_str(),
                     calibration.message.c_str());
      }
    }
  }
  const auto join = [seeds](const std::map<std::string, int>& labels) {
    std::string text;
    for (const auto& [label, count] : labels) {
      text += (text.empty() ? "" : "; ") + label +
              (count == seeds ? "" : " (" + std::to_string(count) + ")");
    }
    return text;
  };
  std::printf(
      "odometry and camera noise %.2fx the default noise model's, seeds "
      "1-%d\n\n"
      "| drive | images | left / right turns > 2 deg (seed 1) | pre-check | "
      "calibration | agree | pre-check time | calibration time |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- |\n",
      noise_factor,
      seeds);
  int disagreements = 0;
  for (const std::string& name : order) {
    const Row& row = rows[name];
    disagreements += seeds - row.agree;
    std::printf("| %s | %d | %d / %d | %s | %s | %d/%d | %.0f ms | %.0f ms |\n",
                name.c_str(),
                row.pairs,
                row.precheck.left,
                row.precheck.right,
                join(precheck_labels[name]).c_str(),
                join(row.calibration_labels).c_str(),
                row.agree,
                seeds,
                1e3 * row.precheck_max_s,
                1e3 * row.calibration_max_s);
  }
  return disagreements == 0 ? 0 : 1;
}

}  // namespace
}  // namespace odomcal

int main(int argc, char** argv) {
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 5;
  const double noise_factor = argc > 2 ? std::atof(argv[2]) : 1.0;
  if (seeds < 1 || !(noise_factor >= 0.0)) {
    std::fprintf(stderr,
                 "usage: precheck_agreement [seeds >= 1] "
                 "[noise_factor >= 0]\n");
    return 2;
  }
  return odomcal::Run(seeds, noise_factor);
}
