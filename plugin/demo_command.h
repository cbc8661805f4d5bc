// `odomcal demo`: the embedded default job. Simulates a robot drive with a
// known extrinsic and scale, writes it as ordinary input files, calibrates
// from those files and compares the result with the ground truth.
// (The rendered-scene demo through COLMAP replaces the simulation later.)
#pragma once

namespace odomcal {

int RunDemo(int argc, char** argv);

}  // namespace odomcal
