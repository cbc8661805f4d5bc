// Not a Google Benchmark: coverage of the rotation axes, x and y on car
// drives whose reconstruction scale wanders (CarDriveOptions), without and
// with the scale drift term (solver/scale_drift_covariance.h), over seeds
// 1..N per walk rate. Prints a markdown table (docs/scale_drift_covariance.md).
//   <build>/benchmarks/scale_drift_study 60

#include "odomcal/adapters/association.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace odomcal {
namespace {

struct Tally {
  int runs = 0;
  int success = 0;
  int named = 0;
  int beyond_before[5] = {0, 0, 0, 0, 0};
  int beyond_after[5] = {0, 0, 0, 0, 0};
  double before2[5] = {0, 0, 0, 0, 0};
  double after2[5] = {0, 0, 0, 0, 0};
  double rate = 0.0;  // sum of the estimated rates
};

void Add(uint64_t seed, double walk, Tally* tally) {
  const DriveSimulatorOptions options = CarDriveOptions(seed, walk);
  const SimulatedDrive drive = SimulateDrive(options);
  const AssociationResult association = AssociateCameraWithOdometry(
      {drive.camera}, drive.odometry, AssociationOptions());
  CalibrationOptions calibration;
  calibration.fixed_translation_z_m = options.odom_from_cam.translation.z();
  const CalibrationResult result =
      CalibrateOdomCam(association.pairs, calibration);
  ++tally->runs;
  if (result.status != CalibrationStatus::kSuccess || !result.covariance) {
    return;
  }
  ++tally->success;
  const ScaleDriftTerm& term = result.diagnostics.scale_drift;
  tally->named += term.named;
  tally->rate += term.rate.rate_per_s;
  Eigen::Matrix<double, 5, 1> error;
  error.head<3>() = LogRotation(result.odom_from_cam.rotation *
                                drive.odom_from_cam.rotation.conjugate());
  error.tail<2>() =
      (result.odom_from_cam.translation - drive.odom_from_cam.translation)
          .head<2>();
  for (int k = 0; k < 5; ++k) {
    const double unit = k < 3 ? kRadToDeg : 1.0;
    const double after = std::sqrt((*result.covariance)(k, k));
    const double before = term.applied ? term.stddev_before(k) / unit : after;
    const double z_before = error(k) / before, z_after = error(k) / after;
    tally->before2[k] += z_before * z_before;
    tally->after2[k] += z_after * z_after;
    tally->beyond_before[k] += std::abs(z_before) > 3.0;
    tally->beyond_after[k] += std::abs(z_after) > 3.0;
  }
}

}  // namespace
}  // namespace odomcal

int main(int argc, char** argv) {
  using namespace odomcal;
  const int num_seeds = argc > 1 ? std::atoi(argv[1]) : 60;
  std::printf(
      "| scale walk | answers | named | mean estimated walk | beyond 3 sigma "
      "(rx, ry, rz, x, y), without / with the term | RMS error / sigma of "
      "x, y, without / with |\n| --- | --- | --- | --- | --- | --- |\n");
  for (const double walk : {0.0, 5e-4, 1e-3, 2e-3}) {
    Tally tally;
    for (int seed = 1; seed <= num_seeds; ++seed) {
      Add(static_cast<uint64_t>(seed), walk, &tally);
    }
    const int n = std::max(tally.success, 1);
    std::printf("| %.2g %%/sqrt(s) | %d of %d | %d | %.2g %%/sqrt(s) | ",
                100.0 * walk,
                tally.success,
                tally.runs,
                tally.named,
                100.0 * std::sqrt(tally.rate / n));
    for (int k = 0; k < 5; ++k) {
      std::printf("%s%d / %d",
                  k ? ", " : "",
                  tally.beyond_before[k],
                  tally.beyond_after[k]);
    }
    std::printf(" | %.2f / %.2f, %.2f / %.2f |\n",
                std::sqrt(tally.before2[3] / n),
                std::sqrt(tally.after2[3] / n),
                std::sqrt(tally.before2[4] / n),
                std::sqrt(tally.after2[4] / n));
  }
  return 0;
}
