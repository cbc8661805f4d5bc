// Mapping a long drive in chunks (issue 18, "cost linear in the drive"):
// COLMAP's incremental mapper slows down faster than linearly with the
// images of one model (each registration runs bundle adjustments over a
// growing model), so a drive longer than one chunk is cut, along the
// odometry's time order, into chunks of at most `max_images` images that
// share `overlap` images with the next, and each chunk is mapped by
// `colmap mapper` on its own (--image_list_path, the same database). Each
// chunk's model is a sub-model of its own: a segment with its own scale in
// the calibration, as the mapper's own sub-models are. The mapper's cost is
// bounded per chunk (not per image: a chunk whose points are tracked over
// many images costs several times the others, docs/benchmarks.md) and
// memory by one chunk's model; COLMAP can map the chunks on several
// machines, as they are independent.
//
// The overlap lets each chunk's ends be mapped with the views around them;
// for the calibration every chunk keeps only its own images (ChunkOwnRange)
// and the first image of the next chunk's, so that no motion pair is counted
// twice and the pair across the boundary still exists.
//
// A chunk whose model the odometry contradicts in a stretch (COLMAP folded
// it) is mapped again with the next random seeds, as a one-model drive is
// (FoldedPairsPerChunk names it).
#pragma once

#include "odomcal/solver/stretch_consistency.h"

#include <vector>

namespace odomcal {

struct ChunkOptions {
  // 0: no chunks (one model of all images). 50, not 100: a
  // chunk's bundle adjustments cost more than linearly in its images.
  int max_images = 50;
  int overlap = 12;    // images shared by consecutive chunks
  void Check() const;  // throws std::invalid_argument naming the field
};

struct MapperChunk {
  int first = 0;  // images [first, last] of the drive (time order) mapped
  int last = 0;
  int own_first = 0;  // images [own_first, own_last] kept for calibration
  int own_last = 0;
};

// The chunks of a drive of `num_images` images: one chunk (all images, all
// its own) when they fit in max_images or max_images is 0; otherwise chunks
// of equal size (at most max_images), consecutive ones sharing at least
// `overlap` images, whose own ranges meet in the middle of each overlap and
// overlap by one image (own_last of a chunk = own_first of the next).
std::vector<MapperChunk> SplitIntoChunks(int num_images,
                                         const ChunkOptions& options);

// Per chunk, the motion pairs of the stretches the calibration left out as
// folded (`stretches` not kept as a segment), counted for the chunk the
// stretch's segment came from: `chunk_of_segment[s]` for the calibration's
// input segment s (-1, or beyond its end: from no chunk).
std::vector<int> FoldedPairsPerChunk(
    int num_chunks,
    const std::vector<int>& chunk_of_segment,
    const std::vector<InconsistentStretch>& stretches);

}  // namespace odomcal
