// Studies of the paper's Monte Carlo protocol behind docs/
// paper_reproduction.md: measurements run by hand that print markdown tables
// (not tests: they assert nothing). Not a timed benchmark.
//
//   paper_studies <study>
//
// Studies of why the batch methods diverge in landmark mode ("Why GT-B still
// diverged"), in this order by `batch_divergence`:
//   gtb_by_estimator           GT-B by two-view estimator, and the control
//   inconsistent_two_view      the inconsistent two-view estimates classified
//   nominal_landmark_point     every method at the nominal landmark point
//   gtb_inlier_rounds_control  GT-B, paper batch and inlier rounds, control
//   direction_scan             the direction scan in the B methods (14 min)
// Studies of the two-view estimates:
//   two_view_large_set         "Two-view estimates" on 5 000 motions
//   geometry                   "The geometry the paper does not state"
#include "odomcal/datasets/paper/paper_evaluation.h"
#include "odomcal/datasets/paper/paper_sweeps.h"
#include "odomcal/datasets/paper/two_view_consistency.h"
#include "odomcal/datasets/paper/two_view_pose.h"
#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/hand_eye_refine.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <numeric>
#include <optional>
#include <random>
#include <sstream>
#include <vector>

namespace odomcal {
namespace {

// Chi-square(5) 99.9th percentile: a motion beyond it is "inconsistent".
constexpr double kChiSquare5Quantile999 = 20.52;

struct Estimator {
  const char* name;
  bool multi_start;
  int minimal_samples;
  bool other_minima;
};

// The estimators of the two-view history, oldest first.
constexpr Estimator kEstimators[] = {
    {"8-point start only", false, 0, false},
    {"every start (8-point, 5-point)", true, 0, false},
    {"+ 7-point minimal samples", true, 10, false},
    {"+ covariance of the other minima (default)", true, 10, true},
};

PaperSimulationOptions Options(double step_sigma_m,
                               const Estimator& estimator) {
  PaperSimulationOptions options =
      NominalPaperSimulation(CameraNoiseMode::kLandmarks);
  options.translation_sigma_m = step_sigma_m;
  options.two_view_multi_start = estimator.multi_start;
  options.two_view_minimal_samples = estimator.minimal_samples;
  options.two_view_covariance_of_other_minima = estimator.other_minima;
  return options;
}

// Replaces every camera motion by the truth plus a draw from its own
// covariance: errors that match their covariances by construction.
void DrawConsistentCameraErrors(PaperSimulation* simulation,
                                std::mt19937_64* rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  for (size_t k = 0; k < simulation->pairs.size(); ++k) {
    MotionPair& pair = simulation->pairs[k];
    const Eigen::LLT<MotionCovariance> llt(*pair.cam_covariance);
    Eigen::Matrix<double, 6, 1> noise;
    for (int c = 0; c < 6; ++c) noise(c) = unit(*rng);
    noise = (llt.matrixL() * noise).eval();
    const Rigid3d& truth = simulation->true_pairs[k].cam_i_from_cam_j;
    pair.cam_i_from_cam_j =
        Rigid3d((ExpRotation(noise.head<3>()) * truth.rotation).normalized(),
                truth.translation + noise.tail<3>());
  }
}

struct GtBDiagnosis {
  int num_trials = 0;
  int num_diverged = 0;
  int exceed[6] = {0, 0, 0, 0, 0, 0};  // rx ry rz tx ty s beyond 3 sigma
  int num_clean = 0;                   // every motion's NEES below 20.52
  int num_clean_diverged = 0;
  double sum_squared_rotation_deg = 0.0;
  std::vector<double> batch_nees;  // 6 dof
};

// GT-B on one simulation (BatchRefinement `batch`), with the divergence test
// of paper_evaluation.h, added to `diagnosis`; `two_view` holds the errors of
// the simulation's own two-view estimates.
void AddGtB(const PaperSimulation& simulation,
            const TwoViewErrors& two_view,
            BatchRefinement batch,
            GtBDiagnosis* diagnosis) {
  CalibrationOptions refine;
  refine.robust_loss = RobustLoss::kNone;
  refine.fixed_translation_z_m = simulation.odom_from_cam.translation.z();
  refine.max_num_iterations = 100;
  const RefinementResult refined = RefineBatch(simulation.pairs,
                                               simulation.odom_from_cam,
                                               simulation.metric_scales,
                                               refine,
                                               batch)
                                       .refinement;
  if (!refined.usable || refined.information.rows() != 6) return;
  const Eigen::MatrixXd covariance = refined.information.inverse();
  Eigen::VectorXd error(6);
  error.head<3>() = LogRotation(simulation.odom_from_cam.rotation *
                                refined.odom_from_cam.rotation.conjugate());
  error.segment<2>(3) = simulation.odom_from_cam.translation.head<2>() -
                        refined.odom_from_cam.translation.head<2>();
  error(5) = simulation.metric_scales[0] - refined.metric_scales[0];
  bool diverged = false;
  for (int k = 0; k < 6; ++k) {
    if (std::abs(error(k)) > 3.0 * std::sqrt(covariance(k, k))) {
      ++diagnosis->exceed[k];
      diverged = true;
    }
  }
  const bool clean =
      *std::max_element(two_view.nees.begin(), two_view.nees.end()) <
      kChiSquare5Quantile999;
  ++diagnosis->num_trials;
  diagnosis->num_diverged += diverged;
  diagnosis->num_clean += clean;
  diagnosis->num_clean_diverged += clean && diverged;
  diagnosis->sum_squared_rotation_deg +=
      std::pow(error.head<3>().norm() * kRadToDeg, 2);
  diagnosis->batch_nees.push_back(error.dot(refined.information * error));
}

// GT-B (the paper's batch) on `num_trials` simulations, split by whether a
// trial holds an inconsistent motion.
GtBDiagnosis DiagnoseGtB(const PaperSimulationOptions& options,
                         int num_trials,
                         bool consistent_camera_errors) {
  GtBDiagnosis diagnosis;
  for (int t = 0; t < num_trials; ++t) {
    std::mt19937_64 rng(TrialSeed(800, "explore", 0, t));
    PaperSimulation simulation = SimulatePaperMotions(options, &rng);
    TwoViewErrors two_view;
    AddTwoViewErrors(simulation, &two_view);
    if (consistent_camera_errors) {
      DrawConsistentCameraErrors(&simulation, &rng);
    }
    AddGtB(simulation, two_view, BatchRefinement::kPaper, &diagnosis);
  }
  std::sort(diagnosis.batch_nees.begin(), diagnosis.batch_nees.end());
  return diagnosis;
}

void PrintRow(const char* geometry,
              const char* estimator,
              const GtBDiagnosis& d) {
  const int n = d.num_trials;
  const int dirty = n - d.num_clean;
  std::cout << "| " << geometry << " | " << estimator << " | "
            << std::sqrt(d.sum_squared_rotation_deg / n) << " | "
            << 100.0 * d.num_diverged / n << " | " << d.exceed[0] << " "
            << d.exceed[1] << " " << d.exceed[2] << " / " << d.exceed[3] << " "
            << d.exceed[4] << " / " << d.exceed[5] << " | "
            << d.num_clean_diverged << " of " << d.num_clean << " | "
            << d.num_diverged - d.num_clean_diverged << " of " << dirty << " | "
            << d.batch_nees[n / 2] << " / " << d.batch_nees[(n * 99) / 100]
            << " |\n";
}

// GT-B at the nominal landmark protocol and with 0.5 m steps, for each
// two-view estimator, and a control whose camera errors are drawn from the
// same covariances (200 trials at 0.2 m, 150 at 0.5 m). Columns: rotation RMSE,
// divergence, how many trials exceeded 3 sigma in rotation (x y z) /
// translation (x y) / scale, the divergences among trials whose motions all
// have a two-view NEES below the chi-square(5) 99.9th percentile and among the
// others, and the batch NEES (6 dof; chi-square(6): median 5.35, 99th
// percentile 16.8).
void GtBByTwoViewEstimator() {
  std::cout << "| step SD | two-view estimator | GT-B rot [deg] | GT-B div "
               "[%] | beyond 3 sigma: rot / xy / scale | div. among "
               "consistent trials | div. among trials with an inconsistent "
               "motion | batch NEES median / p99 |\n|---|---|---|---|---|---|"
               "---|---|\n";
  for (const double step : {0.2, 0.5}) {
    const char* geometry = step == 0.2 ? "0.2 m (nominal)" : "0.5 m";
    const int num_trials = step == 0.2 ? 200 : 150;
    for (const Estimator& estimator : kEstimators) {
      PrintRow(geometry,
               estimator.name,
               DiagnoseGtB(Options(step, estimator), num_trials, false));
    }
    PrintRow(geometry,
             "control: camera errors drawn from the every-start covariances",
             DiagnoseGtB(Options(step, kEstimators[1]), num_trials, true));
  }
}

// 5-dof NEES of a unit-translation estimate (rank-5 covariance).
double UnitNees(const Rigid3d& truth,
                const Rigid3d& estimate,
                const MotionCovariance& covariance) {
  Eigen::Matrix<double, 6, 1> error;
  error.head<3>() = LogRotation(truth.rotation * estimate.rotation.conjugate());
  error.tail<3>() = truth.translation.normalized() - estimate.translation;
  const Eigen::SelfAdjointEigenSolver<MotionCovariance> eigen(covariance);
  double nees = 0.0;
  for (int d = 1; d < 6; ++d) {
    const double projection = eigen.eigenvectors().col(d).dot(error);
    nees += projection * projection / eigen.eigenvalues()(d);
  }
  return nees;
}

// The inconsistent two-view estimates (NEES above the chi-square(5) 99.9th
// percentile) of 2000 motions with 0.5 m steps, classified: a local minimum
// (the bundle adjustment started at the truth ends at a lower cost), gross
// (direction more than 15 degrees off), and consistent when the covariance
// is evaluated at the truth (true pose and points) instead.
void InconsistentTwoViewEstimates() {
  const int num_motions = 2000;
  std::cout << "| two-view estimator | inconsistent [%] (chi-square: 0.1) "
               "| local minima | gross | consistent with the covariance at "
               "the truth | NEES median / p99 |\n|---|---|---|---|---|---|\n";
  for (const Estimator& estimator : kEstimators) {
    std::mt19937_64 rng(901);
    std::normal_distribution<double> unit(0.0, 1.0);
    std::uniform_real_distribution<double> yaw(-kPi / 2, kPi / 2);
    std::uniform_real_distribution<double> depth(0.5, 5.0);
    std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
    const double sigma = 1.0 / 400.0;
    TwoViewOptions options;
    options.multi_start = estimator.multi_start;
    options.num_minimal_samples = estimator.minimal_samples;
    options.covariance_of_other_minima = estimator.other_minima;
    int num = 0, num_bad = 0, num_local = 0, num_gross = 0, num_at_truth = 0;
    std::vector<double> nees;
    for (int m = 0; m < num_motions; ++m) {
      const Rigid3d odom_from_cam = RandomOdomFromCam(&rng);
      const Rigid3d odom_motion(
          YawRotation(yaw(rng)),
          Eigen::Vector3d(0.5 * unit(rng), 0.5 * unit(rng), 0.0));
      const Rigid3d motion =
          CameraMotionFromOdometryMotion(odom_motion, odom_from_cam, 1.0);
      const Rigid3d cam_j_from_cam_i = Inverse(motion);
      std::vector<Eigen::Vector2d> u_i, u_j;
      std::vector<Eigen::Vector3d> points;
      while (u_i.size() < 12) {
        const double z = depth(rng);
        const double x = coordinate(rng);
        const double y = coordinate(rng);
        const Eigen::Vector3d p_i(x * z, y * z, z);
        const Eigen::Vector3d p_j = cam_j_from_cam_i * p_i;
        if (p_j.z() < 0.5) continue;
        Eigen::Vector4d n;
        for (int c = 0; c < 4; ++c) n(c) = sigma * unit(rng);
        u_i.emplace_back(x + n(0), y + n(1));
        u_j.emplace_back(p_j.x() / p_j.z() + n(2), p_j.y() / p_j.z() + n(3));
        points.push_back(p_i);
      }
      const TwoViewEstimate estimate = EstimateTwoViewPose(u_i, u_j, options);
      const double length = motion.translation.norm();
      const Rigid3d unit_truth(motion.rotation, motion.translation / length);
      for (Eigen::Vector3d& point : points) point /= length;
      const std::optional<MotionCovariance> at_truth =
          TwoViewPoseCovarianceAt(u_i, u_j, unit_truth, points, options);
      if (!estimate.success || !at_truth) continue;
      ++num;
      const Rigid3d& pose = estimate.cam_i_from_cam_j;
      nees.push_back(UnitNees(unit_truth, pose, estimate.covariance));
      if (nees.back() < kChiSquare5Quantile999) continue;
      ++num_bad;
      TwoViewOptions from_truth = options;
      from_truth.initial_cam_i_from_cam_j = unit_truth;
      const TwoViewEstimate truth_start =
          EstimateTwoViewPose(u_i, u_j, from_truth);
      num_local += truth_start.success &&
                   truth_start.final_cost < estimate.final_cost - 1e-6;
      num_gross += unit_truth.translation.dot(pose.translation) <
                   std::cos(kGrossDirectionErrorDeg * kDegToRad);
      num_at_truth +=
          UnitNees(unit_truth, pose, *at_truth) < kChiSquare5Quantile999;
    }
    std::sort(nees.begin(), nees.end());
    std::cout << "| " << estimator.name << " | " << 100.0 * num_bad / num
              << " | " << num_local << " | " << num_gross << " | "
              << num_at_truth << " of " << num_bad << " | " << nees[num / 2]
              << " / " << nees[(num * 99) / 100] << " |\n";
  }
}

// Every method at the nominal landmark point (1 px, 20 motions) with the
// default two-view estimator, 200 trials on one thread, nominal and 0.5 m
// steps: rotation RMSE [deg], and divergence [%] for the B methods.
void NominalLandmarkPoint() {
  std::cout << "| step SD | B inlier test | ALS | ALSP-L | CM | ALS-B | "
               "ALSP-L-B | CM-B | GT-B "
               "|\n|---|---|---|---|---|---|---|---|---|\n";
  for (const double step : {0.2, 0.5}) {
    for (const bool inlier_test : {false, true}) {
      EvaluationOptions evaluation;
      evaluation.batch_refinement = inlier_test ? BatchRefinement::kInlierRounds
                                                : BatchRefinement::kPaper;
      // As measured for paper_reproduction.md: the test on C alone.
      evaluation.variance_factor = false;
      const SweepPointResult point =
          RunSweepPoint(Options(step, kEstimators[3]),
                        evaluation,
                        "pixel_noise",
                        3,
                        1.0,
                        200,
                        2,
                        0);
      std::cout << "| " << step << " m | " << (inlier_test ? "on" : "off");
      for (const EvaluationMethod method : AllEvaluationMethods()) {
        if (method == EvaluationMethod::kAlspOrthogonal) continue;
        const MethodSummary& summary = point[method];
        std::cout << " | " << summary.rmse_rotation_deg;
        if (IsBatchMethod(method)) {
          std::cout << " / " << 100.0 * summary.divergence_rate;
        }
      }
      std::cout << " |\n";
    }
  }
}

// GT-B at the nominal landmark point (default two-view estimator) with the
// paper's batch and with the inlier rounds, on the two-view estimates and on
// the control (camera errors drawn from the same covariances), the same
// 1000 simulations for all four: how much of the divergence the two-view
// estimates' inconsistency causes. Columns as GtBByTwoViewEstimator.
void GtBInlierRoundsAgainstControl() {
  const PaperSimulationOptions options = Options(0.2, kEstimators[3]);
  GtBDiagnosis diagnoses[2][2];  // [control][inlier rounds]
  for (int t = 0; t < 1000; ++t) {
    std::mt19937_64 rng(TrialSeed(801, "explore", 0, t));
    PaperSimulation simulation = SimulatePaperMotions(options, &rng);
    TwoViewErrors two_view;
    AddTwoViewErrors(simulation, &two_view);
    for (const bool control : {false, true}) {
      if (control) DrawConsistentCameraErrors(&simulation, &rng);
      for (const bool rounds : {false, true}) {
        AddGtB(
            simulation,
            two_view,
            rounds ? BatchRefinement::kInlierRounds : BatchRefinement::kPaper,
            &diagnoses[control][rounds]);
      }
    }
  }
  std::cout << "| camera motions | batch | GT-B rot [deg] | GT-B div [%] | "
               "beyond 3 sigma: rot / xy / scale | div. among consistent "
               "trials | div. among trials with an inconsistent motion | "
               "batch NEES median / p99 |\n|---|---|---|---|---|---|---|---|\n";
  for (const bool control : {false, true}) {
    for (const bool rounds : {false, true}) {
      GtBDiagnosis& d = diagnoses[control][rounds];
      std::sort(d.batch_nees.begin(), d.batch_nees.end());
      PrintRow(control ? "control: drawn from the covariances"
                       : "two-view estimates",
               rounds ? "inlier rounds" : "paper",
               d);
    }
  }
}

// The two-view direction scan in the B methods (docs/paper_reproduction.md,
// "The direction scan"): at three points of the
// sweeps, with their seeds (base seed 1), the scan off, on, and on with the
// inlier rounds testing each motion under its core covariance (the default).
// About 14 minutes on two threads.
void DirectionScanInTheBatch() {
  struct Point {
    const char* sweep;
    int index;
    double odom_translation_sigma_rel;
    double pixel_sigma;
  };
  const Point points[] = {{"pixel_noise", 3, 0.05, 1.0},
                          {"translation_noise", 2, 0.05, 1.0},
                          {"pixel_noise", 5, 0.05, 2.0}};
  std::cout << "| sweep point | variant | GT-B rot [deg] / x-y [mm] / scale "
               "[%]; divergence [%] (used [%]) | ALSP-L-B |\n| --- | --- | "
               "--- | --- |\n";
  for (const Point& point : points) {
    for (int variant = 0; variant < 3; ++variant) {
      PaperSimulationOptions simulation =
          NominalPaperSimulation(CameraNoiseMode::kLandmarks);
      simulation.odom_translation_sigma_rel = point.odom_translation_sigma_rel;
      simulation.pixel_sigma = point.pixel_sigma;
      if (variant == 0) simulation.two_view_direction_scan_points = 0;
      EvaluationOptions evaluation;
      evaluation.inlier_test_on_core_covariance = variant == 2;
      const SweepPointResult result = RunSweepPoint(simulation,
                                                    evaluation,
                                                    point.sweep,
                                                    point.index,
                                                    point.pixel_sigma,
                                                    1000,
                                                    2,
                                                    1);
      const char* names[] = {"no scan",
                             "scan, inlier test on the full covariance",
                             "scan, inlier test on the core (default)"};
      std::cout << "| " << point.sweep << " " << point.index << " | "
                << names[variant];
      for (const EvaluationMethod method :
           {EvaluationMethod::kGtB, EvaluationMethod::kAlspLengthPreservingB}) {
        const MethodSummary& m = result[method];
        std::printf(" | %.3f / %.2f / %.2f; %.1f (%.1f)",
                    m.rmse_rotation_deg,
                    1e3 * m.rmse_translation_m,
                    100.0 * m.rmse_scale_rel,
                    100.0 * m.divergence_rate,
                    100.0 * m.motions_used);
      }
      std::cout << " |" << std::endl;
    }
  }
}

// The two-view estimators compared on the nominal landmark protocol (1 px,
// 12 landmarks 0.5-5 m deep, f = 400 px, 20 motions per simulation): the
// same motions and observations for each.
struct TwoViewEstimator {
  const char* name;
  bool multi_start;
  int direction_scan_points;
};
const TwoViewEstimator kEightPointOnly = {"8-point only", false, 0};
const TwoViewEstimator kEveryStartNoScan = {
    "every start, no direction scan", true, 0};
const TwoViewEstimator kDefaultEstimator = {
    "every start and the direction scan (default)",
    true,
    TwoViewOptions().direction_scan_points};

// The two-view consistency of `num_simulations` nominal landmark
// simulations of 20 motions.
TwoViewConsistency NominalTwoViewConsistency(const TwoViewEstimator& estimator,
                                             int num_simulations,
                                             uint64_t seed) {
  PaperSimulationOptions options =
      NominalPaperSimulation(CameraNoiseMode::kLandmarks);
  options.two_view_multi_start = estimator.multi_start;
  options.two_view_direction_scan_points = estimator.direction_scan_points;
  std::mt19937_64 rng(seed);
  TwoViewErrors errors;
  for (int k = 0; k < num_simulations; ++k) {
    AddTwoViewErrors(SimulatePaperMotions(options, &rng), &errors);
  }
  return SummarizeTwoViewErrors(errors);
}

// The figures of docs/paper_reproduction.md, "Two-view estimates", on 5 000
// motions of the nominal protocol (seed 704), the three estimators.
void TwoViewLargeSet() {
  std::cout
      << "| two-view estimator | motions | NEES median | p90 | p99 | max | "
         "gross [%] |\n| --- | --- | --- | --- | --- | --- | --- |\n";
  for (const TwoViewEstimator& estimator :
       {kEightPointOnly, kEveryStartNoScan, kDefaultEstimator}) {
    const TwoViewConsistency c = NominalTwoViewConsistency(estimator, 250, 704);
    std::cout << "| " << estimator.name << " | " << c.num_motions << " | "
              << std::setprecision(3) << c.nees_median << " | "
              << c.nees_quantile_90 << " | " << c.nees_quantile_99 << " | "
              << c.nees_max << " | " << 100.0 * c.gross_error_rate << " |\n";
  }
  std::cout << "| chi-square(5) | | " << kChiSquare5Median << " | 9.24 | "
            << kChiSquare5Quantile99 << " | | |\n";
}

// The study of docs/paper_reproduction.md, "The geometry the paper does not
// state" (about 11 minutes on two threads). Prints one markdown row per
// geometry: the two-view NEES median and tail and the gross-error rate (1000
// motions), then over 300 trials of 20 motions at 1 px: ALS, and GT-B on every
// motion (the paper's batch) and ALSP-L-B and GT-B with the batch inlier test
// (the default), as rotation RMSE [deg] / x-y RMSE [mm] / scale RMSE [%] /
// divergence [%].
void GeometryStudy() {
  struct Geometry {
    const char* name;
    double min_depth_m, max_depth_m, max_normalized_coordinate;
    double translation_sigma_m;
  };
  const Geometry geometries[] = {
      {"depth 0.5-5 m, +-45 deg, step SD 0.2 m", 0.5, 5.0, 1.0, 0.2},
      {"depth 0.5-3 m", 0.5, 3.0, 1.0, 0.2},
      {"depth 0.5-2 m", 0.5, 2.0, 1.0, 0.2},
      {"depth 2-10 m", 2.0, 10.0, 1.0, 0.2},
      {"field of view +-30 deg", 0.5, 5.0, 0.577, 0.2},
      {"field of view +-60 deg", 0.5, 5.0, 1.732, 0.2},
      {"step SD 0.5 m", 0.5, 5.0, 1.0, 0.5},
  };
  auto cell = [](const MethodSummary& m) {
    std::ostringstream text;
    text << std::setprecision(3) << m.rmse_rotation_deg << " / "
         << 1000.0 * m.rmse_translation_m << " / " << 100.0 * m.rmse_scale_rel;
    if (std::isfinite(m.divergence_rate)) {  // a B method
      text << " / " << 100.0 * m.divergence_rate;
    }
    return text.str();
  };
  std::cout << "| geometry | NEES median / p99 | gross [%] | ALS | GT-B, every "
               "motion | ALSP-L-B | GT-B |\n";
  for (const Geometry& geometry : geometries) {
    PaperSimulationOptions options =
        NominalPaperSimulation(CameraNoiseMode::kLandmarks);
    options.min_depth_m = geometry.min_depth_m;
    options.max_depth_m = geometry.max_depth_m;
    options.max_normalized_coordinate = geometry.max_normalized_coordinate;
    options.translation_sigma_m = geometry.translation_sigma_m;
    std::mt19937_64 rng(702);
    TwoViewErrors errors;
    for (int k = 0; k < 50; ++k) {
      AddTwoViewErrors(SimulatePaperMotions(options, &rng), &errors);
    }
    const TwoViewConsistency c = SummarizeTwoViewErrors(errors);
    // As measured for paper_reproduction.md: divergence on C alone.
    EvaluationOptions rounds;
    rounds.variance_factor = false;
    EvaluationOptions every_motion = rounds;
    every_motion.batch_refinement = BatchRefinement::kPaper;
    const SweepPointResult plain =
        RunSweepPoint(options, every_motion, "geometry", 0, 0.0, 300, 2, 703);
    const SweepPointResult point =
        RunSweepPoint(options, rounds, "geometry", 0, 0.0, 300, 2, 703);
    std::cout << "| " << geometry.name << " | " << std::setprecision(3)
              << c.nees_median << " / " << c.nees_quantile_99 << " | "
              << 100.0 * c.gross_error_rate << " | "
              << cell(point[EvaluationMethod::kAls]) << " | "
              << cell(plain[EvaluationMethod::kGtB]) << " | "
              << cell(point[EvaluationMethod::kAlspLengthPreservingB]) << " | "
              << cell(point[EvaluationMethod::kGtB]) << " |\n";
  }
}

struct Study {
  const char* name;
  void (*run)();
};

void BatchDivergence();

constexpr Study kStudies[] = {
    {"gtb_by_estimator", GtBByTwoViewEstimator},
    {"inconsistent_two_view", InconsistentTwoViewEstimates},
    {"nominal_landmark_point", NominalLandmarkPoint},
    {"gtb_inlier_rounds_control", GtBInlierRoundsAgainstControl},
    {"direction_scan", DirectionScanInTheBatch},
    {"batch_divergence", BatchDivergence},
    {"two_view_large_set", TwoViewLargeSet},
    {"geometry", GeometryStudy},
};

// The five batch divergence studies, in the order of kStudies.
void BatchDivergence() {
  GtBByTwoViewEstimator();
  InconsistentTwoViewEstimates();
  NominalLandmarkPoint();
  GtBInlierRoundsAgainstControl();
  DirectionScanInTheBatch();
}

int Main(int argc, char** argv) {
  if (argc == 2) {
    for (const Study& study : kStudies) {
      if (std::strcmp(argv[1], study.name) == 0) {
        study.run();
        return 0;
      }
    }
  }
  std::fprintf(stderr, "usage: paper_studies <study>; studies:");
  for (const Study& study : kStudies) std::fprintf(stderr, " %s", study.name);
  std::fprintf(stderr, "\n");
  return 2;
}

}  // namespace
}  // namespace odomcal

int main(int argc, char** argv) { return odomcal::Main(argc, argv); }
