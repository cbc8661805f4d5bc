#include "odomcal/plugin/colmap/mapper_stretches.h"

#include "odomcal/solver/angles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

namespace odomcal {
namespace {

using Pairs = std::vector<std::pair<int, int>>;

Rigid3d Planar(double x, double y, double yaw_deg) {
  return Rigid3d(YawRotation(yaw_deg * kDegToRad), Eigen::Vector3d(x, y, 0));
}

// `n` poses 8 cm apart straight ahead (issue 18's spacing).
std::vector<Rigid3d> Straight(int n) {
  std::vector<Rigid3d> poses;
  for (int i = 0; i < n; ++i) poses.push_back(Planar(0.08 * i, 0, 0));
  return poses;
}

bool Has(const Pairs& pairs, int i, int j) {
  for (const auto& pair : pairs) {
    if (pair == std::make_pair(i, j)) return true;
  }
  return false;
}

// Along a straight drive of 8 cm steps an image is paired with its 6
// nearest images on each side and with the farthest within 100 cm: 12
// images away (within 12.5, 25 and 50 cm: near ones again).
TEST(OdometryCandidatePairs, PairsAtGeometricBaselinesOnBothSides) {
  const int n = 40;
  const Pairs pairs = OdometryCandidatePairs(Straight(n));
  std::vector<int> partners;
  for (const auto& [i, j] : pairs) {
    if (i == 20) partners.push_back(j);
    if (j == 20) partners.push_back(i);
  }
  std::sort(partners.begin(), partners.end());
  EXPECT_EQ(partners,
            (std::vector<int>{
                8, 14, 15, 16, 17, 18, 19, 21, 22, 23, 24, 25, 26, 32}));
  // Near the end the levels take the last images there are.
  EXPECT_TRUE(Has(pairs, 35, 39));
  // 7 pairs per image, not the 12 within 1 m.
  EXPECT_LE(pairs.size(), 7u * n);
  EXPECT_GE(pairs.size(), 6u * n);
}

// Turning in place: close in place but looking elsewhere is no pair,
// except for the nearest neighbours in time.
TEST(OdometryCandidatePairs, ViewingDirectionsTooFarApartAreNotPaired) {
  std::vector<Rigid3d> poses;
  for (int i = 0; i < 12; ++i) poses.push_back(Planar(0, 0, 20.0 * i));
  const Pairs pairs = OdometryCandidatePairs(poses);
  EXPECT_TRUE(Has(pairs, 0, 1));  // 20 deg
  EXPECT_TRUE(Has(pairs, 0, 6));  // 120 deg, but a nearest neighbour
  EXPECT_FALSE(Has(pairs, 0, 7));
  EXPECT_EQ(pairs.size(), 6u * 6u + 5u + 4u + 3u + 2u + 1u);
}

// A 4 m square driven once and back to the start: the last images are
// paired with the first ones (a loop), not with the far corners.
TEST(OdometryCandidatePairs, ALoopPairsTheReturnWithTheStart) {
  std::vector<Rigid3d> poses;
  for (int side = 0; side < 4; ++side) {
    for (int k = 0; k < 20; ++k) {
      const double s = 0.2 * k;
      const double x[4] = {s, 4.0, 4.0 - s, 0.0};
      const double y[4] = {0.0, s, 4.0, 4.0 - s};
      poses.push_back(Planar(x[side], y[side], 90.0 * side));
    }
  }
  poses.push_back(Planar(0.0, 0.0, 360.0));  // back at the start
  const int last = static_cast<int>(poses.size()) - 1;
  const Pairs pairs = OdometryCandidatePairs(poses);
  EXPECT_TRUE(Has(pairs, 0, last));
  EXPECT_TRUE(Has(pairs, 1, last));   // 0.2 m
  EXPECT_FALSE(Has(pairs, 3, last));  // 0.6 m
  EXPECT_FALSE(Has(pairs, 20, 60));   // the opposite corners
  // Without the loop test only neighbours along the path.
  CandidatePairOptions no_loops;
  no_loops.loop_min_path_m = 1e9;
  EXPECT_FALSE(Has(OdometryCandidatePairs(poses, no_loops), 0, last));
}

// The square driven twice (0.2 m steps): the start is paired with its 6
// neighbours (the farthest within 1 m among them), and once with each return to
// it, the closest image of that visit (80, 160), not all images within 0.5 m.
TEST(OdometryCandidatePairs, OneLoopPairPerVisit) {
  std::vector<Rigid3d> poses;
  for (int lap = 0; lap < 2; ++lap) {
    for (int side = 0; side < 4; ++side) {
      for (int k = 0; k < 20; ++k) {
        const double s = 0.2 * k;
        const double x[4] = {s, 4.0, 4.0 - s, 0.0};
        const double y[4] = {0.0, s, 4.0, 4.0 - s};
        poses.push_back(Planar(x[side], y[side], 360.0 * lap + 90.0 * side));
      }
    }
  }
  poses.push_back(Planar(0.0, 0.0, 720.0));
  const Pairs pairs = OdometryCandidatePairs(poses);
  std::vector<int> partners;
  for (const auto& [i, j] : pairs) {
    if (i == 0) partners.push_back(j);
  }
  EXPECT_EQ(partners, (std::vector<int>{1, 2, 3, 4, 5, 6, 80, 160}));
}

TEST(OdometryCandidatePairs, BadOptionsNameTheField) {
  CandidatePairOptions options;
  options.max_distance_m = 0.0;
  try {
    OdometryCandidatePairs(Straight(3), options);
    FAIL();
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(),
                 "max_distance_m must be finite and > 0, got 0.000000");
  }
}

// Straight driving, then a left turn of 4 deg per image: the initial pair
// is the longest baseline with a turn of at least 8 deg.
TEST(ChooseInitialPair, PrefersATurnThenTheLongestBaseline) {
  std::vector<Rigid3d> poses = Straight(20);
  double yaw = 0.0;
  Eigen::Vector3d at = poses.back().translation;
  for (int i = 0; i < 10; ++i) {
    yaw += 4.0;
    at += 0.08 * Eigen::Vector3d(
                     std::cos(yaw * kDegToRad), std::sin(yaw * kDegToRad), 0.0);
    poses.push_back(Planar(at.x(), at.y(), yaw));
  }
  const Pairs candidates = OdometryCandidatePairs(poses);
  const auto pair = ChooseInitialPair(poses, candidates);
  ASSERT_TRUE(pair.has_value());
  // A pair ending in the turn: j - 19 turns of 4 deg, at least 8 deg.
  EXPECT_GE(pair->second, 21);
  const double baseline =
      (poses[pair->first].translation - poses[pair->second].translation).norm();
  EXPECT_GT(baseline, 0.9);
  EXPECT_LE(baseline, 1.0);
  // Straight only: the longest baseline (12 images, 0.96 m), mid-stretch.
  const std::vector<Rigid3d> straight = Straight(31);
  const auto middle =
      ChooseInitialPair(straight, OdometryCandidatePairs(straight));
  ASSERT_TRUE(middle.has_value());
  EXPECT_EQ(*middle, std::make_pair(9, 21));
  // Too short a stretch for the minimum baseline: none.
  const std::vector<Rigid3d> short_one = Straight(2);
  EXPECT_FALSE(ChooseInitialPair(short_one, OdometryCandidatePairs(short_one)));
}

TEST(ViewAngleLimitDeg, HalfTheFieldOfViewAtMostTheMaximum) {
  EXPECT_DOUBLE_EQ(ViewAngleLimitDeg(40.0, 30.0), 20.0);
  EXPECT_DOUBLE_EQ(ViewAngleLimitDeg(63.0, 30.0), 30.0);
  EXPECT_DOUBLE_EQ(ViewAngleLimitDeg(0.0, 30.0), 30.0);  // unknown
}

}  // namespace
}  // namespace odomcal
