// camB_from_camA and its covariance (camera_pair.h): the transform against
// its definition, and the first-order propagation against a sampled one.

#include "odomcal/solver/camera_pair.h"

#include "odomcal/solver/rigid3.h"

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include <random>

namespace odomcal {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

Matrix6d RandomCovariance(std::mt19937_64* rng,
                          double rotation_sigma,
                          double translation_sigma,
                          bool z_held) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  Matrix6d square;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) square(r, c) = gauss(*rng);
  }
  Eigen::Matrix<double, 6, 1> scale;
  scale << Eigen::Vector3d::Constant(rotation_sigma),
      Eigen::Vector3d::Constant(translation_sigma);
  Matrix6d covariance = scale.asDiagonal() *
                        (square * square.transpose() / 6.0) *
                        scale.asDiagonal();
  if (z_held) {
    covariance.row(5).setZero();
    covariance.col(5).setZero();
  }
  return covariance;
}

// A draw of the extrinsic under its covariance (left rotation perturbation,
// additive translation).
Rigid3d Draw(const ExtrinsicWithCovariance& extrinsic, std::mt19937_64* rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  const Matrix6d c =
      extrinsic.covariance + 1e-30 * Matrix6d::Identity();  // z held: PSD
  const Eigen::LDLT<Matrix6d> ldlt(c);
  Vector6d z;
  for (int k = 0; k < 6; ++k) z(k) = gauss(*rng);
  const Vector6d d =
      ldlt.transpositionsP().transpose() *
      (ldlt.matrixL().toDenseMatrix() *
       (ldlt.vectorD().cwiseMax(0.0).cwiseSqrt().asDiagonal() * z));
  return Rigid3d(ExpRotation(d.head<3>()) * extrinsic.odom_from_cam.rotation,
                 extrinsic.odom_from_cam.translation + d.tail<3>());
}

TEST(CameraPair, TransformAndCovarianceMatchSampling) {
  std::mt19937_64 rng(5);
  ExtrinsicWithCovariance a, b;
  a.odom_from_cam = Rigid3d(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5),
                            Eigen::Vector3d(0.3, 0.0, 0.5));
  b.odom_from_cam =
      Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(
                  2.5, Eigen::Vector3d(0.2, -0.4, 0.9).normalized())),
              Eigen::Vector3d(-0.2, 0.05, 0.6));
  a.covariance = RandomCovariance(&rng, 0.01, 0.02, /*z_held=*/true);
  b.covariance = RandomCovariance(&rng, 0.02, 0.01, /*z_held=*/true);
  const CameraPairTransform pair = CameraPairOf(a, b);

  const Rigid3d expected = Inverse(b.odom_from_cam) * a.odom_from_cam;
  EXPECT_LT(
      RotationAngle(expected.rotation.inverse() * pair.camb_from_cama.rotation),
      1e-12);
  EXPECT_LT((expected.translation - pair.camb_from_cama.translation).norm(),
            1e-12);
  EXPECT_TRUE(pair.odom_offset_z_held);
  EXPECT_NEAR(pair.odom_offset_m.z(), -0.1, 1e-12);

  // Sampled covariance of [Log(R_BA R_hat^T), t_BA - t_hat] in camB.
  const int n = 20000;
  Matrix6d sampled = Matrix6d::Zero();
  for (int k = 0; k < n; ++k) {
    const Rigid3d draw = Inverse(Draw(b, &rng)) * Draw(a, &rng);
    Vector6d e;
    e << LogRotation(draw.rotation * pair.camb_from_cama.rotation.inverse()),
        draw.translation - pair.camb_from_cama.translation;
    sampled += e * e.transpose() / n;
  }
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) {
      const double scale =
          std::sqrt(pair.covariance(r, r) * pair.covariance(c, c));
      // 20000 draws: a correlation's sampling error is about 0.007; the
      // second-order terms of these small perturbations are below that.
      EXPECT_NEAR(sampled(r, c), pair.covariance(r, c), 0.03 * scale)
          << "row " << r << " col " << c;
    }
  }
  // Held heights: the offset's z carries no variance.
  EXPECT_EQ(pair.stddev_odom_offset_m.z(), 0.0);
}

TEST(CameraPair, CrossTermsOfOneAdjustmentMatchSampling) {
  // Two extrinsics estimated together (a rig's joint adjustment): one
  // 12 x 12 covariance, strongly correlated, as a shared trajectory makes
  // them.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss(0.0, 1.0);
  ExtrinsicWithCovariance a, b;
  a.odom_from_cam = Rigid3d(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5),
                            Eigen::Vector3d(0.3, 0.0, 0.5));
  b.odom_from_cam = Rigid3d(Eigen::Quaterniond(0.5, 0.5, -0.5, -0.5),
                            Eigen::Vector3d(-0.4, 0.1, 0.6));
  a.z_held = b.z_held = false;
  Eigen::Matrix<double, 12, 1> scale;
  scale << Eigen::Vector3d::Constant(0.01), Eigen::Vector3d::Constant(0.02),
      Eigen::Vector3d::Constant(0.01), Eigen::Vector3d::Constant(0.02);
  // b's perturbation is a's (the trajectory's share) plus its own third.
  Eigen::Matrix<double, 12, 12> square;
  for (int r = 0; r < 12; ++r) {
    for (int c = 0; c < 12; ++c) square(r, c) = gauss(rng) / std::sqrt(12.0);
  }
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 12; ++c) {
      square(r + 6, c) = square(r, c) + square(r + 6, c) / 3.0;
    }
  }
  const Eigen::Matrix<double, 12, 12> joint =
      scale.asDiagonal() * (square * square.transpose()) * scale.asDiagonal();
  a.covariance = joint.topLeftCorner<6, 6>();
  b.covariance = joint.bottomRightCorner<6, 6>();
  const Matrix6d cross = joint.topRightCorner<6, 6>();
  const CameraPairTransform pair = CameraPairOf(a, b, cross);
  const CameraPairTransform apart = CameraPairOf(a, b);
  const Eigen::LLT<Eigen::Matrix<double, 12, 12>> llt(joint);
  const int n = 20000;
  Matrix6d sampled = Matrix6d::Zero();
  Eigen::Vector3d offset_variance = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    Eigen::Matrix<double, 12, 1> z;
    for (int i = 0; i < 12; ++i) z(i) = gauss(rng);
    const Eigen::Matrix<double, 12, 1> d = llt.matrixL() * z;
    const Rigid3d da(ExpRotation(d.head<3>()) * a.odom_from_cam.rotation,
                     a.odom_from_cam.translation + d.segment<3>(3));
    const Rigid3d db(ExpRotation(d.segment<3>(6)) * b.odom_from_cam.rotation,
                     b.odom_from_cam.translation + d.tail<3>());
    const Rigid3d draw = Inverse(db) * da;
    Vector6d e;
    e << LogRotation(draw.rotation * pair.camb_from_cama.rotation.inverse()),
        draw.translation - pair.camb_from_cama.translation;
    sampled += e * e.transpose() / n;
    const Eigen::Vector3d offset =
        (da.translation - db.translation) - pair.odom_offset_m;
    offset_variance += offset.cwiseAbs2() / n;
  }
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) {
      const double scale_rc =
          std::sqrt(pair.covariance(r, r) * pair.covariance(c, c));
      EXPECT_NEAR(sampled(r, c), pair.covariance(r, c), 0.05 * scale_rc)
          << "row " << r << " col " << c;
    }
    // The shared part cancels (in rotation; the translation keeps the
    // lever of the common rotation): treating them as independent
    // overstates.
    EXPECT_LT(pair.covariance(r, r),
              (r < 3 ? 0.2 : 0.8) * apart.covariance(r, r))
        << "row " << r;
  }
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(pair.stddev_odom_offset_m[k],
                std::sqrt(offset_variance[k]),
                0.03 * pair.stddev_odom_offset_m[k]);
  }
}

TEST(CameraPair, ExtrinsicOfRefusesResultsThatAreNotCalibrations) {
  CalibrationResult result;
  EXPECT_FALSE(ExtrinsicOf(result).has_value());  // not run
  result.status = CalibrationStatus::kSuccess;
  result.has_estimate = true;
  EXPECT_FALSE(ExtrinsicOf(result).has_value());  // no covariance
  result.covariance = Eigen::MatrixXd::Identity(6, 6);
  ASSERT_TRUE(ExtrinsicOf(result).has_value());
  EXPECT_TRUE(ExtrinsicOf(result)->z_held);
  EXPECT_EQ(ExtrinsicOf(result)->covariance(5, 5), 0.0);
  result.observability.translation_z = Determination::kEstimated;
  EXPECT_EQ(ExtrinsicOf(result)->covariance(5, 5), 1.0);
  result.observability.translation_x = Determination::kUndetermined;
  EXPECT_FALSE(ExtrinsicOf(result).has_value());
}

}  // namespace
}  // namespace odomcal
