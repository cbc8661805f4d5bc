// Modelling assumptions (docs/robustness.md, "Modelling assumptions"): a
// drive whose true motion leaves the plane of planar wheel odometry is named
// and its covariance inflated; a flat drive is not.

#include "odomcal/tests/odomcal_process.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// `odomcal demo --simulated` over rolling ground of +-tilt_deg, 60 s.
nlohmann::json RunTiltedDemo(double tilt_deg, CommandResult* run) {
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("odomcal_tilt_" + std::to_string(tilt_deg));
  fs::remove_all(dir);
  *run = RunOdomcal({"demo",
                     "--simulated",
                     "--seed",
                     "2",
                     "--duration_s",
                     "60",
                     "--ground_tilt_deg",
                     std::to_string(tilt_deg),
                     "--workspace_path",
                     dir.string()});
  std::ifstream file(dir / "calibration.json");
  nlohmann::json result = nlohmann::json::parse(file, nullptr, false);
  fs::remove_all(dir);
  return result;
}

TEST(ModellingAssumptions, TiltedGroundIsNamedAndItsCovarianceInflated) {
  CommandResult run;
  const nlohmann::json result = RunTiltedDemo(3.0, &run);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("warning: the motion is not planar: per motion pair "
                         "the camera tilts "),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("Planar odometry cannot see slopes or ramps"),
            std::string::npos);
  ASSERT_TRUE(result.is_object());
  const nlohmann::json& planarity = result["diagnostics"]["planarity"];
  EXPECT_TRUE(planarity["checked"].get<bool>());
  EXPECT_FALSE(planarity["consistent"].get<bool>());
  EXPECT_GT(planarity["covariance_inflation"].get<double>(), 4.0);
  EXPECT_GT(planarity["tilt_rms_deg"].get<double>(), 0.05);
}

TEST(ModellingAssumptions, FlatGroundIsNotNamed) {
  CommandResult run;
  const nlohmann::json result = RunTiltedDemo(0.0, &run);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out.find("not planar"), std::string::npos) << run.out;
  ASSERT_TRUE(result.is_object());
  const nlohmann::json& planarity = result["diagnostics"]["planarity"];
  EXPECT_TRUE(planarity["consistent"].get<bool>());
  EXPECT_EQ(planarity["covariance_inflation"].get<double>(), 1.0);
}

}  // namespace
}  // namespace odomcal
