#include "odomcal/adapters/bag/ros1_chunk_codec.h"

#include "odomcal/adapters/format_error.h"

#include <bzlib.h>
#include <lz4frame.h>

#include <algorithm>
#include <memory>

namespace odomcal::bag {
namespace {

// The next output size: double, but never past the declared size plus one
// byte (the byte that detects data longer than declared).
size_t Ros1GrownSize(size_t current, uint32_t declared) {
  const size_t limit = static_cast<size_t>(declared) + 1;
  return std::min(limit, std::max<size_t>(current * 2, size_t{64} * 1024));
}

[[noreturn]] void Ros1SizeMismatch(const char* codec,
                                   size_t got,
                                   uint32_t declared) {
  if (got > declared) {
    throw FormatError(std::string(codec) +
                      " data decompress to more than the chunk's size of " +
                      std::to_string(declared) + " bytes");
  }
  throw FormatError(std::string(codec) + " data decompress to " +
                    std::to_string(got) + " bytes, the chunk's size is " +
                    std::to_string(declared));
}

void Ros1DecompressBz2(const std::vector<uint8_t>& in,
                       uint32_t declared,
                       std::vector<uint8_t>* out) {
  bz_stream stream{};
  if (BZ2_bzDecompressInit(&stream, 0, 0) != BZ_OK) {
    throw FormatError("bz2: cannot initialise the decompressor");
  }
  const std::unique_ptr<bz_stream, void (*)(bz_stream*)> guard(
      &stream, [](bz_stream* s) { BZ2_bzDecompressEnd(s); });
  // libbz2 takes non-const pointers but does not write the input.
  stream.next_in = const_cast<char*>(reinterpret_cast<const char*>(in.data()));
  stream.avail_in = static_cast<unsigned int>(in.size());
  size_t produced = 0;
  out->resize(Ros1GrownSize(0, declared));
  for (;;) {
    if (produced == out->size()) {
      if (out->size() > declared) Ros1SizeMismatch("bz2", produced, declared);
      out->resize(Ros1GrownSize(out->size(), declared));
    }
    stream.next_out = reinterpret_cast<char*>(out->data() + produced);
    stream.avail_out = static_cast<unsigned int>(out->size() - produced);
    const int status = BZ2_bzDecompress(&stream);
    produced = out->size() - stream.avail_out;
    if (status == BZ_STREAM_END) break;
    if (status != BZ_OK) {
      throw FormatError("bz2 data do not decompress (libbz2 error " +
                        std::to_string(status) + ")");
    }
    if (stream.avail_in == 0 && stream.avail_out != 0) {
      throw FormatError("bz2 data end before the end of the bz2 stream");
    }
  }
  if (stream.avail_in != 0) {
    throw FormatError("bz2 data have " + std::to_string(stream.avail_in) +
                      " bytes after the end of the bz2 stream");
  }
  if (produced != declared) Ros1SizeMismatch("bz2", produced, declared);
  out->resize(produced);
}

void Ros1DecompressLz4(const std::vector<uint8_t>& in,
                       uint32_t declared,
                       std::vector<uint8_t>* out) {
  LZ4F_dctx* context = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION))) {
    throw FormatError("lz4: cannot initialise the decompressor");
  }
  const std::unique_ptr<LZ4F_dctx, size_t (*)(LZ4F_dctx*)> guard(
      context, LZ4F_freeDecompressionContext);
  size_t consumed = 0;
  size_t produced = 0;
  out->resize(Ros1GrownSize(0, declared));
  bool frame_done = false;
  while (!frame_done) {
    if (produced == out->size()) {
      if (out->size() > declared) Ros1SizeMismatch("lz4", produced, declared);
      out->resize(Ros1GrownSize(out->size(), declared));
    }
    size_t out_size = out->size() - produced;
    size_t in_size = in.size() - consumed;
    const size_t hint = LZ4F_decompress(context,
                                        out->data() + produced,
                                        &out_size,
                                        in.data() + consumed,
                                        &in_size,
                                        nullptr);
    if (LZ4F_isError(hint)) {
      throw FormatError(std::string("lz4 data do not decompress (") +
                        LZ4F_getErrorName(hint) + ")");
    }
    consumed += in_size;
    produced += out_size;
    frame_done = hint == 0;
    // No progress with input left would loop forever; with no input left the
    // frame is cut off.
    if (!frame_done && in_size == 0 && out_size == 0 &&
        produced < out->size()) {
      throw FormatError("lz4 data end before the end of the lz4 frame");
    }
  }
  if (consumed != in.size()) {
    throw FormatError("lz4 data have " + std::to_string(in.size() - consumed) +
                      " bytes after the end of the lz4 frame");
  }
  if (produced != declared) Ros1SizeMismatch("lz4", produced, declared);
  out->resize(produced);
}

}  // namespace

void Ros1DecompressChunk(const std::string& compression,
                         const std::vector<uint8_t>& compressed,
                         uint32_t uncompressed_size,
                         std::vector<uint8_t>* out) {
  if (uncompressed_size > kRos1MaxChunkBytes) {
    throw FormatError("chunk size of " + std::to_string(uncompressed_size) +
                      " bytes is beyond the limit of " +
                      std::to_string(kRos1MaxChunkBytes));
  }
  if (compression == "none") {
    if (compressed.size() != uncompressed_size) {
      throw FormatError(
          "uncompressed chunk has " + std::to_string(compressed.size()) +
          " bytes of data but a size of " + std::to_string(uncompressed_size));
    }
    out->assign(compressed.begin(), compressed.end());
  } else if (compression == "bz2") {
    Ros1DecompressBz2(compressed, uncompressed_size, out);
  } else if (compression == "lz4") {
    Ros1DecompressLz4(compressed, uncompressed_size, out);
  } else {
    std::string printable;
    for (const char c : compression.substr(0, 32)) {
      printable += (c >= 0x20 && c < 0x7f) ? c : '?';
    }
    throw FormatError("unknown compression '" + printable + "'");
  }
}

}  // namespace odomcal::bag
