// The floor plane under a COLMAP project's metric model in the writers:
// its JSON object, its summary lines and its report section (a side view of
// the fitted floor, the floor points, the cameras and the odometry frame).
#pragma once

#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/solver/calibration_result.h"

#include <nlohmann/json.hpp>

#include <string>

namespace odomcal {

// `floor_plane` of the result JSON; null when the floor was not fitted
// (`odomcal calibrate`, --floor_plane off, no metric model).
nlohmann::json FloorPlaneToJson(const CalibrationResult& result);

// The summary's lines about the floor ("" without one), each starting with
// two spaces and ending with a newline.
std::string FloorPlaneSummary(const CalibrationResult& result);

// How z was found, for the summary's z line: "estimated (...)" or
// "fixed (...)".
std::string TranslationZOrigin(const CalibrationResult& result);

// The report's "Floor plane" section ("" without a fitted plane).
std::string FloorPlaneHtml(const ColmapCalibrationRun& run);

}  // namespace odomcal
