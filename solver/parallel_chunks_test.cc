#include "odomcal/solver/parallel_chunks.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace odomcal::internal {
namespace {

// Every index in exactly one chunk, the chunks of kChunkSize from 0 and
// the last one short, whatever the number of threads.
TEST(ForEachChunk, VisitsEveryIndexOnceInFixedChunks) {
  const int n = 3 * kChunkSize + 17;
  ASSERT_EQ(NumChunks(n), 4);
  for (const int threads : {1, 2, 3, 8, -1}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    std::vector<std::atomic<int>> visits(n);
    std::vector<int> chunk_begin(NumChunks(n), -1), chunk_end(NumChunks(n), -1);
    ForEachChunk(n, threads, [&](int chunk, int begin, int end) {
      chunk_begin[chunk] = begin;
      chunk_end[chunk] = end;
      for (int i = begin; i < end; ++i) ++visits[i];
    });
    for (int i = 0; i < n; ++i) ASSERT_EQ(visits[i].load(), 1) << i;
    for (int chunk = 0; chunk < NumChunks(n); ++chunk) {
      EXPECT_EQ(chunk_begin[chunk], chunk * kChunkSize);
      EXPECT_EQ(chunk_end[chunk], std::min(n, (chunk + 1) * kChunkSize));
    }
  }
  int calls = 0;
  ForEachChunk(0, 2, [&](int, int, int) { ++calls; });
  EXPECT_EQ(calls, 0);
  EXPECT_GE(NumWorkerThreads(-1), 1);
  EXPECT_EQ(NumWorkerThreads(3), 3);
}

// An exception in one chunk reaches the caller after the threads stopped.
TEST(ForEachChunk, RethrowsTheFirstException) {
  for (const int threads : {1, 2}) {
    EXPECT_THROW(ForEachChunk(10 * kChunkSize,
                              threads,
                              [](int chunk, int, int) {
                                if (chunk == 3) {
                                  throw std::runtime_error("chunk 3");
                                }
                              }),
                 std::runtime_error);
  }
}

}  // namespace
}  // namespace odomcal::internal
