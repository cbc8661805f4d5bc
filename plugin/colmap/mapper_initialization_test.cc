#include "odomcal/plugin/colmap/mapper_initialization.h"

#include "odomcal/adapters/colmap_two_view_geometries.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

Eigen::Matrix3d Skew(const Eigen::Vector3d& t) {
  Eigen::Matrix3d s;
  s << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  return s;
}

// E of camera 2 = R * camera 1 + t, for a unit baseline t.
Eigen::Matrix3d Essential(const Eigen::Vector3d& t, double yaw_rad) {
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return Skew(t.normalized()) * rotation;
}

TEST(ForwardMotionOfEssential, IsTheBaselinesAxialPartInTheSecondCamera) {
  EXPECT_NEAR(ForwardMotionOfEssential(Essential({0, 0, 1}, 0.0)), 1.0, 1e-12);
  EXPECT_NEAR(ForwardMotionOfEssential(Essential({1, 0, 0}, 0.3)), 0.0, 1e-12);
  const Eigen::Vector3d t = Eigen::Vector3d(0.6, 0.0, -0.8);
  EXPECT_NEAR(ForwardMotionOfEssential(3.0 * Essential(t, -0.2)), 0.8, 1e-12);
}

InitialPairImage Image(uint32_t id, double x, double yaw_rad = 0.0) {
  InitialPairImage image;
  image.image_id = id;
  image.name = "img" + std::to_string(id) + ".png";
  image.origin_from_odom = Rigid3d(YawRotation(yaw_rad), {x, 0.0, 0.0});
  return image;
}

ColmapVerifiedPair Pair(uint32_t a,
                        uint32_t b,
                        int inliers,
                        std::optional<Eigen::Matrix3d> essential = {}) {
  ColmapVerifiedPair pair;
  pair.image_id1 = a;
  pair.image_id2 = b;
  pair.num_inliers = inliers;
  pair.config = static_cast<int>(TwoViewConfig::kCalibrated);
  pair.essential = essential;
  return pair;
}

TEST(RankInitialPairs, PrefersInliersTimesTheBaselineAcrossTheView) {
  const std::vector<InitialPairImage> images = {
      Image(1, 0.0), Image(2, 1.0), Image(3, 2.0), Image(4, 3.0, 0.5)};
  const std::vector<ColmapVerifiedPair> verified = {
      // Forward motion: refused by COLMAP's default test.
      Pair(1, 3, 900, Essential({0, 0, 1}, 0.0)),
      // Too few inliers.
      Pair(1, 4, 60, Essential({1, 0, 0}, 0.0)),
      // 200 inliers, 1 m, half across the view.
      Pair(1, 2, 200, Essential({0.5, 0, std::sqrt(0.75)}, 0.0)),
      // 150 inliers, 1 m, fully across: the best.
      Pair(2, 3, 150, Essential({1, 0, 0}, 0.0)),
      // An id outside the images given.
      Pair(3, 9, 800, Essential({1, 0, 0}, 0.0)),
  };
  const std::vector<InitialPairCandidate> ranked =
      RankInitialPairs(images, verified, InitialPairTests());
  ASSERT_EQ(ranked.size(), 2u);
  EXPECT_EQ(ranked[0].image_id1, 2u);
  EXPECT_EQ(ranked[0].image_id2, 3u);
  EXPECT_NEAR(ranked[0].score, 150.0, 1e-9);
  EXPECT_EQ(ranked[1].image_id1, 1u);
  EXPECT_NEAR(ranked[1].score, 100.0, 1e-9);
  EXPECT_NEAR(*ranked[1].forward_motion, std::sqrt(0.75), 1e-12);
  EXPECT_EQ(ranked[1].name2, "img2.png");

  // Forward motion accepted: the long forward pair comes first... unless it
  // is exactly forward, which COLMAP refuses even then.
  InitialPairTests relaxed;
  relaxed.max_forward_motion = 1.0;
  const std::vector<InitialPairCandidate> with_forward =
      RankInitialPairs(images, verified, relaxed);
  ASSERT_EQ(with_forward.size(), 2u);
  std::vector<ColmapVerifiedPair> nearly = verified;
  nearly[0].essential = Essential({0.1, 0, 0.995}, 0.0);
  const std::vector<InitialPairCandidate> nearly_forward =
      RankInitialPairs(images, nearly, relaxed);
  ASSERT_EQ(nearly_forward.size(), 3u);
  EXPECT_EQ(nearly_forward[0].image_id2, 3u);
  EXPECT_EQ(nearly_forward[0].image_id1, 1u);
}

TEST(RankInitialPairs, NeedsOdometryAtBothImagesAndABaseline) {
  std::vector<InitialPairImage> images = {
      Image(1, 0.0), Image(2, 0.0, 0.4), Image(3, 1.0)};
  images[2].origin_from_odom.reset();
  const std::vector<ColmapVerifiedPair> verified = {Pair(1, 2, 500),
                                                    Pair(1, 3, 500)};
  EXPECT_TRUE(RankInitialPairs(images, verified, InitialPairTests()).empty());
  InitialPairTests bad;
  bad.min_inliers = 0;
  EXPECT_THROW(RankInitialPairs(images, verified, bad), std::invalid_argument);
}

TEST(InitializationLadder, TriesOdometryPairsThenRelaxedTestsThenAWiderWindow) {
  std::vector<InitialPairCandidate> candidates(4);
  for (size_t i = 0; i < candidates.size(); ++i) {
    candidates[i].image_id1 = static_cast<uint32_t>(i + 1);
    candidates[i].image_id2 = static_cast<uint32_t>(i + 10);
  }
  std::vector<InitialPairCandidate> relaxed = {candidates[1]};
  relaxed.push_back(candidates[0]);
  relaxed[1].image_id2 = 99;  // a pair only the relaxed test lets through
  using Kind = MapperInitialization::Kind;
  const std::vector<MapperInitialization> ladder =
      InitializationLadder(candidates, relaxed, true);
  ASSERT_EQ(ladder.size(), 6u);
  EXPECT_EQ(ladder[0].kind, Kind::kOdometryPair);
  EXPECT_EQ(ladder[2].pair->image_id1, 3u);
  EXPECT_EQ(ladder[3].kind, Kind::kRelaxedSearch);
  EXPECT_EQ(ladder[4].kind, Kind::kRelaxedOdometryPair);
  EXPECT_EQ(ladder[4].pair->image_id2, 99u);
  EXPECT_EQ(ladder[5].kind, Kind::kNeighbourWindow);
  EXPECT_EQ(
      ladder[0].MapperArguments(),
      (std::vector<std::string>{
          "--Mapper.init_image_id1", "1", "--Mapper.init_image_id2", "10"}));
  const std::vector<std::string> relaxed_arguments =
      ladder[4].MapperArguments();
  ASSERT_EQ(relaxed_arguments.size(), 10u);
  EXPECT_EQ(relaxed_arguments[4], "--Mapper.init_max_forward_motion");
  EXPECT_EQ(relaxed_arguments[5], "1");
  EXPECT_TRUE(MapperInitialization().MapperArguments().empty());

  // Without candidates nor chunks: only the relaxed search.
  const std::vector<MapperInitialization> bare =
      InitializationLadder({}, {}, false);
  ASSERT_EQ(bare.size(), 1u);
  EXPECT_EQ(ToString(bare[0].kind), "relaxed_search");
}

TEST(MapperFailureCause, NamesWhatCOLMAPSaid) {
  const fs::path log = fs::temp_directory_path() / "odomcal_mapper_cause.log";
  auto cause_of = [&](const std::string& text) {
    std::ofstream(log) << text;
    return MapperFailureCause(log.string());
  };
  EXPECT_NE(cause_of("Loading database\n  => No good initial image pair "
                     "found.\n\nElapsed time: 0.01 [minutes]\n")
                .find("No good initial image pair found"),
            std::string::npos);
  EXPECT_NE(cause_of("  => Initialization failed - possible solutions:\n")
                .find("Initialization failed"),
            std::string::npos);
  EXPECT_EQ(cause_of("F0101 x.cc:1] Check failed: a == b\n"),
            "COLMAP failed a CHECK: F0101 x.cc:1] Check failed: a == b");
  EXPECT_EQ(cause_of("one\nlast line\n\n"),
            "no model; the log ends \"last line\"");
  fs::remove(log);
  EXPECT_EQ(MapperFailureCause(log.string()), "");
}

}  // namespace
}  // namespace odomcal
