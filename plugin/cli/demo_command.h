// `odomcal demo`: the embedded default job. Renders a synthetic scene with a
// known camera mount (datasets/), runs `odomcal run` on it (COLMAP, then the
// calibration) and prints the result next to the ground truth.
// `--simulated` instead calibrates a simulated trajectory pair in a second,
// without images or COLMAP.
#pragma once

namespace odomcal {

int RunDemo(int argc, char** argv);

}  // namespace odomcal
