#include "odomcal/solver/calibration_result.h"

namespace odomcal {

std::string ToString(CalibrationStatus status) {
  switch (status) {
    case CalibrationStatus::kNotRun:
      return "not_run";
    case CalibrationStatus::kSuccess:
      return "success";
    case CalibrationStatus::kNotEnoughMotion:
      return "not_enough_motion";
    case CalibrationStatus::kUnobservable:
      return "unobservable";
    case CalibrationStatus::kInconsistentData:
      return "inconsistent_data";
    case CalibrationStatus::kRefinementFailed:
      return "refinement_failed";
  }
  return "unknown";
}

}  // namespace odomcal
