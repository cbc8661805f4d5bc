// A downstream project using the installed package: find_package(odomcal).
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/solver/calibrate.h"

int main() {
  // No pairs: a defined refusal, not a crash.
  const odomcal::CalibrationResult result = odomcal::CalibrateOdomCam({}, {});
  return result.status == odomcal::CalibrationStatus::kNotEnoughMotion ? 0 : 1;
}
