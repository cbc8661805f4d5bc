#include "odomcal/plugin/colmap/mapper_chunks.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace odomcal {

void ChunkOptions::Check() const {
  if (max_images < 0) {
    throw std::invalid_argument("max_images must be >= 0, got " +
                                std::to_string(max_images));
  }
  if (overlap < 2 || (max_images > 0 && 2 * overlap > max_images)) {
    throw std::invalid_argument(
        "overlap must be >= 2 and at most half of max_images, got " +
        std::to_string(overlap));
  }
}

std::vector<MapperChunk> SplitIntoChunks(int num_images,
                                         const ChunkOptions& options) {
  options.Check();
  std::vector<MapperChunk> chunks;
  if (num_images <= 0) return chunks;
  if (options.max_images == 0 || num_images <= options.max_images) {
    chunks.push_back({0, num_images - 1, 0, num_images - 1});
    return chunks;
  }
  // n chunks of s images sharing o images span n s - (n - 1) o images: the
  // fewest chunks, then the smallest size that covers the drive (one more
  // image for the rounding of the starts, within max_images).
  const int step = options.max_images - options.overlap;
  const int count = (num_images - options.overlap + step - 1) / step;
  const int size = std::min(
      options.max_images,
      (num_images + (count - 1) * options.overlap + count - 1) / count + 1);
  for (int k = 0; k < count; ++k) {
    MapperChunk chunk;
    chunk.first = static_cast<int>(static_cast<long long>(k) *
                                   (num_images - size) / (count - 1));
    chunk.last = chunk.first + size - 1;
    chunks.push_back(chunk);
  }
  for (int k = 0; k < count; ++k) {
    chunks[k].own_first = k == 0 ? 0 : chunks[k - 1].own_last;
    chunks[k].own_last = k + 1 == count
                             ? num_images - 1
                             : (chunks[k + 1].first + chunks[k].last) / 2;
  }
  return chunks;
}

std::vector<int> FoldedPairsPerChunk(
    int num_chunks,
    const std::vector<int>& chunk_of_segment,
    const std::vector<InconsistentStretch>& stretches) {
  std::vector<int> folded(static_cast<size_t>(std::max(num_chunks, 0)), 0);
  for (const InconsistentStretch& stretch : stretches) {
    if (stretch.kept_as_segment || stretch.input_segment < 0 ||
        stretch.input_segment >= static_cast<int>(chunk_of_segment.size())) {
      continue;
    }
    const int chunk = chunk_of_segment[stretch.input_segment];
    if (chunk >= 0 && chunk < num_chunks) folded[chunk] += stretch.num_pairs;
  }
  return folded;
}

}  // namespace odomcal
