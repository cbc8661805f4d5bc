// A reconstruction restricted to some of its images: what a metric export of
// one part of a sub-model holds when the rest of the sub-model (a folded
// stretch, a part at another scale) must not be carried along.
#pragma once

#include "odomcal/adapters/colmap_model.h"

#include <cstdint>
#include <set>

namespace odomcal {

// Keeps the images in `image_ids` (ids absent from the model are ignored),
// the cameras they use, and the points still observed by at least
// `min_track_length` kept images; observations of dropped points are
// unlinked (kColmapNoPoint3D) so that the result is a consistent model.
ColmapModel ColmapModelSubset(const ColmapModel& model,
                              const std::set<uint32_t>& image_ids,
                              int min_track_length = 2);

}  // namespace odomcal
