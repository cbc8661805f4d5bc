#include "odomcal/plugin/colmap/mapper_attempts.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/noise_estimation.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>

#include <cmath>

namespace odomcal {
namespace {

std::vector<ColmapSegment> OneSubModel(int num_registered_images) {
  ColmapSegment segment;
  segment.sub_model = "0";
  segment.num_registered_images = num_registered_images;
  return {segment};
}

// Noisy motions of a clean model, and the same motions with the camera
// rotation of two pairs turned 2 deg further, as COLMAP's mapper produced
// for one seed of the tilted preset.
class MapperAttemptsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto rng = SeededRng(90);
    MotionSimulatorOptions simulation;
    simulation.num_pairs = 40;
    simulation.add_noise = true;
    truth_ = SimulateMotions(simulation, &rng);
    options_.fixed_translation_z_m = truth_.odom_from_cam.translation.z();
  }

  StretchCheckResult Calibrate(const MotionPairs& pairs) const {
    return CalibrateWithStretchCheck(pairs, options_, StretchOptions());
  }

  MotionPairs WithMisregisteredImages(const std::vector<int>& broken_pairs = {
                                          11, 27}) const {
    MotionPairs pairs = truth_.pairs;
    const double two_deg = 2.0 * M_PI / 180.0;
    for (const int i : broken_pairs) {
      const Eigen::Vector3d axis = pairs[i].cam_i_from_cam_j.rotation *
                                   Eigen::Vector3d::UnitX();  // any axis
      pairs[i].cam_i_from_cam_j.rotation =
          Eigen::Quaterniond(Eigen::AngleAxisd(two_deg, axis)) *
          pairs[i].cam_i_from_cam_j.rotation;
    }
    return pairs;
  }

  // The same drive without turns: odometry and camera rotations identity.
  MotionPairs Straightened(MotionPairs pairs) const {
    const Rigid3d& x = truth_.odom_from_cam;
    for (MotionPair& pair : pairs) {
      pair.odom_i_from_odom_j.rotation = Eigen::Quaterniond::Identity();
      Rigid3d cam = Inverse(x) * pair.odom_i_from_odom_j * x;
      cam.translation /= truth_.metric_scales[0];
      pair.cam_i_from_cam_j = cam;
    }
    return pairs;
  }

  SimulatedMotions truth_;
  CalibrationOptions options_;
};

TEST_F(MapperAttemptsTest, AcceptsAModelTheOdometryAgreesWith) {
  const StretchCheckResult check = Calibrate(truth_.pairs);
  ASSERT_TRUE(check.result.IsSuccess()) << check.result.message;
  const MapperAttempt attempt =
      SummarizeMapperAttempt(0, "sparse", OneSubModel(41), check);
  EXPECT_TRUE(attempt.produced_model);
  EXPECT_EQ(attempt.num_sub_models, 1);
  EXPECT_EQ(attempt.num_registered_images, 41);
  EXPECT_EQ(attempt.num_pairs, 40);
  EXPECT_EQ(attempt.num_pairs_used, 40);
  EXPECT_EQ(attempt.num_contradicting_pairs, 0);
  EXPECT_TRUE(OdometryAcceptsModel(attempt));
}

// Two pairs 0.4 deg off, where the rest agree to a hundredth of that: beyond
// the noise estimated from the data (not used) but inside RANSAC's gate. A
// new mapper run would not be worth it: the model is accepted.
TEST_F(MapperAttemptsTest, AcceptsPairsBeyondOnlyTheEstimatedNoise) {
  auto rng = SeededRng(91);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 40;
  simulation.add_noise = true;
  simulation.noise = ScaleNoise(NoiseModel(), {0.01, 0.01, 0.01, 0.01});
  SimulatedMotions motions = SimulateMotions(simulation, &rng);
  for (const int i : {11, 27}) {
    Eigen::Quaterniond& rotation = motions.pairs[i].cam_i_from_cam_j.rotation;
    rotation = rotation * Eigen::Quaterniond(Eigen::AngleAxisd(
                              0.4 * M_PI / 180.0, Eigen::Vector3d::UnitX()));
  }
  CalibrationOptions options;  // the given noise 10x the data's
  options.fixed_translation_z_m = motions.odom_from_cam.translation.z();
  const StretchCheckResult check =
      CalibrateWithStretchCheck(motions.pairs, options, StretchOptions());
  ASSERT_TRUE(check.result.IsSuccess()) << check.result.message;
  const MapperAttempt attempt =
      SummarizeMapperAttempt(0, "sparse", OneSubModel(41), check);
  EXPECT_EQ(attempt.num_pairs, 40);
  EXPECT_EQ(attempt.num_pairs_used, 38);
  EXPECT_EQ(attempt.num_contradicting_pairs, 0);
  EXPECT_TRUE(attempt.contradicted_spans.empty());
  EXPECT_TRUE(OdometryAcceptsModel(attempt));
}

TEST_F(MapperAttemptsTest, CountsPairsTheOdometryContradicts) {
  const StretchCheckResult check = Calibrate(WithMisregisteredImages());
  ASSERT_TRUE(check.result.IsSuccess()) << check.result.message;
  const MapperAttempt attempt =
      SummarizeMapperAttempt(0, "sparse", OneSubModel(41), check);
  EXPECT_EQ(attempt.num_pairs, 40);
  EXPECT_EQ(attempt.num_pairs_used, 38);
  EXPECT_EQ(attempt.num_contradicting_pairs, 2);
  EXPECT_FALSE(OdometryAcceptsModel(attempt));
}

TEST_F(MapperAttemptsTest, PrefersTheCleanModelWhicheverSeedMadeIt) {
  const MapperAttempt broken = SummarizeMapperAttempt(
      0, "a/0", OneSubModel(41), Calibrate(WithMisregisteredImages()));
  const MapperAttempt clean = SummarizeMapperAttempt(
      1, "a/1", OneSubModel(41), Calibrate(truth_.pairs));
  EXPECT_TRUE(IsBetterMapperAttempt(clean, broken));
  EXPECT_FALSE(IsBetterMapperAttempt(broken, clean));
  EXPECT_EQ(BestMapperAttempt({broken, clean}), 1);
  EXPECT_EQ(BestMapperAttempt({clean, broken}), 0);
}

TEST_F(MapperAttemptsTest, CountsAStretchLeftOutAsContradicting) {
  StretchCheckResult check = Calibrate(truth_.pairs);
  InconsistentStretch folded;
  folded.num_pairs = 5;
  check.stretches.push_back(folded);
  const MapperAttempt attempt =
      SummarizeMapperAttempt(0, "sparse", OneSubModel(46), check);
  EXPECT_EQ(attempt.num_pairs, 45);
  EXPECT_EQ(attempt.num_contradicting_pairs, 5);
  EXPECT_EQ(attempt.num_pairs_left_out, 5);
  EXPECT_FALSE(OdometryAcceptsModel(attempt));
  // A stretch kept with a scale of its own is explained, not contradicting.
  check.stretches.back().kept_as_segment = true;
  EXPECT_TRUE(OdometryAcceptsModel(
      SummarizeMapperAttempt(0, "sparse", OneSubModel(46), check)));
}

TEST_F(MapperAttemptsTest, SeesTheSameContradictionsAgain) {
  const auto attempt = [&](int seed, const MotionPairs& pairs) {
    return SummarizeMapperAttempt(seed, "a", OneSubModel(41), Calibrate(pairs));
  };
  const MapperAttempt first = attempt(0, WithMisregisteredImages({11, 27}));
  ASSERT_EQ(first.contradicted_spans.size(), 2u);
  EXPECT_EQ(
      first.contradicted_spans[0],
      std::make_pair(truth_.pairs[11].stamp_i_ns, truth_.pairs[11].stamp_j_ns));
  EXPECT_TRUE(RepeatsContradictions(
      attempt(1, WithMisregisteredImages({11, 27})), first));
  EXPECT_FALSE(RepeatsContradictions(
      attempt(1, WithMisregisteredImages({11, 30})), first));
  EXPECT_FALSE(
      RepeatsContradictions(attempt(1, WithMisregisteredImages({11})), first));
  const MapperAttempt clean = attempt(1, truth_.pairs);
  EXPECT_FALSE(RepeatsContradictions(clean, clean));
}

TEST_F(MapperAttemptsTest, MatchesAgainWhileNoModelIsAccepted) {
  const MapperAttempt clean =
      SummarizeMapperAttempt(0, "a", OneSubModel(41), Calibrate(truth_.pairs));
  const MapperAttempt outliers = SummarizeMapperAttempt(
      1, "b", OneSubModel(41), Calibrate(WithMisregisteredImages()));
  MapperAttempt no_model;

  // An accepted model needs nothing more, whatever came before it.
  EXPECT_FALSE(ShouldMatchAgain({outliers, clean}));
  // Contradicted models, whether the seeds repeated the pairs or not.
  EXPECT_TRUE(ShouldMatchAgain({outliers, outliers}));
  EXPECT_TRUE(ShouldMatchAgain({no_model, outliers}));
  // No model at all: new matches would not make one.
  EXPECT_FALSE(ShouldMatchAgain({no_model, no_model}));
  EXPECT_FALSE(ShouldMatchAgain({}));
}

// Straight driving: the calibration refuses for the motion, judging no
// pair, so nothing contradicts the odometry and another mapper run (on the
// same drive) has nothing to improve. Seen on the `straight` preset, where
// every pair counted as contradicting cost two mapper runs and a second
// matching, and a warning blamed the odometry.
TEST_F(MapperAttemptsTest, StraightDrivingContradictsNothing) {
  const StretchCheckResult check = Calibrate(Straightened(truth_.pairs));
  ASSERT_EQ(check.result.status, CalibrationStatus::kUnobservable)
      << check.result.message;
  ASSERT_FALSE(check.result.has_estimate);
  const MapperAttempt attempt =
      SummarizeMapperAttempt(0, "sparse", OneSubModel(41), check);
  EXPECT_FALSE(attempt.pairs_tested);
  EXPECT_EQ(attempt.num_pairs, 40);
  EXPECT_EQ(attempt.num_pairs_used, 0);  // no fit
  EXPECT_EQ(attempt.num_contradicting_pairs, 0);
  EXPECT_TRUE(attempt.contradicted_spans.empty());
  EXPECT_TRUE(OdometryAcceptsModel(attempt));
  EXPECT_FALSE(ShouldMatchAgain({attempt}));
}

// One turn only: not enough motion, which a model with more registered
// images might fix, so it is not accepted; but the same pairs again mean
// the drive, not the mapper, lacks the motion.
TEST_F(MapperAttemptsTest, TooLittleMotionRepeatedStopsTheSeeds) {
  MotionPairs pairs = Straightened(truth_.pairs);
  pairs[5] = truth_.pairs[5];
  const StretchCheckResult check = Calibrate(pairs);
  ASSERT_EQ(check.result.status, CalibrationStatus::kNotEnoughMotion)
      << check.result.message;
  const MapperAttempt first =
      SummarizeMapperAttempt(0, "a", OneSubModel(41), check);
  EXPECT_FALSE(first.pairs_tested);
  EXPECT_EQ(first.num_contradicting_pairs, 0);
  EXPECT_FALSE(OdometryAcceptsModel(first));
  EXPECT_FALSE(RepeatsContradictions(first, first));
  EXPECT_TRUE(RepeatsUntestedPairs(first, first));
  pairs.pop_back();  // a model with one image fewer
  const MapperAttempt fewer =
      SummarizeMapperAttempt(1, "b", OneSubModel(40), Calibrate(pairs));
  EXPECT_FALSE(RepeatsUntestedPairs(fewer, first));
  // Tested models never repeat as untested ones.
  const MapperAttempt clean =
      SummarizeMapperAttempt(2, "c", OneSubModel(41), Calibrate(truth_.pairs));
  EXPECT_TRUE(clean.pairs_tested);
  EXPECT_FALSE(RepeatsUntestedPairs(clean, clean));
}

TEST(MapperAttempts, RanksStatusBeforeContradictionsBeforeSize) {
  MapperAttempt success;
  success.produced_model = true;
  success.status = CalibrationStatus::kSuccess;
  success.num_contradicting_pairs = 3;
  success.num_pairs_used = 20;
  MapperAttempt inconsistent = success;
  inconsistent.status = CalibrationStatus::kInconsistentData;
  inconsistent.num_contradicting_pairs = 0;
  EXPECT_TRUE(IsBetterMapperAttempt(success, inconsistent));

  MapperAttempt fewer_contradictions = success;
  fewer_contradictions.num_contradicting_pairs = 1;
  fewer_contradictions.num_pairs_used = 10;
  EXPECT_TRUE(IsBetterMapperAttempt(fewer_contradictions, success));

  MapperAttempt more_pairs = success;
  more_pairs.num_pairs_used = 21;
  EXPECT_TRUE(IsBetterMapperAttempt(more_pairs, success));

  // A straight path is unobservable whatever the model: accepted when clean.
  MapperAttempt straight = success;
  straight.status = CalibrationStatus::kUnobservable;
  straight.num_contradicting_pairs = 0;
  EXPECT_TRUE(OdometryAcceptsModel(straight));
  straight.status = CalibrationStatus::kNotEnoughMotion;
  EXPECT_FALSE(OdometryAcceptsModel(straight));
}

TEST(MapperAttempts, NoModelIsNeverChosen) {
  MapperAttempt none;
  none.produced_model = false;
  EXPECT_EQ(BestMapperAttempt({}), -1);
  EXPECT_EQ(BestMapperAttempt({none, none}), -1);
  EXPECT_FALSE(OdometryAcceptsModel(none));
  MapperAttempt some;
  some.produced_model = true;
  some.status = CalibrationStatus::kInconsistentData;
  EXPECT_EQ(BestMapperAttempt({none, some}), 1);
  EXPECT_TRUE(IsBetterMapperAttempt(some, none));
}

}  // namespace
}  // namespace odomcal
