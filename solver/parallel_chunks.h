// Fixed chunks of an index range, worked on by several threads (internal:
// not installed). The chunks do not depend on the number of threads: a
// caller that keeps one partial result per chunk and adds them in chunk
// order gets the same bits on any number of threads, and a range of one
// chunk those of a plain loop.
#pragma once

#include <functional>

namespace odomcal::internal {

inline constexpr int kChunkSize = 256;

// The threads to use for CalibrationOptions::num_threads (-1: the
// hardware's).
int NumWorkerThreads(int num_threads);

int NumChunks(int n);

// fn(chunk, begin, end) for every chunk [begin, end) of [0, n), on up to
// `num_threads` threads (the calling one among them). The first exception
// fn throws is rethrown here, after every thread has stopped.
void ForEachChunk(int n,
                  int num_threads,
                  const std::function<void(int chunk, int begin, int end)>& fn);

}  // namespace odomcal::internal
