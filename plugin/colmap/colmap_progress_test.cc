#include "odomcal/plugin/colmap/colmap_progress.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace odomcal {
namespace {

// Fixture lines as COLMAP 3.8 (Debian bookworm) writes them to the stage
// logs of `odomcal run` (GLOG_logtostderr=1).

TEST(ColmapOutputProgress, FeatureExtraction) {
  ColmapOutputProgress progress(40);
  EXPECT_EQ(progress.Fraction(), -1.0);
  EXPECT_EQ(progress.Describe(0.4), "started, 0 s");
  EXPECT_FALSE(progress.Feed("Feature extraction"));
  EXPECT_FALSE(
      progress.Feed("=============================================="
                    "================================"));
  EXPECT_TRUE(progress.Feed("Processed file [1/40]"));
  EXPECT_FALSE(progress.Feed("  Name:            000001.png"));
  EXPECT_FALSE(progress.Feed("  Features:        1297"));
  EXPECT_TRUE(progress.Feed("Processed file [11/40]"));
  EXPECT_DOUBLE_EQ(progress.Fraction(), 10.0 / 40.0);
  // 10 of 40 in 5 s: 15 s for the other 30.
  EXPECT_EQ(progress.Describe(5.0),
            "extracted features of image 11/40, 5 s, about 15 s left");
}

TEST(ColmapOutputProgress, SequentialAndSpatialMatching) {
  ColmapOutputProgress progress(300);
  EXPECT_FALSE(progress.Feed("Indexing images... done in 0.000s"));
  // The matchers print the image first and its time once matched.
  EXPECT_TRUE(progress.Feed("Matching image [1/300] in 0.532s"));
  EXPECT_TRUE(progress.Feed("Matching image [121/300]"));
  EXPECT_DOUBLE_EQ(progress.Fraction(), 120.0 / 300.0);
  EXPECT_EQ(progress.Describe(45.0),
            "matching image 121/300, 45 s, about 68 s left");
  // Before a tenth is done no time left is guessed; minutes past 2.
  EXPECT_TRUE(progress.Feed("Matching image [20/300] in 0.512s"));
  EXPECT_EQ(progress.Describe(130.0), "matching image 20/300, 2.2 min");
}

TEST(ColmapOutputProgress, PairMatchingBlocks) {
  ColmapOutputProgress progress;
  EXPECT_TRUE(progress.Feed("Matching block [3/5] in 4.210s"));
  EXPECT_DOUBLE_EQ(progress.Fraction(), 2.0 / 5.0);
  EXPECT_EQ(progress.Describe(8.0), "matching block 3/5, 8 s, about 12 s left");
  // Exhaustive matching: blocks of a square.
  EXPECT_TRUE(progress.Feed("Matching block [2/3, 1/3]"));
  EXPECT_DOUBLE_EQ(progress.Fraction(), 3.0 / 9.0);
}

TEST(ColmapOutputProgress, MapperCountsTheImagesOfEveryModel) {
  ColmapOutputProgress progress(300);
  EXPECT_TRUE(progress.Feed("Finding good initial image pair"));
  EXPECT_EQ(progress.Describe(2.0), "finding an initial image pair, 2 s");
  EXPECT_FALSE(progress.Feed("Initializing with image pair #12 and #18"));
  EXPECT_TRUE(progress.Feed("Registering image #19 (3)"));
  EXPECT_TRUE(progress.Feed("Registering image #104 (85)"));
  EXPECT_DOUBLE_EQ(progress.Fraction(), 85.0 / 300.0);
  EXPECT_EQ(progress.Describe(33.0),
            "registered 85 of 300 images, 33 s, "
            "about 83 s left");
  // A second model: its count starts again; the images add up.
  EXPECT_TRUE(progress.Feed("Finding good initial image pair"));
  EXPECT_EQ(progress.Describe(40.0),
            "finding an initial image pair (85 images registered), 40 s, "
            "about 101 s left");
  EXPECT_TRUE(progress.Feed("Registering image #201 (3)"));
  EXPECT_EQ(progress.Describe(41.0).substr(0, 27),
            "registered 88 of 300 images");
  // Lines with glog's prefix are read too.
  EXPECT_TRUE(
      progress.Feed("I1124 02:40:11.123456 12345 incremental_mapper.cc:40] "
                    "Registering image #202 (4)"));
  EXPECT_DOUBLE_EQ(progress.Fraction(), 89.0 / 300.0);
}

}  // namespace
}  // namespace odomcal
