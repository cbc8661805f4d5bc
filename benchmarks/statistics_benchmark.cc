// Consistency of the default calibration over many simulated runs: RMSE
// against the noise-weighted batch reference (GT-B: the refinement started at
// the truth with the true per-pair covariances), coverage of the stated
// 3 sigma and the mean NEES. Not a timed benchmark; docs/statistics.md has
// the commands and the numbers.
//
//   statistics_benchmark paper [seeds] [motions] [outlier_fraction]
//                              [noise_prior_weight]
//   statistics_benchmark drive [seeds] [odometry_hz] [camera_hz] [noise_factor]
//                              [vo] [odometry_keep_every] [wheel_scale_errors]
//                              [odometry_resample_hz] [yaw_scale]
//                              [duration_s]
//   statistics_benchmark cost [motions] [estimate_noise]
//
// paper: the paper protocol with parametric camera noise (odometry 0.01 rad
// yaw / 2 % translation, camera 0.005 rad rotation / 0.01 rad translation
// direction), pairs given to CalibrateOdomCam without their covariances (as
// the CLI sees them). drive: 2-minute drives of the drive simulator
// (differential drive, both turn directions), associated like the CLI does,
// camera pose noise 0.02 deg / 2 mm times noise_factor. vo = 1: instead,
// camera poses composed from noisy relative motions (0.05 deg per axis and
// 1 % of the step length per step) and random wheel travel noise (2 % per
// odometry period), all times noise_factor (pair_formation_study's levels;
// its systematic wheel scale errors, +0.3 % / -0.2 %, with
// wheel_scale_errors = 1). odometry_keep_every = k keeps
// every k-th odometry sample after simulating (the simulator's camera rate
// must divide its odometry rate: 28 Hz / 7 Hz with k = 7 gives 4 Hz odometry
// and a 7 Hz camera). odometry_resample_hz keeps the odometry samples
// nearest to a grid at that rate (e.g. 3.8 Hz from 266 Hz, with a 7 Hz
// camera); yaw_scale divides the odometry's yaw increments (1.05: the
// sensors' yaw increments disagree by 5 %); duration_s: the drive's length
// (120 s). The drive mode also prints, for the default and the default +
// systematics, the runs with a noise level at the floor and at the ceiling
// (noise_estimation.h)
// and the runs whose result lies within its own 3 sigma of the same
// calibration with the given noise (--estimate_noise off), and the
// plain batch over all consecutive frames (no keyframes, no RANSAC), the
// issue's rotation reference, without and with the clock offset and the
// odometry intrinsics estimated (the like-for-like reference of the CLI's
// default), and the rotation RMSE ratios with paired bootstrap intervals.
// cost: one default calibration of the paper protocol's data (seed 1) with
// the noise estimated (estimate_noise = 1, the default) or given (0); prints
// its wall time and the process's peak resident memory before and after it.
// One size per process, so that the peak is this calibration's.

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/datasets/paper/paper_simulation.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"
#include "odomcal/solver/hand_eye_refine.h"

#include <sys/resource.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace odomcal {
namespace {

struct Errors {
  double rotation_deg = 0.0;
  double translation_m = 0.0;
  double scale_rel = 0.0;
};

Errors ErrorsOf(const Rigid3d& estimate,
                double scale,
                const Rigid3d& truth,
                double true_scale) {
  Errors e;
  e.rotation_deg =
      RotationAngle(estimate.rotation.conjugate() * truth.rotation) * kRadToDeg;
  e.translation_m = (estimate.translation - truth.translation).head<2>().norm();
  e.scale_rel = (scale - true_scale) / true_scale;
  return e;
}

// Sums over runs of one configuration.
struct Tally {
  int runs = 0, failures = 0, with_covariance = 0;
  int rotation_covered = 0, x_covered = 0, y_covered = 0, scale_covered = 0;
  double nees = 0.0;
  double used_fraction = 0.0;
  // Each run's squared errors, NaN where it failed (runs of the same seed
  // line up across tallies, for the paired bootstrap).
  std::vector<double> rotation_errors2, translation_errors2, scale_errors2;
  // Sum of the stated rotation variances (trace of the rotation block):
  // its root mean is what the covariance predicts the rotation RMSE to be.
  double stated_rotation_variance = 0.0;
  // Sums of the signed relative scale error and of the stated relative
  // scale standard deviation: a mean error beyond the mean stated sigma is a
  // bias the covariance does not cover.
  double scale_error_sum = 0.0;
  double stated_scale_stddev_sum = 0.0;
  // Sum of the stated x/y variances (trace of the x, y block): its root mean
  // is what the covariance predicts the x/y RMSE to be.
  double stated_xy_variance = 0.0;

  void Add(const CalibrationResult& result,
           const Rigid3d& truth,
           double true_scale) {
    ++runs;
    if (!result.has_estimate || result.metric_scales.empty() ||
        !std::isfinite(result.metric_scales[0])) {
      ++failures;
      for (auto* errors2 :
           {&rotation_errors2, &translation_errors2, &scale_errors2}) {
        errors2->push_back(std::numeric_limits<double>::quiet_NaN());
      }
      return;
    }
    const Errors e = ErrorsOf(
        result.odom_from_cam, result.metric_scales[0], truth, true_scale);
    rotation_errors2.push_back(e.rotation_deg * e.rotation_deg);
    translation_errors2.push_back(e.translation_m * e.translation_m);
    scale_errors2.push_back(e.scale_rel * e.scale_rel);
    scale_error_sum += e.scale_rel;
    used_fraction += static_cast<double>(result.diagnostics.num_pairs_used) /
                     result.diagnostics.num_pairs_in;
    if (!result.covariance || result.covariance->rows() < 6) return;
    ++with_covariance;
    const Eigen::MatrixXd& c = *result.covariance;
    Eigen::VectorXd error(6);
    error.head<3>() =
        LogRotation(truth.rotation * result.odom_from_cam.rotation.conjugate());
    error.segment<2>(3) =
        (truth.translation - result.odom_from_cam.translation).head<2>();
    error(5) = true_scale - result.metric_scales[0];
    auto within = [&](int k) {
      return std::abs(error(k)) <= 3.0 * std::sqrt(c(k, k));
    };
    rotation_covered += within(0) && within(1) && within(2);
    x_covered += within(3);
    y_covered += within(4);
    scale_covered += within(5);
    nees += error.dot(c.topLeftCorner<6, 6>().ldlt().solve(error));
    stated_rotation_variance += c.topLeftCorner<3, 3>().trace();
    stated_scale_stddev_sum += std::sqrt(c(5, 5)) / true_scale;
    stated_xy_variance += c.block<2, 2>(3, 3).trace();
  }

  double StatedRotationDeg() const {
    return std::sqrt(stated_rotation_variance / std::max(1, with_covariance)) *
           kRadToDeg;
  }

  // Over the runs that solved.
  static double Rmse(const std::vector<double>& errors2) {
    double sum = 0.0;
    int n = 0;
    for (double e2 : errors2) {
      if (!std::isfinite(e2)) continue;
      sum += e2;
      ++n;
    }
    return std::sqrt(sum / std::max(1, n));
  }
  void Print(const char* name) const {
    const double n = std::max(1, with_covariance);
    std::printf(
        "%-22s runs %3d fail %2d | RMSE rot %.4f deg  xy %.2f mm  scale "
        "%.3f %% | stated rot %.4f deg | within 3 sigma: rot %3.0f %%  x "
        "%3.0f %%  y %3.0f %%  scale %3.0f %% | mean NEES %.2f (6) | pairs "
        "used %.1f %% | mean scale error %+.3f %% (stated sigma %.3f %%) | "
        "stated xy %.2f mm\n",
        name,
        runs,
        failures,
        Rmse(rotation_errors2),
        1000.0 * Rmse(translation_errors2),
        100.0 * Rmse(scale_errors2),
        StatedRotationDeg(),
        100.0 * rotation_covered / n,
        100.0 * x_covered / n,
        100.0 * y_covered / n,
        100.0 * scale_covered / n,
        nees / n,
        100.0 * used_fraction / std::max(1, runs - failures),
        100.0 * scale_error_sum / std::max(1, runs - failures),
        100.0 * stated_scale_stddev_sum / n,
        1000.0 * std::sqrt(stated_xy_variance / n));
  }
};

// RMSE of `a` over that of `b` (squared errors per seed) on the seeds both
// solved, with the 95 % interval of a paired bootstrap over the seeds: a
// ratio over 30 runs is itself uncertain, and this says by how much.
struct RmseRatio {
  double ratio = 0.0, low = 0.0, high = 0.0;
};

RmseRatio PairedRmseRatio(const std::vector<double>& a,
                          const std::vector<double>& b) {
  std::vector<std::pair<double, double>> runs;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    if (std::isfinite(a[i]) && std::isfinite(b[i])) {
      runs.emplace_back(a[i], b[i]);
    }
  }
  RmseRatio result;
  if (runs.empty()) return result;
  auto ratio_of = [&](const std::vector<int>& draw) {
    double sum_a = 0.0, sum_b = 0.0;
    for (int k : draw) {
      sum_a += runs[k].first;
      sum_b += runs[k].second;
    }
    return std::sqrt(sum_a / sum_b);
  };
  std::vector<int> all(runs.size());
  std::iota(all.begin(), all.end(), 0);
  result.ratio = ratio_of(all);
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(runs.size()) - 1);
  std::vector<double> ratios;
  std::vector<int> draw(runs.size());
  for (int r = 0; r < 4000; ++r) {
    for (int& k : draw) k = pick(rng);
    ratios.push_back(ratio_of(draw));
  }
  std::sort(ratios.begin(), ratios.end());
  result.low = ratios[static_cast<size_t>(0.025 * ratios.size())];
  result.high = ratios[static_cast<size_t>(0.975 * ratios.size())];
  return result;
}

// The paper protocol's noise with parametric camera noise (file comment).
PaperSimulationOptions PaperProtocol(int motions) {
  PaperSimulationOptions simulation;
  simulation.num_motions = motions;
  simulation.odom_yaw_sigma_rad = 0.01;
  simulation.odom_translation_sigma_rel = 0.02;
  simulation.camera_noise = CameraNoiseMode::kParametric;
  simulation.cam_rotation_sigma_rad = 0.005;
  simulation.cam_direction_sigma_rad = 0.01;
  return simulation;
}

int RunPaper(int seeds,
             int motions,
             double outlier_fraction,
             double noise_prior_weight) {
  PaperSimulationOptions simulation = PaperProtocol(motions);
  simulation.outlier_fraction = outlier_fraction;
  Tally estimated, given, gt_b;
  for (int seed = 0; seed < seeds; ++seed) {
    std::mt19937_64 rng(1000 + seed);
    const Rigid3d truth = RandomOdomFromCam(&rng);
    const double scale = std::exp(std::uniform_real_distribution<double>(
        std::log(0.5), std::log(2.0))(rng));
    const PaperSimulation sim =
        SimulatePaperMotions(simulation, truth, {scale}, &rng);
    // GT-B on the inliers, with the true covariances.
    CalibrationOptions options;
    options.fixed_translation_z_m = truth.translation.z();
    options.noise_prior_weight = noise_prior_weight;
    std::vector<int> inliers;
    for (size_t i = 0; i < sim.pairs.size(); ++i) {
      if (!sim.is_outlier[i]) inliers.push_back(static_cast<int>(i));
    }
    const RefinementResult gt =
        RefineOdomFromCam(sim.pairs, inliers, truth, {scale}, options);
    CalibrationResult gt_result;  // GT-B's estimate; no covariance
    gt_result.has_estimate = gt.usable;
    gt_result.odom_from_cam = gt.odom_from_cam;
    gt_result.metric_scales = gt.metric_scales;
    gt_b.Add(gt_result, truth, scale);
    MotionPairs plain = sim.pairs;
    for (MotionPair& pair : plain) {
      pair.odom_covariance.reset();
      pair.cam_covariance.reset();
    }
    estimated.Add(CalibrateOdomCam(plain, options), truth, scale);
    options.estimate_noise = false;
    given.Add(CalibrateOdomCam(plain, options), truth, scale);
  }
  std::printf("paper protocol: %d seeds, %d motions, %.0f %% outliers\n",
              seeds,
              motions,
              100.0 * outlier_fraction);
  std::printf(
      "%-22s runs %3d fail %2d | RMSE rot %.4f deg  xy %.2f mm  scale "
      "%.3f %% | mean scale error %+.3f %%\n",
      "GT-B (inliers)",
      gt_b.runs,
      gt_b.failures,
      Tally::Rmse(gt_b.rotation_errors2),
      1000.0 * Tally::Rmse(gt_b.translation_errors2),
      100.0 * Tally::Rmse(gt_b.scale_errors2),
      100.0 * gt_b.scale_error_sum / std::max(1, gt_b.runs - gt_b.failures));
  for (const auto& [name, tally] :
       {std::pair<const char*, const Tally&>{"default", estimated},
        std::pair<const char*, const Tally&>{"--estimate_noise off", given}}) {
    tally.Print(name);
    const RmseRatio r =
        PairedRmseRatio(tally.rotation_errors2, gt_b.rotation_errors2);
    const RmseRatio t =
        PairedRmseRatio(tally.translation_errors2, gt_b.translation_errors2);
    const RmseRatio c =
        PairedRmseRatio(tally.scale_errors2, gt_b.scale_errors2);
    std::printf(
        "%-22s RMSE / GT-B (95 %% paired bootstrap): rot %.3f (%.3f-%.3f)  "
        "xy %.3f (%.3f-%.3f)  scale %.3f (%.3f-%.3f)\n",
        "",
        r.ratio,
        r.low,
        r.high,
        t.ratio,
        t.low,
        t.high,
        c.ratio,
        c.low,
        c.high);
  }
  return 0;
}

// The odometry's yaw increments divided by yaw_scale (the truth is then
// dtheta_true = yaw_scale dtheta_odometry, the systematics' model):
// re-integrated from the relative motions of consecutive samples.
void DisagreeInYaw(double yaw_scale, Trajectory* odometry) {
  std::vector<StampedPose>& poses = odometry->poses;
  if (poses.empty()) return;
  Rigid3d previous_true = poses[0].world_from_sensor;
  for (size_t i = 1; i < poses.size(); ++i) {
    const Rigid3d true_pose = poses[i].world_from_sensor;
    const Rigid3d step = Inverse(previous_true) * true_pose;
    const double yaw = LogRotation(step.rotation).z();
    const Rigid3d scaled_step(YawRotation(yaw / yaw_scale), step.translation);
    poses[i].world_from_sensor = poses[i - 1].world_from_sensor * scaled_step;
    previous_true = true_pose;
  }
}

// The samples nearest to a grid at `rate_hz` (their own stamps kept: a
// jitter of up to half the source's sample interval, as in real logs).
void Resample(double rate_hz, Trajectory* odometry) {
  const std::vector<StampedPose>& poses = odometry->poses;
  if (poses.size() < 2) return;
  std::vector<StampedPose> kept;
  const double period_ns = 1e9 / rate_hz;
  size_t i = 0;
  for (double t = static_cast<double>(poses.front().stamp_ns);
       t <= static_cast<double>(poses.back().stamp_ns);
       t += period_ns) {
    while (i + 1 < poses.size() && std::abs(poses[i + 1].stamp_ns - t) <
                                       std::abs(poses[i].stamp_ns - t)) {
      ++i;
    }
    if (kept.empty() || kept.back().stamp_ns != poses[i].stamp_ns) {
      kept.push_back(poses[i]);
    }
  }
  odometry->poses = kept;
}

// Whether `other` lies within `result`'s stated 3 sigma in rotation (each
// axis), x, y and the first scale.
bool WithinOwnThreeSigma(const CalibrationResult& result,
                         const CalibrationResult& other) {
  if (!result.covariance || result.covariance->rows() < 6 ||
      !other.has_estimate || other.metric_scales.empty()) {
    return false;
  }
  const Eigen::MatrixXd& c = *result.covariance;
  Eigen::VectorXd difference(6);
  difference.head<3>() = LogRotation(other.odom_from_cam.rotation *
                                     result.odom_from_cam.rotation.conjugate());
  difference.segment<2>(3) =
      (other.odom_from_cam.translation - result.odom_from_cam.translation)
          .head<2>();
  difference(5) = other.metric_scales[0] - result.metric_scales[0];
  for (int k = 0; k < 6; ++k) {
    if (std::abs(difference(k)) > 3.0 * std::sqrt(c(k, k))) return false;
  }
  return true;
}

bool NoiseAt(NoiseBound which, const CalibrationResult& result) {
  if (!result.noise_estimate) return false;
  for (const NoiseBound bound : result.noise_estimate->component_bound) {
    if (bound == which) return true;
  }
  return false;
}

int RunDrive(int seeds,
             double odometry_hz,
             double camera_hz,
             double noise_factor,
             bool vo,
             int keep_every,
             bool wheel_scale_errors,
             double resample_hz,
             double yaw_scale,
             double duration_s) {
  Tally estimated, given, batch, cli, batch_systematics;
  int cli_failures = 0;
  double yaw_scale_error2 = 0.0;
  int yaw_scale_estimated = 0, yaw_scale_covered = 0;
  int num_drifting = 0;  // runs whose camera poses the association saw drift
  // Per default / default + systematics: runs with a noise level at the
  // floor, at the ceiling, and runs within their own 3 sigma of the given
  // noise's result.
  int at_floor[2] = {0, 0}, at_ceiling[2] = {0, 0};
  int agrees_with_given[2] = {0, 0};
  for (int seed = 0; seed < seeds; ++seed) {
    DriveSimulatorOptions options;
    options.seed = 2000 + seed;
    options.duration_s = duration_s;
    options.odometry_rate_hz = odometry_hz;
    options.camera_rate_hz = camera_hz;
    if (vo) {
      options.camera_step_rotation_noise_deg = 0.05 * noise_factor;
      options.camera_step_translation_noise_rel = 0.01 * noise_factor;
      options.wheel_travel_noise_rel = 0.02 * noise_factor;
    } else {
      options.camera_rotation_noise_deg = 0.02 * noise_factor;
      options.camera_position_noise = 0.002 * noise_factor;
    }
    if (wheel_scale_errors) {
      options.wheel_scale_error_left = 0.003;
      options.wheel_scale_error_right = -0.002;
    }
    SimulatedDrive drive = SimulateDrive(options);
    std::vector<StampedPose> kept;
    for (size_t i = 0; i < drive.odometry.poses.size(); i += keep_every) {
      kept.push_back(drive.odometry.poses[i]);
    }
    drive.odometry.poses = kept;
    if (yaw_scale != 1.0) DisagreeInYaw(yaw_scale, &drive.odometry);
    if (resample_hz > 0.0) Resample(resample_hz, &drive.odometry);
    const AssociationResult association = AssociateCameraWithOdometry(
        {drive.camera}, drive.odometry, AssociationOptions());
    num_drifting += association.camera_pose_drift.drifting;
    CalibrationOptions calibration;
    calibration.fixed_translation_z_m = drive.odom_from_cam.translation.z();
    const CalibrationResult default_result =
        CalibrateOdomCam(association.pairs, calibration);
    estimated.Add(default_result, drive.odom_from_cam, drive.metric_scale);
    calibration.estimate_noise = false;
    const CalibrationResult given_result =
        CalibrateOdomCam(association.pairs, calibration);
    given.Add(given_result, drive.odom_from_cam, drive.metric_scale);
    at_floor[0] += NoiseAt(NoiseBound::kFloor, default_result);
    at_ceiling[0] += NoiseAt(NoiseBound::kCeiling, default_result);
    agrees_with_given[0] += WithinOwnThreeSigma(default_result, given_result);
    // The clock offset and the odometry intrinsics estimated with the
    // extrinsic (EstimateSystematics, as the CLI does), for the given
    // association and calibration options.
    auto with_systematics = [&](const AssociationOptions& association_options,
                                const CalibrationOptions& calibration_options,
                                SystematicsEstimate* systematics) {
      MotionPairs pairs;
      CalibrationResult result;
      AssociationResult final_association;
      *systematics = EstimateSystematics(
          {drive.camera},
          drive.odometry,
          association_options,
          calibration_options,
          SystematicsEstimationOptions(),
          [&](const AssociationResult& associated) {
            pairs = associated.pairs;
            result = CalibrateOdomCam(pairs, calibration_options);
            return std::make_pair(static_cast<const MotionPairs*>(&pairs),
                                  &result);
          },
          &final_association);
      return result;
    };
    // As `odomcal calibrate` with its defaults.
    {
      CalibrationOptions defaults;
      defaults.fixed_translation_z_m = drive.odom_from_cam.translation.z();
      SystematicsEstimate systematics;
      const CalibrationResult result =
          with_systematics(AssociationOptions(), defaults, &systematics);
      cli.Add(result, drive.odom_from_cam, drive.metric_scale);
      cli_failures += result.status != CalibrationStatus::kSuccess;
      if (systematics.intrinsics_estimated[0]) {
        const double error = systematics.intrinsics.yaw_scale - yaw_scale;
        yaw_scale_error2 += error * error;
        ++yaw_scale_estimated;
        yaw_scale_covered +=
            std::abs(error) <= 3.0 * systematics.intrinsics_stddev[0];
      }
      defaults.estimate_noise = false;
      SystematicsEstimate given_systematics;
      const CalibrationResult given_noise_result =
          with_systematics(AssociationOptions(), defaults, &given_systematics);
      at_floor[1] += NoiseAt(NoiseBound::kFloor, result);
      at_ceiling[1] += NoiseAt(NoiseBound::kCeiling, result);
      agrees_with_given[1] += WithinOwnThreeSigma(result, given_noise_result);
    }
    // The reference: every consecutive camera frame, no RANSAC; without and
    // with the systematics (the like-for-like reference of the CLI's
    // default, which estimates them).
    AssociationOptions all_frames;
    all_frames.keyframe_min_rotation_deg = 0.0;
    all_frames.keyframe_min_translation_m = 0.0;
    CalibrationOptions plain;
    plain.fixed_translation_z_m = drive.odom_from_cam.translation.z();
    plain.use_ransac = false;
    batch.Add(CalibrateOdomCam(AssociateCameraWithOdometry(
                                   {drive.camera}, drive.odometry, all_frames)
                                   .pairs,
                               plain),
              drive.odom_from_cam,
              drive.metric_scale);
    SystematicsEstimate unused;
    batch_systematics.Add(with_systematics(all_frames, plain, &unused),
                          drive.odom_from_cam,
                          drive.metric_scale);
  }
  std::printf(
      "drives: %d seeds, %g s, odometry %g Hz, camera %g Hz, noise %g x "
      "(%s)%s\n",
      seeds,
      duration_s,
      resample_hz > 0.0 ? resample_hz : odometry_hz / keep_every,
      camera_hz,
      noise_factor,
      vo ? "VO-like camera 0.05 deg, 1 %/step; wheel travel 2 %"
         : "camera pose 0.02 deg, 2 mm",
      wheel_scale_errors ? ", wheel scale errors +0.3 % / -0.2 %" : "");
  if (yaw_scale != 1.0) {
    std::printf("odometry yaw increments / %g (true yaw_scale %g)\n",
                yaw_scale,
                yaw_scale);
  }
  std::printf(
      "automatic keyframes: camera poses drift in %d of %d runs (keyframes "
      "1 deg / 0.02 m there, else 5 deg / 0.1 m)\n",
      num_drifting,
      seeds);
  estimated.Print("default");
  given.Print("--estimate_noise off");
  cli.Print("default + systematics");
  batch.Print("plain batch, all frames");
  batch_systematics.Print("plain batch + systematics");
  auto print_ratio = [](const char* name, const RmseRatio& r) {
    std::printf(
        "%-22s rotation RMSE %s: %.3f (95 %% paired bootstrap "
        "%.3f-%.3f)\n",
        "",
        name,
        r.ratio,
        r.low,
        r.high);
  };
  auto rotation_ratio = [](const Tally& a, const Tally& b) {
    return PairedRmseRatio(a.rotation_errors2, b.rotation_errors2);
  };
  print_ratio("default / plain batch", rotation_ratio(estimated, batch));
  print_ratio("default + systematics / plain batch",
              rotation_ratio(cli, batch));
  print_ratio("default + systematics / plain batch + systematics",
              rotation_ratio(cli, batch_systematics));
  std::printf(
      "%-22s default + systematics: %d of %d runs not successful (exit != "
      "0); yaw_scale estimated in %d, RMSE %.4f, within 3 sigma %d\n",
      "",
      cli_failures,
      seeds,
      yaw_scale_estimated,
      std::sqrt(yaw_scale_error2 / std::max(1, yaw_scale_estimated)),
      yaw_scale_covered);
  const char* names[2] = {"default", "default + systematics"};
  for (int k = 0; k < 2; ++k) {
    std::printf(
        "%-22s %s: of %d runs, a noise level at the floor in %d, at the "
        "ceiling in %d; within its own 3 sigma of the given noise's result "
        "in %d\n",
        "",
        names[k],
        seeds,
        at_floor[k],
        at_ceiling[k],
        agrees_with_given[k]);
  }
  return 0;
}

double PeakResidentMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
}

double CpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
         1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

int RunCost(int motions, bool estimate_noise) {
  const PaperSimulationOptions simulation = PaperProtocol(motions);
  std::mt19937_64 rng(1001);
  const Rigid3d truth = RandomOdomFromCam(&rng);
  MotionPairs pairs =
      SimulatePaperMotions(simulation, truth, {1.0}, &rng).pairs;
  for (MotionPair& pair : pairs) {
    pair.odom_covariance.reset();
    pair.cam_covariance.reset();
  }
  CalibrationOptions options;
  options.fixed_translation_z_m = truth.translation.z();
  options.estimate_noise = estimate_noise;
  const double before_mib = PeakResidentMiB();
  const double cpu_start = CpuSeconds();
  const auto start = std::chrono::steady_clock::now();
  const CalibrationResult result = CalibrateOdomCam(pairs, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  const double cpu_seconds = CpuSeconds() - cpu_start;
  std::printf(
      "%d motions, noise %s: %.3f s (CPU %.3f s), peak resident %.1f MiB "
      "(%.1f MiB before the calibration), %s\n",
      motions,
      estimate_noise ? "estimated" : "given",
      seconds,
      cpu_seconds,
      PeakResidentMiB(),
      before_mib,
      result.has_estimate ? "estimate" : "no estimate");
  return result.has_estimate ? 0 : 1;
}

}  // namespace
}  // namespace odomcal

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  auto arg = [&](int k, double fallback) {
    return argc > k ? std::atof(argv[k]) : fallback;
  };
  if (mode == "paper") {
    return odomcal::RunPaper(static_cast<int>(arg(2, 30)),
                             static_cast<int>(arg(3, 20)),
                             arg(4, 0.0),
                             arg(5, 0.0));
  }
  if (mode == "drive") {
    return odomcal::RunDrive(static_cast<int>(arg(2, 30)),
                             arg(3, 50.0),
                             arg(4, 5.0),
                             arg(5, 1.0),
                             arg(6, 0.0) != 0.0,
                             std::max(1, static_cast<int>(arg(7, 1))),
                             arg(8, 0.0) != 0.0,
                             arg(9, 0.0),
                             arg(10, 1.0),
                             arg(11, 120.0));
  }
  if (mode == "cost") {
    return odomcal::RunCost(static_cast<int>(arg(2, 10000)),
                            arg(3, 1.0) != 0.0);
  }
  std::fprintf(
      stderr,
      "usage: statistics_benchmark paper [seeds] [motions] "
      "[outlier_fraction] [noise_prior_weight] | drive [seeds] [odometry_hz] "
      "[camera_hz] [noise_factor] [vo] [odometry_keep_every] "
      "[wheel_scale_errors] [odometry_resample_hz] [yaw_scale] "
      "[duration_s] | "
      "cost [motions] [estimate_noise]\n");
  return 2;
}
