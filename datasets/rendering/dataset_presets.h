// Named RenderedDatasetOptions for `odomcal render --preset NAME`.
//
//   small     CI: 40 images 320x240 at 2.5 Hz, forward camera, one 8 x 6 m room
//   default   the demo: 64 images 320x240 at 2.5 Hz, forward camera (26 s)
//   tilted    40 images 320x240, camera pitched 20 deg down, rolled 90 deg, 0.7
//   m up hard      two rooms joined by a featureless corridor (the
//   reconstruction
//             splits in two), 1-1.5 % wheel errors, slip, yaw drift, 25 ms
//             time offset and 2 ms jitter; 130 images 320x240 at 2.5 Hz
//   straight  straight driving only (rotation unobservable), 40 images
//   long      room A, textured corridor, room B and back into A (a loop),
//             turns both ways, mild wheel noise; 1000 images 320x240 at
//             3.3 Hz (5 minutes); `odomcal render --num_images` shortens it
//   road      a car on a road (road_scene.h): straight, left turn, straight,
//             right turn, straight at 7 m/s; forward camera 1.65 m up, 80
//             images 640x200 at 10 Hz; exact odometry
//   road_sloped  the same on ground sloped up to 2.5 deg along x and 2 deg
//             along y: the car pitches and banks, its odometry is planar
//
// All share the 50 Hz odometry; the rooms the default texture density (6 mm
// texels).
#pragma once

#include "odomcal/datasets/rendering/rendered_dataset.h"

#include <cstdint>
#include <string>
#include <vector>

namespace odomcal {

struct DatasetPresetInfo {
  std::string name;
  std::string summary;  // one line
};

std::vector<DatasetPresetInfo> DatasetPresets();

// Throws std::invalid_argument listing the valid names for an unknown one.
RenderedDatasetOptions MakeDatasetPreset(const std::string& name,
                                         uint64_t seed);

}  // namespace odomcal
