// The first line of every robot file (robot_description.h) names it as
// odomcal's, so that --overwrite may replace it (IsOdomcalResultFile,
// plugin/output/output_file.h): "<!-- odomcal robot output: ... -->" in the
// URDF, "# odomcal robot output: ..." in the others. Apart from
// robot_description.h so that readers need no Eigen.
#pragma once

namespace odomcal {

inline constexpr char kRobotOutputMarker[] = "odomcal robot output";

}  // namespace odomcal
