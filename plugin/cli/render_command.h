// `odomcal render`: writes a rendered calibration dataset (datasets/
// rendered_dataset.h) for a named preset:
//   odomcal render --preset NAME --output_path DIR [--seed S] [--overwrite]
//                  [--rig NAME [--capped_camera CAMERA]...]
// (--rig: datasets/rendering/rendered_rig.h). DIR must not exist or be empty
// unless --overwrite; with it, the images and files of an earlier dataset in
// DIR are replaced (stale NNNNNN.png beyond the new count and a rig's stale
// <camera>/<stamp>.png are removed; other files are left alone). Progress goes
// to stdout; errors are one line on stderr with exit code 2.
#pragma once

namespace odomcal {

int RunRender(int argc, char** argv);

}  // namespace odomcal
