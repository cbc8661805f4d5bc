#include "odomcal/solver/observability.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace odomcal {
namespace {

using Names = std::vector<std::string>;

Observability Calibrated(int num_segments) {
  Observability observability;
  observability.metric_scales.assign(num_segments, Determination::kEstimated);
  return observability;
}

TEST(Observability, PlanarCalibrationNamesTheHeldZOnly) {
  const Observability observability = Calibrated(1);
  EXPECT_TRUE(observability.ExtrinsicDetermined());
  EXPECT_TRUE(observability.AllDetermined());
  EXPECT_EQ(UnobservableNames(observability), Names{"translation_z"});
  EXPECT_TRUE(UndeterminedNames(observability).empty());
}

TEST(Observability, EstimatedZIsNotNamed) {
  Observability observability = Calibrated(1);
  observability.translation_z = Determination::kEstimated;
  EXPECT_TRUE(UnobservableNames(observability).empty());
}

// The held z comes first, the undetermined quantities follow in the fixed
// order rotation, x, y, z, scales (the order of the JSON since version 1).
TEST(Observability, HeldFirstThenUndeterminedInFixedOrder) {
  Observability observability = Calibrated(1);
  observability.metric_scales[0] = Determination::kUndetermined;
  observability.translation_y = Determination::kUndetermined;
  observability.rotation = Determination::kUndetermined;
  observability.translation_x = Determination::kUndetermined;
  EXPECT_FALSE(observability.ExtrinsicDetermined());
  EXPECT_EQ(UnobservableNames(observability),
            (Names{"translation_z",
                   "rotation",
                   "translation_x",
                   "translation_y",
                   "metric_scale"}));
  EXPECT_EQ(
      UndeterminedNames(observability),
      (Names{"rotation", "translation_x", "translation_y", "metric_scale"}));
}

TEST(Observability, NothingNamesEverythingAsUndetermined) {
  EXPECT_EQ(
      UnobservableNames(Observability::Nothing(0)),
      (Names{"rotation", "translation_x", "translation_y", "translation_z"}));
  Observability in_place = Observability::Nothing(2);
  in_place.rotation = Determination::kEstimated;
  EXPECT_EQ(UnobservableNames(in_place),
            (Names{"translation_x",
                   "translation_y",
                   "translation_z",
                   "metric_scale[0]",
                   "metric_scale[1]"}));
}

TEST(Observability, OneSegmentsScaleOfSeveral) {
  Observability observability = Calibrated(3);
  observability.metric_scales[1] = Determination::kUndetermined;
  EXPECT_TRUE(observability.ExtrinsicDetermined());
  EXPECT_FALSE(observability.AllDetermined());
  EXPECT_TRUE(observability.ScaleDetermined(0));
  EXPECT_FALSE(observability.ScaleDetermined(1));
  EXPECT_FALSE(observability.ScaleDetermined(3));
  EXPECT_EQ(UnobservableNames(observability),
            (Names{"translation_z", "metric_scale[1]"}));
  EXPECT_EQ(ScaleName(0, 1), "metric_scale");
  EXPECT_EQ(ScaleName(2, 3), "metric_scale[2]");
}

}  // namespace
}  // namespace odomcal
