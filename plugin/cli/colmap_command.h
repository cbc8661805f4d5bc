// `odomcal colmap`: calibrates an existing COLMAP project (sparse model or
// the mapper's sparse root with sub-models) against wheel odometry; writes
// only into --output_path, never inside the input project.
#pragma once

namespace odomcal {

int RunColmap(int argc, char** argv);

}  // namespace odomcal
