#include "odomcal/plugin/colmap/image_coverage.h"

#include "odomcal/plugin/colmap/colmap_calibration.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

namespace odomcal {
namespace {

// `n` images 0.2 s apart (5 Hz), named "000".."n-1".
std::vector<TimedImage> Drive(int n) {
  std::vector<TimedImage> images;
  for (int i = 0; i < n; ++i) {
    char name[16];
    std::snprintf(name, sizeof(name), "%03d", i);
    images.push_back({name, 1'000'000'000 + i * int64_t{200'000'000}});
  }
  return images;
}

std::set<std::string> Names(const std::vector<TimedImage>& images,
                            int first,
                            int end) {
  std::set<std::string> names;
  for (int i = first; i < end; ++i) names.insert(images[i].name);
  return names;
}

// The measured case of issue 18: 85 of 300 images registered, the rest not.
TEST(ImageCoverage, EightyFiveOfThreeHundredIsAGapAndAWarning) {
  const std::vector<TimedImage> drive = Drive(300);
  const std::set<std::string> registered = Names(drive, 0, 85);
  const ImageCoverage coverage =
      SummarizeImageCoverage(drive, registered, registered);
  EXPECT_EQ(coverage.num_selected_images, 300);
  EXPECT_EQ(coverage.num_registered_images, 85);
  EXPECT_EQ(coverage.num_in_calibration, 85);
  EXPECT_DOUBLE_EQ(coverage.Fraction(), 85.0 / 300.0);
  // 84 intervals of 299 covered.
  EXPECT_DOUBLE_EQ(coverage.duration_fraction, 84.0 / 299.0);
  ASSERT_EQ(coverage.stretches.size(), 2u);
  EXPECT_TRUE(coverage.stretches[0].in_calibration);
  EXPECT_EQ(coverage.stretches[0].last_image, 84);
  EXPECT_DOUBLE_EQ(coverage.stretches[0].Fraction(), 1.0);
  EXPECT_FALSE(coverage.stretches[1].in_calibration);
  EXPECT_EQ(coverage.stretches[1].first_image, 85);
  EXPECT_EQ(coverage.stretches[1].num_images, 215);
  EXPECT_EQ(coverage.stretches[1].first_stamp_ns, drive[85].stamp_ns);
  EXPECT_EQ(coverage.stretches[1].last_stamp_ns, drive[299].stamp_ns);
  EXPECT_EQ(CoverageClause(coverage),
            "85 of 300 selected images (28 %) in the calibration");
  EXPECT_EQ(CoverageWarning(coverage).value_or(""),
            "only 85 of 300 selected images (28 %) in the calibration (below "
            "90 %), covering 28 % of the drive's duration: the calibration "
            "and the metric model describe part of the drive; not in it: "
            "images 86-300 (17.0-59.8 s, 0 registered)");
}

TEST(ImageCoverage, ShortMissesCountInsideTheirStretch) {
  const std::vector<TimedImage> drive = Drive(100);
  std::set<std::string> in = Names(drive, 0, 100);
  // Two single misses and a pair: no gap; a run of 3 is one.
  for (const int i : {0, 10, 40, 41, 70, 71, 72}) in.erase(drive[i].name);
  const ImageCoverage coverage = SummarizeImageCoverage(drive, in, in);
  ASSERT_EQ(coverage.stretches.size(), 3u);
  EXPECT_TRUE(coverage.stretches[0].in_calibration);
  EXPECT_EQ(coverage.stretches[0].first_image, 0);
  EXPECT_EQ(coverage.stretches[0].last_image, 69);
  EXPECT_EQ(coverage.stretches[0].num_in_calibration, 66);
  EXPECT_FALSE(coverage.stretches[1].in_calibration);
  EXPECT_EQ(coverage.stretches[1].num_images, 3);
  EXPECT_TRUE(coverage.stretches[2].in_calibration);
  EXPECT_EQ(coverage.stretches[2].num_images, 27);
  EXPECT_EQ(coverage.num_in_calibration, 93);
  // 93 % is enough: no warning.
  EXPECT_FALSE(CoverageWarning(coverage).has_value());
  EXPECT_EQ(CoverageClause(coverage),
            "93 of 100 selected images (93 %) in the calibration");
  // Covered time: images 1-69 and 73-99 of 0-99.
  EXPECT_DOUBLE_EQ(coverage.duration_fraction, (68.0 + 26.0) / 99.0);
}

TEST(ImageCoverage, WarnsJustBelowNinetyPercent) {
  const std::vector<TimedImage> drive = Drive(100);
  const std::set<std::string> registered = Names(drive, 0, 100);
  const ImageCoverage at =
      SummarizeImageCoverage(drive, registered, Names(drive, 0, 90));
  EXPECT_FALSE(CoverageWarning(at).has_value());
  const ImageCoverage below =
      SummarizeImageCoverage(drive, registered, Names(drive, 0, 89));
  ASSERT_TRUE(CoverageWarning(below).has_value());
  // Registered but outside any motion pair used: the gap says so.
  EXPECT_NE(CoverageWarning(below)->find("images 90-100 (17.8-19.8 s, 11 "
                                         "registered)"),
            std::string::npos)
      << *CoverageWarning(below);
}

TEST(ImageCoverage, NothingInTheCalibrationIsOneGap) {
  const std::vector<TimedImage> drive = Drive(2);
  const ImageCoverage coverage = SummarizeImageCoverage(drive, {}, {});
  ASSERT_EQ(coverage.stretches.size(), 1u);
  EXPECT_FALSE(coverage.stretches[0].in_calibration);
  EXPECT_EQ(coverage.duration_fraction, 0.0);
  EXPECT_TRUE(CoverageWarning(coverage).has_value());
}

// Images count as in the calibration only inside a pair used of their own
// sub-model (with the camera time offset applied), not merely registered.
TEST(ImageCoverage, ImagesInCalibrationFollowThePairsUsed) {
  ColmapCalibrationRun run;
  for (int s = 0; s < 2; ++s) {
    ColmapSegment segment;
    for (int k = 0; k < 4; ++k) {
      StampedPose pose;
      pose.stamp_ns = 100 * (4 * s + k);
      segment.trajectory.poses.push_back(pose);
      segment.image_names.push_back(std::to_string(4 * s + k));
    }
    run.segments.push_back(segment);
  }
  // Output segment 0 comes from input segment 1; its pair spans odometry
  // time 510..610, image times 500..600 with an offset of 10 ns.
  run.check.input_segment_of_output_segment = {1};
  MotionPair pair;
  pair.segment = 0;
  pair.stamp_i_ns = 510;
  pair.stamp_j_ns = 610;
  run.check.pairs.push_back(pair);
  EXPECT_EQ(ImagesInCalibration(run, 10), (std::set<std::string>{"5", "6"}));
  EXPECT_EQ(ImagesInCalibration(run, 0), (std::set<std::string>{"6"}));
  EXPECT_EQ(RegisteredImages(run).size(), 8u);
}

}  // namespace
}  // namespace odomcal
