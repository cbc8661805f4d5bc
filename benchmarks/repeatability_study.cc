// Not a Google Benchmark: the false-alarm and detection rates of the
// repeatability check (solver/repeatability.h, docs/repeatability.md)
// on simulated 2-minute drives, associated as the command line does.
//   <build>/benchmarks/repeatability_study [num_clean=100] [num_knocked=20]
// Clean drives: how many raise the alarm (target <= 1 %). Drives whose mount
// turns by 1 degree (about a random axis) halfway: how many are named (target
// >= 95 %) with the change within 10 % of the drive's length of the knock.
#include "odomcal/adapters/association.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/solver/calibrate.h"
#include "odomcal/solver/repeatability.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

namespace {

using namespace odomcal;

struct Outcome {
  bool calibrated = false;
  bool ran = false;
  bool alarm = false;
  double change_s = -1.0;  // after the first pair, when named
  double halves_chi_square_per_dof = 0.0;
  double quarters_chi_square_per_dof = 0.0;
};

Outcome RunDrive(uint64_t seed, double knock_deg, double knock_time_s) {
  DriveSimulatorOptions options;
  options.seed = seed;
  options.duration_s = 120.0;
  options.odometry_rate_hz = 50.0;
  options.camera_rate_hz = 5.0;
  options.camera_rotation_noise_deg = 0.05;
  options.camera_position_noise = 0.003;
  options.wheel_travel_noise_rel = 0.01;
  options.mount_knock_deg = knock_deg;
  options.mount_knock_time_s = knock_time_s;
  std::mt19937_64 rng(seed * 7919 + 17);
  std::normal_distribution<double> gauss;
  options.mount_knock_axis =
      Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
  const SimulatedDrive drive = SimulateDrive(options);
  const AssociationResult association =
      AssociateCameraWithOdometry({drive.camera}, drive.odometry, {});
  CalibrationOptions calibration;
  calibration.fixed_translation_z_m = drive.odom_from_cam.translation.z();
  const CalibrationResult result =
      CalibrateOdomCam(association.pairs, calibration);
  Outcome outcome;
  outcome.calibrated = result.IsSuccess();
  const Repeatability check = CheckRepeatability(
      association.pairs, result, calibration, RepeatabilityOptions());
  outcome.ran = check.ran;
  outcome.alarm = check.ran && !check.consistent;
  for (const RepeatabilityTest& test : check.tests) {
    if (!test.ran) continue;
    (test.name == "halves" ? outcome.halves_chi_square_per_dof
                           : outcome.quarters_chi_square_per_dof) =
        test.chi_square / test.dof;
  }
  if (check.change_stamp_ns) {
    outcome.change_s = 1e-9 * static_cast<double>(*check.change_stamp_ns -
                                                  check.first_stamp_ns);
  }
  return outcome;
}

}  // namespace

int main(int argc, char** argv) {
  const int num_clean = argc > 1 ? std::atoi(argv[1]) : 100;
  const int num_knocked = argc > 2 ? std::atoi(argv[2]) : 20;
  int clean_ran = 0, false_alarms = 0;
  std::vector<double> halves, quarters;
  for (int k = 0; k < num_clean; ++k) {
    const Outcome outcome = RunDrive(1000 + k, 0.0, 0.0);
    clean_ran += outcome.ran;
    false_alarms += outcome.alarm;
    if (outcome.ran) {
      halves.push_back(outcome.halves_chi_square_per_dof);
      quarters.push_back(outcome.quarters_chi_square_per_dof);
    }
  }
  int knocked_ran = 0, detected = 0, located = 0;
  for (int k = 0; k < num_knocked; ++k) {
    const Outcome outcome = RunDrive(5000 + k, 1.0, 60.0);
    knocked_ran += outcome.ran;
    detected += outcome.alarm;
    located += outcome.alarm && outcome.change_s >= 0.0 &&
               std::abs(outcome.change_s - 60.0) <= 12.0;
  }
  std::printf("| drives | checked | alarms | named within 10 %% |\n");
  std::printf("| --- | --- | --- | --- |\n");
  std::printf("| clean | %d of %d | %d (%.1f %%) | |\n",
              clean_ran,
              num_clean,
              false_alarms,
              100.0 * false_alarms / std::max(1, clean_ran));
  std::printf("| 1 deg knock at 60 s | %d of %d | %d (%.1f %%) | %d |\n",
              knocked_ran,
              num_knocked,
              detected,
              100.0 * detected / std::max(1, knocked_ran),
              located);
  // A chi-square per dof averages 1 when the blocks' covariances are honest.
  const auto mean = [](const std::vector<double>& values) {
    double sum = 0.0;
    for (const double value : values) sum += value;
    return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
  };
  std::printf(
      "\nclean drives: mean chi-square per dof %.2f (halves), %.2f "
      "(quarters)\n",
      mean(halves),
      mean(quarters));
  return 0;
}
