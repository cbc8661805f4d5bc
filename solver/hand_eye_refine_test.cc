#include "odomcal/solver/hand_eye_refine.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/hand_eye_cost.h"
#include "odomcal/solver/hand_eye_residual.h"
#include "odomcal/solver/planarity_check.h"
#include "odomcal/tests/test_seed.h"

#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace odomcal {
namespace {

std::vector<int> AllIndices(const MotionPairs& pairs) {
  std::vector<int> indices(pairs.size());
  for (size_t i = 0; i < pairs.size(); ++i) indices[i] = static_cast<int>(i);
  return indices;
}

TEST(HandEyeResidual, ZeroAtTheTruth) {
  auto rng = SeededRng(20);
  MotionSimulatorOptions options;
  options.num_segments = 2;
  const SimulatedMotions truth = SimulateMotions(options, &rng);
  for (const MotionPair& pair : truth.pairs) {
    const Vector6d r = HandEyeResidual(
        pair, truth.odom_from_cam, truth.metric_scales[pair.segment]);
    EXPECT_LT(r.norm(), 1e-12);
  }
}

// The covariance model matches the sample covariance of the residual under
// the simulator's noise (which follows the same measurement model).
TEST(HandEyeResidualCovariance, MatchesMonteCarlo) {
  auto rng = SeededRng(21);
  MotionSimulatorOptions options;
  options.num_pairs = 1;
  const SimulatedMotions truth = SimulateMotions(options, &rng);
  const MotionPair& exact = truth.pairs[0];
  const double scale = truth.metric_scales[0];
  NoiseModel noise;
  noise.odom_tilt_sigma_deg = 0.1;
  const Matrix6d predicted =
      HandEyeResidualCovariance(exact, truth.odom_from_cam, scale, noise);
  constexpr int kSamples = 20000;
  Matrix6d sample = Matrix6d::Zero();
  const double deg = kPi / 180.0;
  const double yaw =
      std::abs(LogRotation(exact.odom_i_from_odom_j.rotation).z());
  const double length = exact.odom_i_from_odom_j.translation.norm();
  const double in_plane = noise.odom_translation_sigma_m +
                          noise.odom_translation_sigma_rel * length;
  // A planar log's height error: the constant part and the slope over the
  // step, not the in-plane slip.
  ASSERT_TRUE(IsPlanarMotion(exact.odom_i_from_odom_j));
  const double height =
      std::hypot(noise.odom_translation_sigma_m, 0.1 * deg * length);
  for (int n = 0; n < kSamples; ++n) {
    MotionPair noisy = exact;
    noisy.odom_i_from_odom_j =
        PerturbMotion(exact.odom_i_from_odom_j,
                      Eigen::Vector3d(0.1 * deg,
                                      0.1 * deg,
                                      noise.odom_yaw_sigma_deg * deg +
                                          noise.odom_yaw_sigma_rel * yaw),
                      Eigen::Vector3d(in_plane, in_plane, height),
                      &rng);
    noisy.cam_i_from_cam_j = PerturbMotion(
        exact.cam_i_from_cam_j,
        Eigen::Vector3d::Constant(noise.cam_rotation_sigma_deg * deg),
        Eigen::Vector3d::Constant(noise.cam_translation_sigma_rel *
                                  exact.cam_i_from_cam_j.translation.norm()),
        &rng);
    const Vector6d r = HandEyeResidual(noisy, truth.odom_from_cam, scale);
    sample += r * r.transpose();
  }
  sample /= kSamples;
  // 20000 samples: relative standard error of a variance ~ 1 %.
  for (int k = 0; k < 6; ++k) {
    EXPECT_NEAR(sample(k, k) / predicted(k, k), 1.0, 0.05) << "diagonal " << k;
  }
}

// A planar log's height error is its constant part and the ground's slope
// over the step, not the in-plane slip; SE(3) odometry keeps it per axis.
TEST(HandEyeResidualCovariance, PlanarOdometryHeightIsNotSlip) {
  NoiseModel noise;
  noise.odom_translation_sigma_m = 0.002;
  noise.odom_translation_sigma_rel = 0.01;
  noise.odom_tilt_sigma_deg = 0.5;
  MotionPair pair;
  pair.odom_i_from_odom_j =
      Rigid3d(YawRotation(0.3), Eigen::Vector3d(3.0, 4.0, 0.0));
  const double in_plane = 0.002 + 0.01 * 5.0;
  const double slope = 0.5 * kPi / 180.0 * 5.0;
  MotionCovariance planar = OdometryCovariance(pair, noise, MeasuredStep(pair));
  EXPECT_NEAR(planar(3, 3), in_plane * in_plane, 1e-15);
  EXPECT_NEAR(planar(4, 4), in_plane * in_plane, 1e-15);
  EXPECT_NEAR(planar(5, 5), 0.002 * 0.002 + slope * slope, 1e-15);
  pair.odom_i_from_odom_j.translation.z() = 0.01;
  const double length = pair.odom_i_from_odom_j.translation.norm();
  const double per_axis = 0.002 + 0.01 * length;
  EXPECT_NEAR(OdometryCovariance(pair, noise, MeasuredStep(pair))(5, 5),
              per_axis * per_axis,
              1e-15);
}

// The step the noise is sized by: each sensor's measurement and the other's
// prediction of it, weighed by their variances.
TEST(ModelledStep, IsTheInverseVarianceMeanOfMeasurementAndPrediction) {
  const Rigid3d odom_from_cam(Eigen::Quaterniond::Identity(),
                              Eigen::Vector3d::Zero());
  MotionPair pair;
  pair.odom_i_from_odom_j =
      Rigid3d(YawRotation(0.2), Eigen::Vector3d(0.9, 0.0, 0.0));
  pair.cam_i_from_cam_j =
      Rigid3d(YawRotation(0.3), Eigen::Vector3d(0.55, 0.0, 0.0));
  const double scale = 2.0;  // the camera predicts a 1.1 m step
  NoiseModel noise;
  noise.odom_translation_sigma_m = 0.0;
  noise.odom_translation_sigma_rel = 0.02;  // sigma 0.018 m at 0.9 m
  noise.cam_translation_sigma_rel = 0.01;
  noise.cam_translation_along_sigma_rel = 0.01;  // sigma 0.011 m at 1.1 m
  noise.odom_yaw_sigma_deg = 0.0;
  noise.odom_yaw_sigma_rel = 0.05;  // sigma 0.01 rad at 0.2 rad
  noise.cam_rotation_sigma_deg = 0.01 * 180.0 / kPi;  // sigma 0.01 rad
  const StepSize step = ModelledStep(pair, odom_from_cam, scale, noise);
  const double odometry_variance = 0.018 * 0.018;
  const double camera_variance = 0.011 * 0.011;
  const double length = (camera_variance * 0.9 + odometry_variance * 1.1) /
                        (odometry_variance + camera_variance);
  EXPECT_NEAR(step.odometry_length_m, length, 1e-12);
  EXPECT_NEAR(step.camera_length, length / scale, 1e-12);
  EXPECT_NEAR(step.odometry_yaw_rad, 0.25, 1e-12);  // equal variances

  // The measured step where the estimate has no usable scale.
  const StepSize measured = ModelledStep(pair, odom_from_cam, 0.0, noise);
  EXPECT_DOUBLE_EQ(measured.odometry_length_m, 0.9);
  EXPECT_DOUBLE_EQ(measured.camera_length, 0.55);
  EXPECT_NEAR(measured.odometry_yaw_rad, 0.2, 1e-12);

  // An exact camera (no translation noise) decides the step alone.
  noise.cam_translation_sigma_rel = 0.0;
  noise.cam_translation_along_sigma_rel = 0.0;
  EXPECT_NEAR(ModelledStep(pair, odom_from_cam, scale, noise).odometry_length_m,
              1.1,
              1e-12);
}

// A trust-region step to a log-scale whose exp overflows is a failed
// evaluation, not a success with NaN residuals (which Ceres logs to stderr).
TEST(HandEyeCost, OverflowingScaleFailsTheEvaluation) {
  auto rng = SeededRng(23);
  MotionSimulatorOptions options;
  options.num_pairs = 2;
  const SimulatedMotions truth = SimulateMotions(options, &rng);
  const MotionPair& pair = truth.pairs[0];
  const Matrix6d w = HandEyeSqrtInformation(
      pair, truth.odom_from_cam, truth.metric_scales[0], NoiseModel());
  std::unique_ptr<ceres::CostFunction> cost(HandEyeCost::Create(pair, w));
  const Eigen::Quaterniond& q = truth.odom_from_cam.rotation;
  double q_xyzw[4] = {q.x(), q.y(), q.z(), q.w()};
  double p_xy[2] = {0.3, -0.1};
  double p_z[1] = {0.0};
  double residuals[6];
  double jacobian_q[24], jacobian_p[12], jacobian_s[6], jacobian_z[6];
  double* jacobians[] = {jacobian_q, jacobian_p, jacobian_s, jacobian_z};
  double log_scale[1] = {std::log(truth.metric_scales[0])};
  const double* parameters[] = {q_xyzw, p_xy, log_scale, p_z};
  EXPECT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  EXPECT_TRUE(cost->Evaluate(parameters, residuals, jacobians));
  log_scale[0] = 800.0;  // exp overflows
  EXPECT_FALSE(cost->Evaluate(parameters, residuals, nullptr));
  EXPECT_FALSE(cost->Evaluate(parameters, residuals, jacobians));
}

TEST(HandEyeCost, GradientCheckerPasses) {
  auto rng = SeededRng(22);
  MotionSimulatorOptions options;
  options.num_pairs = 10;
  options.add_noise = true;
  const SimulatedMotions truth = SimulateMotions(options, &rng);
  ceres::EigenQuaternionManifold quaternion_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {
      &quaternion_manifold, nullptr, nullptr, nullptr};
  for (const MotionPair& pair : truth.pairs) {
    const Matrix6d w = HandEyeSqrtInformation(
        pair, truth.odom_from_cam, truth.metric_scales[0], NoiseModel());
    std::unique_ptr<ceres::CostFunction> cost(HandEyeCost::Create(pair, w));
    // Evaluate away from the truth so that no residual is trivially zero.
    const Eigen::Quaterniond q = ExpRotation(Eigen::Vector3d(0.1, -0.2, 0.3)) *
                                 truth.odom_from_cam.rotation;
    double q_xyzw[4] = {q.x(), q.y(), q.z(), q.w()};
    double p_xy[2] = {0.3, -0.1};
    double log_scale[1] = {std::log(truth.metric_scales[0]) + 0.2};
    double p_z[1] = {0.05};
    const double* parameters[] = {q_xyzw, p_xy, log_scale, p_z};
    ceres::NumericDiffOptions numeric_diff_options;
    ceres::GradientChecker checker(
        cost.get(), &manifolds, numeric_diff_options);
    ceres::GradientChecker::ProbeResults results;
    checker.Probe(parameters, 1e-6, &results);
    ASSERT_EQ(results.local_jacobians.size(), 4u);
    // Ceres' own verdict is purely relative and flags entries that are zero
    // analytically and 1e-14 numerically; compare with a mixed tolerance.
    for (size_t block = 0; block < 4; ++block) {
      const auto& analytic = results.local_jacobians[block];
      const auto& numeric = results.local_numeric_jacobians[block];
      const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
      EXPECT_LT((analytic - numeric).cwiseAbs().maxCoeff(), 1e-7 * scale)
          << "block " << block << "\n"
          << results.error_log;
    }
  }
}

// Every pair refined, started at the simulation's truth.
RefinementResult RefineFromTheTruth(const SimulatedMotions& truth,
                                    const CalibrationOptions& calibration) {
  return RefineOdomFromCam(truth.pairs,
                           AllIndices(truth.pairs),
                           truth.odom_from_cam,
                           truth.metric_scales,
                           calibration);
}

TEST(RefineOdomFromCam, StaysAtTheTruthWithoutNoise) {
  auto rng = SeededRng(23);
  MotionSimulatorOptions options;
  options.num_segments = 2;
  const SimulatedMotions truth = SimulateMotions(options, &rng);
  CalibrationOptions calibration;
  calibration.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  const RefinementResult refined = RefineFromTheTruth(truth, calibration);
  ASSERT_TRUE(refined.usable) << refined.report;
  EXPECT_LT(refined.final_cost, 1e-20);
  EXPECT_LT(RotationAngle(refined.odom_from_cam.rotation.conjugate() *
                          truth.odom_from_cam.rotation),
            1e-10);
  EXPECT_LT(
      (refined.odom_from_cam.translation - truth.odom_from_cam.translation)
          .norm(),
      1e-10);
}

// The camera's translation noise grows with the scale: with the weights
// held at one scale, the estimate is the errors-in-variables one, low by
// the camera's relative variance over its three axes (here -0.80 %, 14
// standard errors of these runs' mean); weighed at the scale tried, it is
// not (-0.04 %).
TEST(RefineOdomFromCam, ScaleIsNotAttenuatedByTheCameraNoise) {
  auto rng = SeededRng(26);
  MotionSimulatorOptions options;
  options.num_pairs = 1000;
  options.add_noise = true;
  options.noise.cam_translation_sigma_rel = 0.05;
  options.noise.cam_translation_along_sigma_rel = 0.05;
  options.noise.odom_translation_sigma_m = 0.001;
  options.noise.odom_translation_sigma_rel = 0.001;
  constexpr int kRuns = 8;
  double error_sum = 0.0, variance_sum = 0.0;
  for (int run = 0; run < kRuns; ++run) {
    const SimulatedMotions truth = SimulateMotions(options, &rng);
    CalibrationOptions calibration;
    calibration.noise = options.noise;
    calibration.fixed_translation_z_m = truth.odom_from_cam.translation.z();
    const RefinementResult refined = RefineFromTheTruth(truth, calibration);
    ASSERT_TRUE(refined.usable) << refined.report;
    const double relative_variance =
        refined.information.inverse()(5, 5) /
        (truth.metric_scales[0] * truth.metric_scales[0]);
    error_sum += refined.metric_scales[0] / truth.metric_scales[0] - 1.0;
    variance_sum += relative_variance;
  }
  // The mean error within 3 standard errors of the mean.
  const double mean_error = error_sum / kRuns;
  const double standard_error = std::sqrt(variance_sum) / kRuns;
  EXPECT_LT(std::abs(mean_error), 3.0 * standard_error);
}

TEST(RefineOdomFromCam, ConvergesFromAPerturbedStart) {
  auto rng = SeededRng(24);
  for (int trial = 0; trial < 20; ++trial) {
    MotionSimulatorOptions options;
    options.num_segments = 1 + trial % 3;
    const SimulatedMotions truth = SimulateMotions(options, &rng);
    CalibrationOptions calibration;
    calibration.fixed_translation_z_m = truth.odom_from_cam.translation.z();
    Rigid3d start = truth.odom_from_cam;
    start.rotation =
        ExpRotation(Eigen::Vector3d(0.1, -0.08, 0.15)) * start.rotation;
    start.translation += Eigen::Vector3d(0.05, -0.04, 0.0);
    std::vector<double> scales = truth.metric_scales;
    for (double& s : scales) s *= 1.2;
    const RefinementResult refined = RefineOdomFromCam(
        truth.pairs, AllIndices(truth.pairs), start, scales, calibration);
    ASSERT_TRUE(refined.usable) << refined.report;
    EXPECT_LT(RotationAngle(refined.odom_from_cam.rotation.conjugate() *
                            truth.odom_from_cam.rotation) *
                  180.0 / kPi,
              1e-6);
    EXPECT_LT((refined.odom_from_cam.translation.head<2>() -
               truth.odom_from_cam.translation.head<2>())
                  .norm(),
              1e-9);
    for (size_t k = 0; k < scales.size(); ++k) {
      EXPECT_NEAR(refined.metric_scales[k] / truth.metric_scales[k], 1.0, 1e-9);
    }
  }
}

// A refinement that skips its information gets the same bits from
// RefinementInformation later; a result of other segments gets none.
TEST(RefinementInformation, IsTheRefinementsOwnComputedLater) {
  auto rng = SeededRng(25);
  MotionSimulatorOptions options;
  options.num_segments = 2;
  options.add_noise = true;
  const SimulatedMotions truth = SimulateMotions(options, &rng);
  CalibrationOptions calibration;
  calibration.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  Rigid3d start = truth.odom_from_cam;
  start.rotation =
      ExpRotation(Eigen::Vector3d(0.02, -0.01, 0.03)) * start.rotation;
  const std::vector<int> all = AllIndices(truth.pairs);
  const RefinementResult computed = RefineOdomFromCam(
      truth.pairs, all, start, truth.metric_scales, calibration);
  const RefinementResult skipped =
      RefineOdomFromCam(truth.pairs,
                        all,
                        start,
                        truth.metric_scales,
                        calibration,
                        TranslationZ::kHold,
                        InformationAtSolution::kSkip);
  ASSERT_TRUE(computed.usable && skipped.usable);
  ASSERT_GT(computed.information.size(), 0);
  EXPECT_EQ(skipped.information.size(), 0);
  std::vector<int> segments;
  const Eigen::MatrixXd later = RefinementInformation(truth.pairs,
                                                      all,
                                                      start,
                                                      truth.metric_scales,
                                                      calibration,
                                                      TranslationZ::kHold,
                                                      skipped,
                                                      &segments);
  EXPECT_TRUE(later == computed.information);
  EXPECT_EQ(segments, computed.information_segments);

  // Only segment 0's pairs: the solution's two scales do not fit.
  std::vector<int> first_segment;
  for (const int i : all) {
    if (truth.pairs[i].segment == 0) first_segment.push_back(i);
  }
  EXPECT_EQ(RefinementInformation(truth.pairs,
                                  first_segment,
                                  start,
                                  truth.metric_scales,
                                  calibration,
                                  TranslationZ::kHold,
                                  skipped,
                                  &segments)
                .size(),
            0);
}

// Information in reported coordinates: a left rotation perturbation of phi
// radians and scales in metres per unit. Checked against finite differences
// of the whitened cost: J^T J must equal the Gauss-Newton Hessian.
TEST(HandEyeInformation, MatchesFiniteDifferenceJacobian) {
  auto rng = SeededRng(25);
  MotionSimulatorOptions options;
  options.num_pairs = 15;
  const SimulatedMotions truth = SimulateMotions(options, &rng);
  CalibrationOptions calibration;
  calibration.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  const std::vector<int> all = AllIndices(truth.pairs);
  std::vector<int> segments;
  const Eigen::MatrixXd information = HandEyeInformation(truth.pairs,
                                                         all,
                                                         truth.odom_from_cam,
                                                         truth.metric_scales,
                                                         calibration,
                                                         &segments);
  ASSERT_EQ(information.rows(), 6);
  // Whitening fixed at the truth, as HandEyeInformation does.
  std::vector<Matrix6d> w;
  for (const MotionPair& pair : truth.pairs) {
    w.push_back(HandEyeSqrtInformation(
        pair, truth.odom_from_cam, truth.metric_scales[0], calibration.noise));
  }
  auto residuals = [&](const Eigen::VectorXd& x) {
    Rigid3d estimate = truth.odom_from_cam;
    estimate.rotation = ExpRotation(x.head<3>()) * estimate.rotation;
    estimate.translation.head<2>() += x.segment<2>(3);
    const double scale = truth.metric_scales[0] + x(5);
    Eigen::VectorXd r(6 * truth.pairs.size());
    for (size_t i = 0; i < truth.pairs.size(); ++i) {
      r.segment<6>(6 * i) =
          w[i] * HandEyeResidual(truth.pairs[i], estimate, scale);
    }
    return r;
  };
  Eigen::MatrixXd jacobian(6 * truth.pairs.size(), 6);
  constexpr double kStep = 1e-6;
  for (int k = 0; k < 6; ++k) {
    Eigen::VectorXd step = Eigen::VectorXd::Zero(6);
    step(k) = kStep;
    jacobian.col(k) = (residuals(step) - residuals(-step)) / (2 * kStep);
  }
  const Eigen::MatrixXd expected = jacobian.transpose() * jacobian;
  EXPECT_LT((information - expected).norm() / expected.norm(), 1e-5);
}

}  // namespace
}  // namespace odomcal
