// The warning that names COLMAP's scale drift in a sub-model (the stretch
// check's ScaleDrift, solver/stretch_consistency.h):
//   "sub-model 0: COLMAP's scale drifts by +10.1 % (3 sigma 0.4 %) from <t0>
//   to <t1> s (seen in the step lengths against the odometry): calibrated
//   and exported as 4 stretches with scales of their own: <t0> .. <t> s
//   0.3712 m/unit, ..."
// Without a trend (fewer than 5 pairs fit it) it says that the scale
// changes, not by how much; when the extrinsic is not determined it says
// that nothing is exported; an undetermined scale is not printed as a
// number.
#pragma once

#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/stretch_consistency.h"

#include <string>

namespace odomcal {

// A relative change as a signed percentage: 0.101 -> "+10.1 %".
std::string SignedPercent(double fraction);

std::string ScaleDriftWarning(const std::string& sub_model,
                              const ScaleDrift& drift,
                              const CalibrationResult& result);

}  // namespace odomcal
