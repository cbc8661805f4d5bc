// Decompression of ROS 1 bag chunks: "none", "bz2" (libbz2) and "lz4" (the
// LZ4 frame format, which roslz4 writes; liblz4's LZ4F API).
//
// Internal to odomcal_bag. The output grows only as the decompressor produces
// bytes, so a chunk header that claims a huge size costs nothing before the
// data backs it up.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace odomcal::bag {

// The largest uncompressed chunk accepted. rosbag's default is 768 KiB;
// `rosbag record --chunksize` allows more, but not this much.
constexpr uint32_t kRos1MaxChunkBytes = 1u << 30;

// Decompresses `compressed` into *out (replaced), which must come to exactly
// `uncompressed_size` bytes. Throws FormatError with the bare problem
// ("unknown compression 'zip'", "bz2 data decompress to more than 100 bytes").
void Ros1DecompressChunk(const std::string& compression,
                         const std::vector<uint8_t>& compressed,
                         uint32_t uncompressed_size,
                         std::vector<uint8_t>* out);

}  // namespace odomcal::bag
