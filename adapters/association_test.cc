#include "odomcal/adapters/association.h"

#include "odomcal/solver/angles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

namespace odomcal {
namespace {

// Exact interpolation and noise-free data: only double rounding remains
// (positions of a few metres, a few hundred compositions at most).
constexpr double kExactTolerance = 1e-12;
// Hand-eye residuals compose four transforms of ~10 m; still noise-free.
constexpr double kHandEyeTolerance = 1e-9;
constexpr int64_t kSecond = 1000000000;
// A Unix-like base stamp, so that nothing works only for small integers.
constexpr int64_t kBaseNs = 1403636579763555584;

double Radians(double degrees) { return degrees * kPi / 180.0; }

// Constant-velocity unicycle: forward speed v (m/s), yaw rate w (rad/s).
struct Unicycle {
  Eigen::Vector2d start_xy;
  double start_yaw = 0.0;
  double v = 0.0;
  double w = 0.0;

  // Closed form written as chord length and chord direction, which stays
  // well conditioned as w -> 0 (no v / w).
  Rigid3d PoseAt(double t) const {
    const double half_turn = 0.5 * w * t;
    const double sinc =
        std::abs(half_turn) < 1e-300 ? 1.0 : std::sin(half_turn) / half_turn;
    const double chord = v * t * sinc;
    const double heading = start_yaw + half_turn;
    const Eigen::Vector2d xy =
        start_xy +
        chord * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    return Rigid3d(YawRotation(start_yaw + w * t),
                   Eigen::Vector3d(xy.x(), xy.y(), 0.0));
  }
};

// Samples pose_at(t) at stamps base + i * step for i in [0, count).
Trajectory Sample(const std::function<Rigid3d(double)>& pose_at,
                  int64_t step_ns,
                  int count,
                  bool planar) {
  Trajectory trajectory;
  trajectory.planar = planar;
  for (int i = 0; i < count; ++i) {
    const int64_t offset_ns = step_ns * i;
    trajectory.poses.push_back(
        {kBaseNs + offset_ns, pose_at(static_cast<double>(offset_ns) / 1e9)});
  }
  return trajectory;
}

double SecondsSinceBase(int64_t stamp_ns) {
  return static_cast<double>(stamp_ns - kBaseNs) / 1e9;
}

void ExpectRigidNear(const Rigid3d& actual,
                     const Rigid3d& expected,
                     double tolerance) {
  EXPECT_LT(actual.rotation.angularDistance(expected.rotation), tolerance)
      << "rotation " << actual.rotation.coeffs().transpose() << " vs "
      << expected.rotation.coeffs().transpose();
  EXPECT_LT((actual.translation - expected.translation).norm(), tolerance)
      << "translation " << actual.translation.transpose() << " vs "
      << expected.translation.transpose();
}

Trajectory StraightLine(int count, int64_t step_ns, double speed_mps) {
  return Sample(
      [&](double t) {
        return Rigid3d(Eigen::Quaterniond::Identity(),
                       Eigen::Vector3d(speed_mps * t, 0.0, 0.0));
      },
      step_ns,
      count,
      /*planar=*/true);
}

// The odometry's pose at stamp_ns is the unicycle's, to rounding.
void ExpectUnicyclePoseAt(const Trajectory& odometry,
                          const Unicycle& unicycle,
                          int64_t stamp_ns) {
  SCOPED_TRACE(stamp_ns);
  InterpolationFailure why = InterpolationFailure::kInGap;
  const std::optional<Rigid3d> pose =
      InterpolateOdometry(odometry, stamp_ns, 0.25, &why);
  ASSERT_TRUE(pose.has_value());
  EXPECT_EQ(why, InterpolationFailure::kNone);
  ExpectRigidNear(
      *pose, unicycle.PoseAt(SecondsSinceBase(stamp_ns)), kExactTolerance);
}

TEST(InterpolateOdometry, PlanarExactOnUnicycleArc) {
  // Turns through yaw = pi (wrap-around) within the samples.
  const Unicycle unicycle{Eigen::Vector2d(2.0, -1.0), 2.9, 1.5, 0.8};
  const int64_t step_ns = 100000000;  // 10 Hz: 0.08 rad between samples
  const Trajectory odometry =
      Sample([&](double t) { return unicycle.PoseAt(t); }, step_ns, 21, true);
  for (int i = 0; i < 20; ++i) {
    for (const int64_t within_ns : {step_ns / 2, step_ns / 3, int64_t{1}}) {
      ExpectUnicyclePoseAt(
          odometry, unicycle, kBaseNs + i * step_ns + within_ns);
    }
  }
}

TEST(InterpolateOdometry, SlerpLinearIsNotExactOnArc) {
  // Documents why planar logs use SE(2): the chord misses the arc by about
  // the sagitta, here ~1.5 mm at mid-interval.
  const Unicycle unicycle{Eigen::Vector2d(0.0, 0.0), 0.0, 1.5, 0.8};
  const Trajectory odometry =
      Sample([&](double t) { return unicycle.PoseAt(t); }, 100000000, 3, false);
  const int64_t stamp_ns = kBaseNs + 50000000;
  const std::optional<Rigid3d> pose =
      InterpolateOdometry(odometry, stamp_ns, 0.25, nullptr);
  ASSERT_TRUE(pose.has_value());
  const double error =
      (pose->translation - unicycle.PoseAt(0.05).translation).norm();
  EXPECT_GT(error, 1e-3);
  EXPECT_LT(error, 2e-3);
}

TEST(InterpolateOdometry, PlanarSmallAngleLimit) {
  for (const double w : {0.0, 1e-7, -3e-6, 1e-5}) {
    SCOPED_TRACE(w);
    const Unicycle unicycle{Eigen::Vector2d(-4.0, 7.0), -0.7, 2.0, w};
    const int64_t step_ns = 100000000;
    const Trajectory odometry =
        Sample([&](double t) { return unicycle.PoseAt(t); }, step_ns, 11, true);
    for (int i = 0; i < 10; ++i) {
      const int64_t stamp_ns = kBaseNs + i * step_ns + step_ns / 4;
      const std::optional<Rigid3d> pose =
          InterpolateOdometry(odometry, stamp_ns, 0.25, nullptr);
      ASSERT_TRUE(pose.has_value());
      ExpectRigidNear(
          *pose, unicycle.PoseAt(SecondsSinceBase(stamp_ns)), kExactTolerance);
    }
  }
}

TEST(InterpolateOdometry, PlanarTurnInPlace) {
  // v = 0: only the yaw changes; the position must stay put.
  const Unicycle unicycle{Eigen::Vector2d(1.0, 1.0), 0.2, 0.0, -2.0};
  const Trajectory odometry =
      Sample([&](double t) { return unicycle.PoseAt(t); }, 100000000, 2, true);
  const std::optional<Rigid3d> pose =
      InterpolateOdometry(odometry, kBaseNs + 70000000, 0.25, nullptr);
  ASSERT_TRUE(pose.has_value());
  ExpectRigidNear(*pose, unicycle.PoseAt(0.07), kExactTolerance);
}

TEST(InterpolateOdometry, Se3EndpointsAndMidpoint) {
  const Rigid3d a(Eigen::Quaterniond(0.92736184954957035, 0.1, 0.2, 0.3),
                  Eigen::Vector3d(1.0, 2.0, 3.0));
  const Rigid3d b(a.rotation * ExpRotation(Eigen::Vector3d(0.3, -0.2, 0.5)),
                  Eigen::Vector3d(2.0, 0.0, 5.0));
  Trajectory odometry;
  odometry.poses = {{kBaseNs, a}, {kBaseNs + kSecond / 10, b}};

  const std::optional<Rigid3d> at_a =
      InterpolateOdometry(odometry, kBaseNs, 0.25, nullptr);
  ASSERT_TRUE(at_a.has_value());
  EXPECT_EQ(at_a->rotation.coeffs(), a.rotation.coeffs());
  EXPECT_EQ(at_a->translation, a.translation);
  const std::optional<Rigid3d> at_b =
      InterpolateOdometry(odometry, kBaseNs + kSecond / 10, 0.25, nullptr);
  ASSERT_TRUE(at_b.has_value());
  EXPECT_EQ(at_b->rotation.coeffs(), b.rotation.coeffs());
  EXPECT_EQ(at_b->translation, b.translation);

  const Rigid3d expected_mid(
      a.rotation * ExpRotation(0.5 * Eigen::Vector3d(0.3, -0.2, 0.5)),
      Eigen::Vector3d(1.5, 1.0, 4.0));
  const std::optional<Rigid3d> mid =
      InterpolateOdometry(odometry, kBaseNs + kSecond / 20, 0.25, nullptr);
  ASSERT_TRUE(mid.has_value());
  ExpectRigidNear(*mid, expected_mid, kExactTolerance);

  // The same rotation stored as -q takes the same (short) path.
  odometry.poses[1].world_from_sensor.rotation.coeffs() *= -1.0;
  const std::optional<Rigid3d> mid_negated =
      InterpolateOdometry(odometry, kBaseNs + kSecond / 20, 0.25, nullptr);
  ASSERT_TRUE(mid_negated.has_value());
  ExpectRigidNear(*mid_negated, expected_mid, kExactTolerance);
}

TEST(InterpolateOdometry, RefusesOutsideSpanAndInGaps) {
  Trajectory odometry;
  InterpolationFailure why = InterpolationFailure::kNone;
  EXPECT_FALSE(InterpolateOdometry(odometry, 0, 0.25, &why).has_value());
  EXPECT_EQ(why, InterpolationFailure::kOutsideSpan);

  odometry.poses = {{0, Rigid3d()},
                    {kSecond / 10, Rigid3d()},
                    {kSecond, Rigid3d()},  // 0.9 s gap before this one
                    {kSecond + kSecond / 4, Rigid3d()}};  // exactly the limit
  // Beyond a tenth of the end interval (0.1 s first, 0.25 s last).
  EXPECT_FALSE(InterpolateOdometry(odometry, -kSecond / 100 - 1, 0.25, &why)
                   .has_value());
  EXPECT_EQ(why, InterpolationFailure::kOutsideSpan);
  EXPECT_FALSE(
      InterpolateOdometry(
          odometry, kSecond + kSecond / 4 + kSecond / 40 + 1, 0.25, &why)
          .has_value());
  EXPECT_EQ(why, InterpolationFailure::kOutsideSpan);
  EXPECT_FALSE(
      InterpolateOdometry(odometry, kSecond / 2, 0.25, &why).has_value());
  EXPECT_EQ(why, InterpolationFailure::kInGap);

  // Samples at both ends of a gap are still usable, and a gap equal to the
  // limit is not refused.
  EXPECT_TRUE(InterpolateOdometry(odometry, kSecond, 0.25, &why).has_value());
  EXPECT_EQ(why, InterpolationFailure::kNone);
  EXPECT_TRUE(
      InterpolateOdometry(odometry, kSecond / 10, 0.25, nullptr).has_value());
  EXPECT_TRUE(
      InterpolateOdometry(odometry, kSecond + 1, 0.25, nullptr).has_value());
  EXPECT_TRUE(
      InterpolateOdometry(odometry, kSecond + kSecond / 4, 0.25, nullptr)
          .has_value());

  EXPECT_THROW(InterpolateOdometry(odometry, 0, 0.0, nullptr),
               std::invalid_argument);
  EXPECT_THROW(InterpolateOdometry(odometry, 0, NAN, nullptr),
               std::invalid_argument);
}

// Beyond the ends of the log the constant-velocity motion of the end
// interval is continued for at most a tenth of that interval (the slack a
// hair of estimated clock offset needs), never further.
TEST(InterpolateOdometry, ExtrapolatesATenthOfTheEndIntervalAtMost) {
  const Unicycle unicycle{Eigen::Vector2d(1.0, 2.0), 0.3, 1.5, 0.8};
  const int64_t step_ns = kSecond / 10;
  const Trajectory odometry =
      Sample([&](double t) { return unicycle.PoseAt(t); }, step_ns, 11, true);
  const int64_t first_ns = odometry.poses.front().stamp_ns;
  const int64_t last_ns = odometry.poses.back().stamp_ns;
  for (const int64_t stamp_ns : {last_ns + 3000,
                                 last_ns + step_ns / 10,
                                 first_ns - 3000,
                                 first_ns - step_ns / 10}) {
    // Exact: the unicycle keeps its velocity beyond the samples.
    ExpectUnicyclePoseAt(odometry, unicycle, stamp_ns);
  }
  for (const int64_t stamp_ns :
       {last_ns + step_ns / 10 + 1, first_ns - step_ns / 10 - 1}) {
    InterpolationFailure why = InterpolationFailure::kNone;
    EXPECT_FALSE(InterpolateOdometry(odometry, stamp_ns, 0.25, &why));
    EXPECT_EQ(why, InterpolationFailure::kOutsideSpan);
  }
  // Not beyond an end interval that is a gap (only the last one is: the
  // stamp is refused as outside the span, not in a gap).
  Trajectory last_gap = odometry;
  last_gap.poses.back().stamp_ns += 1000000000;
  InterpolationFailure why = InterpolationFailure::kNone;
  EXPECT_TRUE(InterpolateOdometry(
      last_gap, last_gap.poses[1].stamp_ns + 1000, 0.5, nullptr));
  EXPECT_FALSE(InterpolateOdometry(
      last_gap, last_gap.poses.back().stamp_ns + 3000, 0.5, &why));
  EXPECT_EQ(why, InterpolationFailure::kOutsideSpan);
}

TEST(AssociationOptions, CheckNamesTheField) {
  AssociationOptions options;
  EXPECT_NO_THROW(options.Check());
  options.max_odometry_gap_s = -1.0;  // 0 is automatic
  try {
    options.Check();
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& error) {
    // The field's name first, which the CLI turns into its flag.
    EXPECT_EQ(std::string(error.what()),
              "max_odometry_gap_s must be finite and > 0, got -1");
  }
  options = AssociationOptions();
  options.keyframe_min_rotation_deg = -1.5;
  try {
    options.Check();
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()),
              "keyframe_min_rotation_deg must be finite and >= 0, got -1.5");
  }
  options = AssociationOptions();
  options.keyframe_min_translation_m = INFINITY;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

TEST(AssociateCameraWithOdometry, KeyframesByTranslation) {
  // 1 m/s for 1 s at 100 Hz: 1 cm per sample.
  const Trajectory odometry = StraightLine(101, kSecond / 100, 1.0);
  AssociationOptions options;
  options.keyframe_min_translation_m = 0.095;  // every 10th sample
  options.keyframe_min_rotation_deg = 90.0;
  const AssociationResult result =
      AssociateCameraWithOdometry({odometry}, odometry, options);
  EXPECT_EQ(result.num_camera_poses, 101);
  EXPECT_EQ(result.num_usable_camera_poses, 101);
  EXPECT_EQ(result.num_keyframes, 11);
  ASSERT_EQ(result.keyframe_stamps_ns.size(), 11u);
  for (int k = 0; k < 11; ++k) {
    EXPECT_EQ(result.keyframe_stamps_ns[k], kBaseNs + k * kSecond / 10);
  }
  ASSERT_EQ(result.pairs.size(), 10u);
  for (const MotionPair& pair : result.pairs) {
    EXPECT_EQ(pair.stamp_j_ns - pair.stamp_i_ns, kSecond / 10);
    EXPECT_NEAR(pair.odom_i_from_odom_j.translation.x(), 0.1, kExactTolerance);
  }
  EXPECT_EQ(result.num_pairs_per_segment, std::vector<int>({10}));
}

TEST(AssociateCameraWithOdometry, KeyframesByRotationOrTranslation) {
  // Turning 1 degree per sample in place, then driving 2 cm per sample.
  Trajectory odometry;
  for (int i = 0; i <= 20; ++i) {
    odometry.poses.push_back(
        {kBaseNs + i * kSecond / 100,
         Rigid3d(YawRotation(Radians(i)), Eigen::Vector3d::Zero())});
  }
  const Eigen::Quaterniond heading = YawRotation(Radians(20));
  for (int i = 1; i <= 20; ++i) {
    odometry.poses.push_back(
        {kBaseNs + (20 + i) * kSecond / 100,
         Rigid3d(heading, heading * Eigen::Vector3d(0.02 * i, 0.0, 0.0))});
  }
  AssociationOptions options;
  options.keyframe_min_rotation_deg = 4.5;    // every 5th turning sample
  options.keyframe_min_translation_m = 0.07;  // every 4th driving sample
  const AssociationResult result =
      AssociateCameraWithOdometry({odometry}, odometry, options);
  std::vector<int64_t> expected;
  for (const int i : {0, 5, 10, 15, 20, 24, 28, 32, 36, 40}) {
    expected.push_back(kBaseNs + i * kSecond / 100);
  }
  EXPECT_EQ(result.keyframe_stamps_ns, expected);
  EXPECT_EQ(result.pairs.size(), expected.size() - 1);
}

TEST(AssociateCameraWithOdometry, CountsRefusalsAndBreaksChains) {
  // Odometry at 10 Hz over [0, 1] s and [2, 3] s, nothing in between.
  Trajectory odometry;
  odometry.planar = true;
  for (int i = 0; i <= 30; ++i) {
    if (i > 10 && i < 20) continue;
    odometry.poses.push_back({i * kSecond / 10,
                              Rigid3d(Eigen::Quaterniond::Identity(),
                                      Eigen::Vector3d(0.1 * i, 0.0, 0.0))});
  }
  Trajectory camera;
  for (const double t :
       {-0.5, 0.0, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 2.25, 2.5, 3.0, 3.5}) {
    camera.poses.push_back(
        {static_cast<int64_t>(std::llround(t * 1e9)), Rigid3d()});
  }
  AssociationOptions options;
  options.keyframe_min_rotation_deg = 0.0;  // every usable pose
  options.keyframe_min_translation_m = 0.0;
  const AssociationResult result =
      AssociateCameraWithOdometry({camera}, odometry, options);
  EXPECT_EQ(result.num_camera_poses, 12);
  EXPECT_EQ(result.num_outside_odometry_span, 2);
  EXPECT_EQ(result.num_in_odometry_gaps, 1);
  EXPECT_EQ(result.num_usable_camera_poses, 9);
  EXPECT_EQ(result.num_keyframes, 9);
  ASSERT_EQ(result.pairs.size(), 7u);  // 4 in [0, 1] s, 3 in [2, 3] s
  for (const MotionPair& pair : result.pairs) {
    EXPECT_FALSE(pair.stamp_i_ns < 3 * kSecond / 2 &&
                 pair.stamp_j_ns > 3 * kSecond / 2)
        << "pair spans the refused pose: " << pair.stamp_i_ns << " "
        << pair.stamp_j_ns;
    EXPECT_NEAR(
        pair.odom_i_from_odom_j.translation.x(),
        0.1 * static_cast<double>(pair.stamp_j_ns - pair.stamp_i_ns) / 1e8,
        kExactTolerance);
  }
}

TEST(AssociateCameraWithOdometry, AppliesCameraTimeOffset) {
  // odometry_time = camera_time + offset: a camera whose clock runs 2 s
  // behind the odometry is found with offset +2 s, not without it.
  const Trajectory odometry = StraightLine(11, kSecond / 10, 1.0);
  Trajectory camera = odometry;
  for (StampedPose& pose : camera.poses) pose.stamp_ns -= 2 * kSecond;
  AssociationOptions options;
  const AssociationResult without =
      AssociateCameraWithOdometry({camera}, odometry, options);
  EXPECT_EQ(without.num_outside_odometry_span, 11);
  EXPECT_TRUE(without.pairs.empty());
  options.camera_time_offset_ns = 2 * kSecond;
  const AssociationResult with =
      AssociateCameraWithOdometry({camera}, odometry, options);
  EXPECT_EQ(with.num_usable_camera_poses, 11);
  ASSERT_FALSE(with.pairs.empty());
  EXPECT_EQ(with.pairs.front().stamp_i_ns, odometry.poses.front().stamp_ns);
  EXPECT_EQ(without.camera_time_offset_ns, 0);  // the offset the stamps hold
  EXPECT_EQ(with.camera_time_offset_ns, 2 * kSecond);
}

// The images of a camera triggered with the odometry sit exactly on its
// samples; an estimated clock offset a hair above zero puts the last one a
// few microseconds after the log's end. It is kept (and the first one under
// a hair below zero), with the pose continued along the last interval; an
// offset beyond a tenth of the sampling interval still refuses it.
TEST(AssociateCameraWithOdometry,
     KeepsTheImageAtTheLastSampleUnderAHairOfOffset) {
  const Trajectory odometry = StraightLine(11, kSecond / 10, 1.0);
  const Trajectory camera = odometry;
  AssociationOptions options;
  options.keyframe_min_rotation_deg = 0.0;  // every usable pose
  options.keyframe_min_translation_m = 0.0;
  for (const int64_t offset_ns : {int64_t{3000}, int64_t{-3000}}) {
    SCOPED_TRACE(offset_ns);
    options.camera_time_offset_ns = offset_ns;
    const AssociationResult result =
        AssociateCameraWithOdometry({camera}, odometry, options);
    EXPECT_EQ(result.num_outside_odometry_span, 0);
    EXPECT_EQ(result.num_usable_camera_poses, 11);
    ASSERT_EQ(result.pairs.size(), 10u);
    const MotionPair& end =
        offset_ns > 0 ? result.pairs.back() : result.pairs.front();
    EXPECT_EQ(offset_ns > 0 ? end.stamp_j_ns : end.stamp_i_ns,
              (offset_ns > 0 ? odometry.poses.back().stamp_ns
                             : odometry.poses.front().stamp_ns) +
                  offset_ns);
    EXPECT_NEAR(end.odom_i_from_odom_j.translation.x(), 0.1, kExactTolerance);
  }
  options.camera_time_offset_ns = kSecond / 100 + 1;
  EXPECT_EQ(AssociateCameraWithOdometry({camera}, odometry, options)
                .num_outside_odometry_span,
            1);
}

TEST(AssociateCameraWithOdometry, RejectsUnsortedInput) {
  Trajectory odometry = StraightLine(3, kSecond, 1.0);
  Trajectory camera = odometry;
  std::swap(camera.poses[0], camera.poses[1]);
  EXPECT_THROW(
      AssociateCameraWithOdometry({camera}, odometry, AssociationOptions()),
      std::invalid_argument);
  EXPECT_THROW(
      AssociateCameraWithOdometry({odometry}, camera, AssociationOptions()),
      std::invalid_argument);
}

// Camera poses of a rigidly mounted camera in an SfM frame with its own
// gauge and scale: x_in_world = (sfm_from_origin * x_in_origin) / scale.
Trajectory CameraSegment(const Rigid3d& odom_from_cam,
                         const Rigid3d& sfm_from_origin,
                         double metres_per_unit,
                         double begin_s,
                         double end_s,
                         int64_t step_ns,
                         int64_t camera_time_offset_ns,
                         const std::function<Rigid3d(double)>& odometry_at) {
  Trajectory camera;
  for (int64_t offset_ns = static_cast<int64_t>(begin_s * 1e9);
       offset_ns <= static_cast<int64_t>(end_s * 1e9);
       offset_ns += step_ns) {
    const Rigid3d origin_from_cam =
        odometry_at(static_cast<double>(offset_ns) / 1e9) * odom_from_cam;
    Rigid3d world_from_cam = sfm_from_origin * origin_from_cam;
    world_from_cam.translation /= metres_per_unit;
    camera.poses.push_back(
        {kBaseNs + offset_ns - camera_time_offset_ns, world_from_cam});
  }
  return camera;
}

void ExpectHandEyeHolds(const AssociationResult& result,
                        const Rigid3d& odom_from_cam,
                        const std::vector<double>& metres_per_unit) {
  for (const MotionPair& pair : result.pairs) {
    ASSERT_GE(pair.segment, 0);
    ASSERT_LT(pair.segment, static_cast<int>(metres_per_unit.size()));
    Rigid3d cam_i_from_cam_j_metric = pair.cam_i_from_cam_j;
    cam_i_from_cam_j_metric.translation *= metres_per_unit[pair.segment];
    ExpectRigidNear(pair.odom_i_from_odom_j * odom_from_cam,
                    odom_from_cam * cam_i_from_cam_j_metric,
                    kHandEyeTolerance);
  }
}

TEST(AssociateCameraWithOdometry, PairsSatisfyHandEyeWithKnownExtrinsic) {
  const auto odometry_at = [](double t) {
    return Rigid3d(
        ExpRotation(Eigen::Vector3d(
            0.1 * std::sin(t), 0.2 * std::cos(0.5 * t), 0.7 * t)),
        Eigen::Vector3d(2.0 * std::cos(t), 3.0 * std::sin(t), 0.3 * t));
  };
  const int64_t odometry_step_ns = kSecond / 100;
  const Trajectory odometry =
      Sample(odometry_at, odometry_step_ns, 1001, /*planar=*/false);
  const Rigid3d odom_from_cam(
      Eigen::Quaterniond(
          0.5, -0.5, 0.5, -0.5),  // cam z forward, x right, y down
      Eigen::Vector3d(0.4, -0.05, 1.2));
  const int64_t offset_ns = -7654321;
  // Camera every 3rd odometry sample, so lookups hit samples exactly.
  const Trajectory segment0 =
      CameraSegment(odom_from_cam,
                    Rigid3d(ExpRotation(Eigen::Vector3d(0.3, -1.0, 2.0)),
                            Eigen::Vector3d(5, -3, 1)),
                    2.5,
                    0.5,
                    4.5,
                    3 * odometry_step_ns,
                    offset_ns,
                    odometry_at);
  const Trajectory segment1 =
      CameraSegment(odom_from_cam,
                    Rigid3d(ExpRotation(Eigen::Vector3d(-2.0, 0.1, 0.4)),
                            Eigen::Vector3d(-10, 0, 7)),
                    0.04,
                    5.5,
                    9.5,
                    3 * odometry_step_ns,
                    offset_ns,
                    odometry_at);
  AssociationOptions options;
  options.camera_time_offset_ns = offset_ns;
  const AssociationResult result =
      AssociateCameraWithOdometry({segment0, segment1}, odometry, options);

  EXPECT_EQ(result.num_camera_poses,
            static_cast<int>(segment0.poses.size() + segment1.poses.size()));
  EXPECT_EQ(result.num_usable_camera_poses, result.num_camera_poses);
  ASSERT_EQ(result.num_pairs_per_segment.size(), 2u);
  EXPECT_GT(result.num_pairs_per_segment[0], 10);
  EXPECT_GT(result.num_pairs_per_segment[1], 10);
  ASSERT_EQ(result.pairs.size(),
            static_cast<size_t>(result.num_pairs_per_segment[0] +
                                result.num_pairs_per_segment[1]));
  for (size_t k = 0; k < result.pairs.size(); ++k) {
    const MotionPair& pair = result.pairs[k];
    const int expected_segment =
        static_cast<int>(k) < result.num_pairs_per_segment[0] ? 0 : 1;
    EXPECT_EQ(pair.segment, expected_segment);
    // Stamps are odometry times, inside the segment's span.
    const double begin_s = expected_segment == 0 ? 0.5 : 5.5;
    EXPECT_GE(SecondsSinceBase(pair.stamp_i_ns), begin_s - 1e-9);
    EXPECT_LT(pair.stamp_i_ns, pair.stamp_j_ns);
    // Each pair moved past a threshold.
    EXPECT_TRUE(RotationAngle(pair.odom_i_from_odom_j.rotation) >=
                    Radians(options.keyframe_min_rotation_deg) ||
                pair.odom_i_from_odom_j.translation.norm() >=
                    options.keyframe_min_translation_m);
  }
  ExpectHandEyeHolds(result, odom_from_cam, {2.5, 0.04});
}

TEST(AssociateCameraWithOdometry, PlanarInterpolatedPairsSatisfyHandEye) {
  // Odometry at 20 Hz on a unicycle arc; the camera runs every 37 ms with a
  // clock offset, so most lookups interpolate, exactly, in SE(2).
  const Unicycle unicycle{Eigen::Vector2d(1.0, 2.0), 0.4, 1.2, 0.5};
  const auto odometry_at = [&](double t) { return unicycle.PoseAt(t); };
  const Trajectory odometry =
      Sample(odometry_at, kSecond / 20, 201, /*planar=*/true);
  const Rigid3d odom_from_cam(
      Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5) *
          ExpRotation(Eigen::Vector3d(0.02, -0.03, 0.01)),
      Eigen::Vector3d(0.3, 0.1, 0.8));
  const int64_t offset_ns = 3 * kSecond / 1000;
  const Trajectory camera = CameraSegment(odom_from_cam,
                                          Rigid3d(),
                                          0.5,
                                          0.0,
                                          10.0,
                                          37 * kSecond / 1000,
                                          offset_ns,
                                          odometry_at);
  AssociationOptions options;
  options.camera_time_offset_ns = offset_ns;
  const AssociationResult result =
      AssociateCameraWithOdometry({camera}, odometry, options);
  EXPECT_EQ(result.num_usable_camera_poses, result.num_camera_poses);
  EXPECT_GT(result.pairs.size(), 20u);
  ExpectHandEyeHolds(result, odom_from_cam, {0.5});
}

}  // namespace
}  // namespace odomcal

namespace odomcal {
namespace {

// Samples at base + i * period_s (+ jitter_s[i] when given).
Trajectory StraightLog(double period_s,
                       int count,
                       const std::vector<double>& jitter_s = {}) {
  Trajectory log;
  log.planar = true;
  for (int i = 0; i < count; ++i) {
    const double t = i * period_s + (jitter_s.empty() ? 0.0 : jitter_s[i]);
    log.poses.push_back({kBaseNs + std::llround(t * 1e9),
                         Rigid3d(Eigen::Quaterniond::Identity(),
                                 Eigen::Vector3d(0.5 * t, 0.0, 0.0))});
  }
  return log;
}

TEST(AutomaticOdometryGap, FollowsTheSamplingWithinFloorAndCeiling) {
  // 50 Hz: 2.5 intervals = 0.05 s, below the floor (the old fixed default).
  EXPECT_DOUBLE_EQ(AutomaticOdometryGapS(StraightLog(0.02, 100)), 0.25);
  // 4 Hz: 2.5 x 0.25 s.
  EXPECT_NEAR(AutomaticOdometryGapS(StraightLog(0.25, 40)), 0.625, 1e-9);
  // 0.5 Hz: capped.
  EXPECT_DOUBLE_EQ(AutomaticOdometryGapS(StraightLog(2.0, 10)), 1.0);
  // Too few samples for an interval: the floor.
  EXPECT_DOUBLE_EQ(AutomaticOdometryGapS(StraightLog(0.25, 1)), 0.25);
  // An explicit value wins.
  EXPECT_DOUBLE_EQ(OdometryGapLimitS(0.3, StraightLog(0.25, 40)), 0.3);
  EXPECT_NEAR(OdometryGapLimitS(kAutomaticOdometryGap, StraightLog(0.25, 40)),
              0.625,
              1e-9);
}

TEST(AutomaticOdometryGap, IgnoresJitterAndStillRefusesDropouts) {
  // 4 Hz with +-20 % jitter on every stamp and a 1.25 s dropout (4 samples
  // missing) in the middle.
  std::vector<double> jitter_s;
  for (int i = 0; i < 60; ++i) jitter_s.push_back(0.05 * std::sin(1.7 * i));
  Trajectory log = StraightLog(0.25, 60, jitter_s);
  log.poses.erase(log.poses.begin() + 30, log.poses.begin() + 34);
  const double median_s = MedianSampleIntervalS(log);
  EXPECT_NEAR(median_s, 0.25, 0.03);
  EXPECT_NEAR(AutomaticOdometryGapS(log), 2.5 * median_s, 1e-12);
  // A camera time in the dropout is refused, one between two jittered
  // samples is not.
  Trajectory camera;
  const int64_t in_dropout =
      (log.poses[29].stamp_ns + log.poses[30].stamp_ns) / 2;
  const int64_t regular = (log.poses[10].stamp_ns + log.poses[11].stamp_ns) / 2;
  camera.poses = {{regular, Rigid3d()}, {in_dropout, Rigid3d()}};
  const AssociationResult result =
      AssociateCameraWithOdometry({camera}, log, AssociationOptions());
  EXPECT_EQ(result.num_usable_camera_poses, 1);
  EXPECT_EQ(result.num_in_odometry_gaps, 1);
  EXPECT_EQ(result.num_outside_odometry_span, 0);
  EXPECT_TRUE(result.max_odometry_gap_automatic);
  EXPECT_NEAR(result.max_odometry_gap_s, 2.5 * median_s, 1e-12);
}

// The MAPIR case: 3.8 Hz wheel odometry, a 7 Hz camera inside its span.
TEST(AutomaticOdometryGap, LowRateOdometryIsUsableAndCountedApart) {
  const double period_s = 1.0 / 3.8;
  const Trajectory odometry = StraightLog(period_s, 160);  // ~42 s
  Trajectory camera;
  for (int i = 0; i < 281; ++i) {
    camera.poses.push_back(
        {kBaseNs + std::llround((0.1 + i / 7.0) * 1e9), Rigid3d()});
  }
  camera.poses.push_back({kBaseNs - kSecond, Rigid3d()});  // before the log
  std::rotate(camera.poses.begin(), camera.poses.end() - 1, camera.poses.end());
  AssociationOptions options;
  AssociationResult result =
      AssociateCameraWithOdometry({camera}, odometry, options);
  EXPECT_NEAR(result.odometry_rate_hz, 3.8, 1e-6);
  EXPECT_NEAR(result.max_odometry_gap_s, 2.5 * period_s, 1e-6);
  EXPECT_EQ(result.num_camera_poses, 282);
  EXPECT_EQ(result.num_outside_odometry_span, 1);
  EXPECT_EQ(result.num_in_odometry_gaps, 0);
  EXPECT_EQ(result.num_usable_camera_poses, 281);
  // The old fixed 0.25 s: every pose between samples is "in a gap", none
  // outside the span but the one before it.
  options.max_odometry_gap_s = 0.25;
  result = AssociateCameraWithOdometry({camera}, odometry, options);
  EXPECT_FALSE(result.max_odometry_gap_automatic);
  EXPECT_DOUBLE_EQ(result.max_odometry_gap_s, 0.25);
  EXPECT_EQ(result.num_outside_odometry_span, 1);
  EXPECT_EQ(result.num_in_odometry_gaps + result.num_usable_camera_poses, 281);
  EXPECT_GT(result.num_in_odometry_gaps, 270);
}

// 1 deg / 2 cm keyframes (for VO-like poses): every frame the robot moved
// to, consecutively; frames while it stands still merge into one keyframe.
TEST(AssociateCameraWithOdometry, MovingFramePairsAreConsecutiveFrames) {
  // 50 Hz odometry: 1 s straight at 0.5 m/s, 1 s standing, 1 s turning in
  // place at 0.3 rad/s; 5 Hz camera on odometry stamps.
  Trajectory odometry;
  odometry.planar = true;
  for (int i = 0; i <= 150; ++i) {
    const double t = i / 50.0;
    const double x = 0.5 * std::min(t, 1.0);
    const double yaw = 0.3 * std::max(t - 2.0, 0.0);
    odometry.poses.push_back(
        {kBaseNs + i * kSecond / 50,
         Rigid3d(YawRotation(yaw), Eigen::Vector3d(x, 0.0, 0.0))});
  }
  Trajectory camera;
  for (int i = 0; i <= 150; i += 10) camera.poses.push_back(odometry.poses[i]);
  AssociationOptions options;
  options.keyframe_min_rotation_deg = 1.0;
  options.keyframe_min_translation_m = 0.02;
  const AssociationResult result =
      AssociateCameraWithOdometry({camera}, odometry, options);
  EXPECT_EQ(result.num_usable_camera_poses, 16);
  // Frames at 0 .. 1 s (6), the standing ones merged into the one at 1 s,
  // then 2.2 .. 3 s (5; 3.4 degrees each): 5 + 5 pairs.
  ASSERT_EQ(result.pairs.size(), 10u);
  for (size_t p = 0; p < result.pairs.size(); ++p) {
    const MotionPair& pair = result.pairs[p];
    if (p > 0) {
      EXPECT_EQ(pair.stamp_i_ns, result.pairs[p - 1].stamp_j_ns);
    }
    // Camera times on odometry samples: nothing interpolated.
    EXPECT_FALSE(pair.odom_interpolation_covariance.has_value());
  }
  EXPECT_EQ(result.pairs[4].stamp_j_ns - kBaseNs, kSecond);
  EXPECT_EQ(result.pairs[5].stamp_i_ns - kBaseNs, kSecond);
  EXPECT_EQ(result.pairs[5].stamp_j_ns - kBaseNs, 22 * kSecond / 10);
}

}  // namespace
}  // namespace odomcal
