#include "odomcal/solver/parallel_chunks.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace odomcal::internal {

int NumWorkerThreads(int num_threads) {
  if (num_threads > 0) return num_threads;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

int NumChunks(int n) { return n <= 0 ? 0 : (n + kChunkSize - 1) / kChunkSize; }

void ForEachChunk(
    int n,
    int num_threads,
    const std::function<void(int chunk, int begin, int end)>& fn) {
  const int num_chunks = NumChunks(n);
  const auto run = [&](int chunk) {
    const int begin = chunk * kChunkSize;
    fn(chunk, begin, std::min(n, begin + kChunkSize));
  };
  const int threads =
      std::min(NumWorkerThreads(num_threads), std::max(1, num_chunks));
  if (threads == 1) {
    for (int chunk = 0; chunk < num_chunks; ++chunk) run(chunk);
    return;
  }
  std::atomic<int> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  const auto work = [&] {
    for (int chunk = next++; chunk < num_chunks; chunk = next++) {
      try {
        run(chunk);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next = num_chunks;  // the others stop at their next chunk
      }
    }
  };
  std::vector<std::thread> workers;
  workers.reserve(threads - 1);
  for (int t = 1; t < threads; ++t) {
    try {
      workers.emplace_back(work);
    } catch (const std::system_error&) {
      break;  // no thread to be had: the ones running do the rest
    }
  }
  work();
  for (std::thread& worker : workers) worker.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace odomcal::internal
