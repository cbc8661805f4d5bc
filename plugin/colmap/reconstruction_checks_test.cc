#include "odomcal/plugin/colmap/joint_adjustment_run.h"
#include "odomcal/plugin/colmap/reconstruction_pipeline.h"
#include "odomcal/plugin/colmap/reconstruction_stages.h"

#include <gtest/gtest.h>

namespace odomcal::reconstruction {
namespace {

// The calibrations that check a model between the stages (every mapper
// attempt, chunk combination and fold posed) read the two-step result: a
// joint adjustment there would adjust the whole drive once per check.
TEST(CheckCalibrationInputs, ChecksRunTheTwoStepCalibrationOnly) {
  ReconstructionOptions run;
  run.project.odometry_path = "odometry.csv";
  run.project.calibration.num_threads = 1;
  run.project.joint_adjustment.use = JointAdjustmentUse::kOn;
  run.project.joint_adjustment.jackknife.num_blocks = 5;

  const ColmapCalibrationInputs inputs =
      CheckCalibrationInputs(run, "ws/combination_1", "ws/database.db");
  EXPECT_EQ(inputs.joint_adjustment.use, JointAdjustmentUse::kOff);
  EXPECT_EQ(inputs.model_path, "ws/combination_1");
  EXPECT_EQ(inputs.database_path, "ws/database.db");
  // Everything else is the run's.
  EXPECT_EQ(inputs.odometry_path, "odometry.csv");
  EXPECT_EQ(inputs.calibration.num_threads, 1);
  EXPECT_EQ(inputs.joint_adjustment.jackknife.num_blocks, 5);
  // The final calibration still adjusts.
  EXPECT_EQ(run.project.joint_adjustment.use, JointAdjustmentUse::kOn);
}

}  // namespace
}  // namespace odomcal::reconstruction
