#include "odomcal/plugin/colmap/mapper_chunks.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace odomcal {
namespace {

// The split's arithmetic with chunks of at most 200 images sharing 25 (the
// default is 50 sharing 12, benchmarks.md).
ChunkOptions TwoHundredImageChunks() {
  ChunkOptions options;
  options.max_images = 200;
  options.overlap = 25;
  return options;
}

TEST(SplitIntoChunks, DriveThatFitsIsOneChunk) {
  ChunkOptions options = TwoHundredImageChunks();
  const std::vector<MapperChunk> chunks = SplitIntoChunks(200, options);
  ASSERT_EQ(chunks.size(), 1u);
  EXPECT_EQ(chunks[0].first, 0);
  EXPECT_EQ(chunks[0].last, 199);
  EXPECT_EQ(chunks[0].own_first, 0);
  EXPECT_EQ(chunks[0].own_last, 199);
  EXPECT_EQ(SplitIntoChunks(50, ChunkOptions()).size(), 1u);  // the default
  EXPECT_EQ(SplitIntoChunks(51, ChunkOptions()).size(), 2u);
  options.max_images = 0;  // off
  EXPECT_EQ(SplitIntoChunks(5000, options).size(), 1u);
  EXPECT_TRUE(SplitIntoChunks(0, ChunkOptions()).empty());
}

TEST(SplitIntoChunks, CoversTheDriveWithBoundedOverlappingChunks) {
  for (const ChunkOptions& options : {TwoHundredImageChunks(), ChunkOptions()})
    for (const int num_images : {201, 300, 376, 377, 855, 999, 1000, 4321}) {
      SCOPED_TRACE(std::to_string(num_images) + " images, chunks of " +
                   std::to_string(options.max_images));
      const std::vector<MapperChunk> chunks =
          SplitIntoChunks(num_images, options);
      // The fewest chunks of at most s images sharing o: ceil((n - o) /
      // (s - o)).
      const int step = options.max_images - options.overlap;
      EXPECT_EQ(static_cast<int>(chunks.size()),
                (num_images - options.overlap + step - 1) / step);
      EXPECT_EQ(chunks.front().first, 0);
      EXPECT_EQ(chunks.back().last, num_images - 1);
      EXPECT_EQ(chunks.front().own_first, 0);
      EXPECT_EQ(chunks.back().own_last, num_images - 1);
      for (size_t k = 0; k < chunks.size(); ++k) {
        const MapperChunk& c = chunks[k];
        EXPECT_LE(c.last - c.first + 1, options.max_images);
        EXPECT_LE(c.first, c.own_first);
        EXPECT_LT(c.own_first, c.own_last);
        EXPECT_LE(c.own_last, c.last);
        if (k == 0) continue;
        const MapperChunk& previous = chunks[k - 1];
        EXPECT_GE(previous.last - c.first + 1, options.overlap);
        // Own ranges share exactly one image: every motion pair once.
        EXPECT_EQ(previous.own_last, c.own_first);
      }
    }
}

TEST(SplitIntoChunks, ThreeHundredImagesAreTwoEqualChunks) {
  const std::vector<MapperChunk> chunks =
      SplitIntoChunks(300, TwoHundredImageChunks());
  ASSERT_EQ(chunks.size(), 2u);
  // 2 s - 25 >= 300: s = 163 (+1 for the rounding of the starts).
  EXPECT_EQ(chunks[0].first, 0);
  EXPECT_EQ(chunks[0].last, 163);
  EXPECT_EQ(chunks[1].first, 136);
  EXPECT_EQ(chunks[1].last, 299);
  EXPECT_EQ(chunks[0].own_last, 149);
  EXPECT_EQ(chunks[1].own_first, 149);
}

// The default on the rendered 1000-image drive's 617 selected images
// (benchmarks.md): 16 chunks of 50, each owning about 38.
TEST(SplitIntoChunks, DefaultChunksOfTheThousandImageDrive) {
  const std::vector<MapperChunk> chunks = SplitIntoChunks(617, ChunkOptions());
  ASSERT_EQ(chunks.size(), 16u);
  for (const MapperChunk& chunk : chunks) {
    EXPECT_EQ(chunk.last - chunk.first + 1, 50);
  }
  EXPECT_EQ(chunks[1].first, 37);
  EXPECT_EQ(chunks.back().last, 616);
}

TEST(SplitIntoChunks, RejectsBadOptions) {
  ChunkOptions options;
  options.overlap = 150;
  try {
    SplitIntoChunks(1000, options);
    ADD_FAILURE() << "accepted an overlap above half the chunk";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()),
              "overlap must be >= 2 and at most half of max_images, got 150");
  }
  options = ChunkOptions();
  options.max_images = -1;
  EXPECT_THROW(SplitIntoChunks(10, options), std::invalid_argument);
}

// A folded stretch counts for the chunk its segment's sub-model came from;
// a stretch kept as a segment of its own (another scale), or of a segment
// from no chunk, counts for none.
TEST(FoldedPairsPerChunk, CountsEachFoldedStretchForTheChunkOfItsSegment) {
  auto stretch = [](int segment, int num_pairs, bool kept) {
    InconsistentStretch s;
    s.input_segment = segment;
    s.num_pairs = num_pairs;
    s.kept_as_segment = kept;
    return s;
  };
  // Segments 0 and 1 from chunk 0, 2 from chunk 2, 3 from none.
  const std::vector<int> chunk_of_segment = {0, 0, 2, -1};
  EXPECT_EQ(FoldedPairsPerChunk(3, chunk_of_segment, {}),
            std::vector<int>({0, 0, 0}));
  EXPECT_EQ(FoldedPairsPerChunk(3,
                                chunk_of_segment,
                                {stretch(0, 10, false),
                                 stretch(1, 6, false),
                                 stretch(2, 4, false),
                                 stretch(2, 5, true),
                                 stretch(3, 7, false),
                                 stretch(4, 8, false)}),
            std::vector<int>({16, 0, 4}));
}

}  // namespace
}  // namespace odomcal
