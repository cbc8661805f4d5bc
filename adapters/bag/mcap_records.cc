// MCAP record fields and chunk decompression (mcap_records.h).
#include "odomcal/adapters/bag/mcap_records.h"

#include "odomcal/adapters/bag/ros2_storage.h"
#include "odomcal/adapters/format_error.h"

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <new>
#include <string>

namespace odomcal::bag::internal {

void McapCursor::Fail(const std::string& what) const {
  throw FormatError(*context_ + ": " + what);
}

const uint8_t* McapCursor::Take(size_t size, const char* field) {
  if (size > remaining()) {
    Fail(std::string(field) + " needs " + std::to_string(size) +
         " bytes, the record has " + std::to_string(remaining()) + " left");
  }
  const uint8_t* begin = data_ + position_;
  position_ += size;
  return begin;
}

uint16_t McapCursor::U16(const char* field) {
  const uint8_t* b = Take(2, field);
  return static_cast<uint16_t>(b[0] | (b[1] << 8));
}

uint32_t McapCursor::U32(const char* field) {
  const uint8_t* b = Take(4, field);
  uint32_t value = 0;
  for (int i = 3; i >= 0; --i) value = (value << 8) | b[i];
  return value;
}

uint64_t McapCursor::U64(const char* field) {
  const uint8_t* b = Take(8, field);
  uint64_t value = 0;
  for (int i = 7; i >= 0; --i) value = (value << 8) | b[i];
  return value;
}

std::string McapCursor::String(const char* field) {
  const uint32_t size = U32(field);
  const uint8_t* bytes = Take(size, field);
  return std::string(reinterpret_cast<const char*>(bytes), size);
}

void McapCursor::SkipPrefixed32(const char* field) { Take(U32(field), field); }

std::pair<const uint8_t*, size_t> McapCursor::Rest() {
  const size_t size = remaining();
  return {Take(size, "data"), size};
}

McapSchema ParseMcapSchema(McapCursor* cursor) {
  McapSchema schema;
  schema.id = cursor->U16("schema id");
  schema.name = cursor->String("schema name");
  schema.encoding = cursor->String("schema encoding");
  cursor->SkipPrefixed32("schema data");
  return schema;
}

McapChannel ParseMcapChannel(McapCursor* cursor) {
  McapChannel channel;
  channel.id = cursor->U16("channel id");
  channel.schema_id = cursor->U16("schema id");
  channel.topic = cursor->String("topic");
  channel.message_encoding = cursor->String("message encoding");
  cursor->SkipPrefixed32("channel metadata");
  return channel;
}

McapMessageView ParseMcapMessage(McapCursor* cursor) {
  McapMessageView message;
  message.channel_id = cursor->U16("channel id");
  cursor->U32("sequence");
  message.log_time = cursor->U64("log time");
  cursor->U64("publish time");
  const auto [data, size] = cursor->Rest();
  message.data = data;
  message.size = size;
  return message;
}

McapChunkView ParseMcapChunk(McapCursor* cursor) {
  McapChunkView chunk;
  cursor->U64("message start time");
  cursor->U64("message end time");
  chunk.uncompressed_size = cursor->U64("uncompressed size");
  chunk.uncompressed_crc = cursor->U32("uncompressed crc");
  chunk.compression = cursor->String("compression");
  const uint64_t size = cursor->U64("records length");
  if (size > cursor->remaining()) {
    cursor->Fail("records length " + std::to_string(size) +
                 " past the record's end");
  }
  chunk.records_size = static_cast<size_t>(size);
  chunk.records = cursor->Take(chunk.records_size, "records");
  return chunk;
}

McapChunkIndex ParseMcapChunkIndex(McapCursor* cursor) {
  McapChunkIndex index;
  cursor->U64("message start time");
  cursor->U64("message end time");
  index.chunk_start_offset = cursor->U64("chunk start offset");
  index.chunk_length = cursor->U64("chunk length");
  const uint32_t map_size = cursor->U32("message index offsets");
  if (map_size % 10 != 0) {
    cursor->Fail("message index offsets of " + std::to_string(map_size) +
                 " bytes, not a multiple of 10");
  }
  McapCursor map(cursor->Take(map_size, "message index offsets"),
                 map_size,
                 cursor->context());
  for (uint32_t i = 0; i < map_size / 10; ++i) {
    const uint16_t channel = map.U16("channel id");
    index.message_index_offsets.emplace_back(channel, map.U64("offset"));
  }
  return index;
}

McapStatistics ParseMcapStatistics(McapCursor* cursor) {
  McapStatistics statistics;
  statistics.message_count = cursor->U64("message count");
  cursor->U16("schema count");
  cursor->U32("channel count");
  cursor->U32("attachment count");
  cursor->U32("metadata count");
  cursor->U32("chunk count");
  cursor->U64("message start time");
  cursor->U64("message end time");
  const uint32_t map_size = cursor->U32("channel message counts");
  if (map_size % 10 != 0) {
    cursor->Fail("channel message counts of " + std::to_string(map_size) +
                 " bytes, not a multiple of 10");
  }
  McapCursor map(cursor->Take(map_size, "channel message counts"),
                 map_size,
                 cursor->context());
  for (uint32_t i = 0; i < map_size / 10; ++i) {
    const uint16_t channel = map.U16("channel id");
    statistics.channel_message_counts.emplace_back(channel, map.U64("count"));
  }
  return statistics;
}

McapFooter ParseMcapFooter(McapCursor* cursor) {
  McapFooter footer;
  footer.summary_start = cursor->U64("summary start");
  footer.summary_offset_start = cursor->U64("summary offset start");
  footer.summary_crc = cursor->U32("summary crc");
  return footer;
}

McapIndexSpan ParseMcapMessageIndex(McapCursor* cursor) {
  McapIndexSpan span;
  span.channel_id = cursor->U16("channel id");
  const uint32_t size = cursor->U32("records");
  if (size % 16 != 0) {
    cursor->Fail("message index records of " + std::to_string(size) +
                 " bytes, not a multiple of 16");
  }
  span.count = size / 16;
  for (uint64_t i = 0; i < span.count; ++i) {
    const uint64_t log_time = cursor->U64("log time");
    cursor->U64("offset");
    if (i == 0 || log_time < span.first_log_time)
      span.first_log_time = log_time;
    if (i == 0 || log_time > span.last_log_time) span.last_log_time = log_time;
  }
  return span;
}

namespace {

struct McapZstdFree {
  void operator()(ZSTD_DCtx* context) const { ZSTD_freeDCtx(context); }
};
struct McapLz4Free {
  void operator()(LZ4F_dctx* context) const {
    LZ4F_freeDecompressionContext(context);
  }
};

// One call of a streaming decompressor: consumes from *input_used on,
// writes from *output_used on, returns 0 at the end of a frame.
template <typename Step>
void McapInflate(const McapChunkView& chunk,
                 const std::string& context,
                 std::vector<uint8_t>* out,
                 Step step) {
  const size_t declared = static_cast<size_t>(chunk.uncompressed_size);
  // One byte beyond the declared size shows a chunk that inflates to more.
  const size_t limit = declared + 1;
  out->resize(std::min(limit, std::max<size_t>(chunk.records_size, 1 << 16)));
  size_t input_used = 0;
  size_t output_used = 0;
  while (true) {
    if (output_used == out->size()) {
      if (out->size() == limit) break;
      out->resize(std::min(limit, out->size() * 2));
    }
    const size_t input_before = input_used;
    const size_t output_before = output_used;
    const size_t left = step(&input_used, &output_used);
    if (output_used > declared) break;
    if (input_used == chunk.records_size && left == 0) break;
    if (input_used == input_before && output_used == output_before) {
      throw FormatError(context + ": " + chunk.compression +
                        " data ends inside a frame");
    }
  }
  if (output_used != declared) {
    throw FormatError(context + ": " + chunk.compression +
                      " data inflates to " +
                      (output_used > declared
                           ? "more than "
                           : std::to_string(output_used) + " bytes, not ") +
                      std::to_string(declared) + " bytes (uncompressed size)");
  }
  out->resize(declared);
}

}  // namespace

void DecompressMcapChunk(const McapChunkView& chunk,
                         const std::string& context,
                         std::vector<uint8_t>* out) {
  if (chunk.uncompressed_size >= std::numeric_limits<size_t>::max() / 2) {
    throw FormatError(context + ": uncompressed size " +
                      std::to_string(chunk.uncompressed_size) + " too large");
  }
  if (chunk.compression.empty()) {
    if (chunk.records_size != chunk.uncompressed_size) {
      throw FormatError(context + ": uncompressed chunk of " +
                        std::to_string(chunk.records_size) +
                        " bytes declares " +
                        std::to_string(chunk.uncompressed_size));
    }
    out->assign(chunk.records, chunk.records + chunk.records_size);
  } else if (chunk.compression == "zstd") {
    const std::unique_ptr<ZSTD_DCtx, McapZstdFree> zstd(ZSTD_createDCtx());
    if (!zstd) throw std::bad_alloc();
    McapInflate(chunk, context, out, [&](size_t* in_used, size_t* out_used) {
      ZSTD_inBuffer input{chunk.records, chunk.records_size, *in_used};
      ZSTD_outBuffer output{out->data(), out->size(), *out_used};
      const size_t result = ZSTD_decompressStream(zstd.get(), &output, &input);
      if (ZSTD_isError(result) != 0) {
        throw FormatError(context + ": zstd: " + ZSTD_getErrorName(result));
      }
      *in_used = input.pos;
      *out_used = output.pos;
      return result;
    });
  } else if (chunk.compression == "lz4") {
    LZ4F_dctx* raw = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)) !=
        0) {
      throw std::bad_alloc();
    }
    const std::unique_ptr<LZ4F_dctx, McapLz4Free> lz4(raw);
    McapInflate(chunk, context, out, [&](size_t* in_used, size_t* out_used) {
      size_t input_size = chunk.records_size - *in_used;
      size_t output_size = out->size() - *out_used;
      const size_t result = LZ4F_decompress(lz4.get(),
                                            out->data() + *out_used,
                                            &output_size,
                                            chunk.records + *in_used,
                                            &input_size,
                                            nullptr);
      if (LZ4F_isError(result) != 0) {
        throw FormatError(context + ": lz4: " + LZ4F_getErrorName(result));
      }
      *in_used += input_size;
      *out_used += output_size;
      return result;
    });
  } else {
    throw FormatError(context + ": unknown compression " +
                      Ros2Quoted(chunk.compression));
  }
  if (chunk.uncompressed_crc != 0) {
    const uint32_t crc = McapCrc32(0, out->data(), out->size());
    if (crc != chunk.uncompressed_crc) {
      throw FormatError(context + ": CRC mismatch (records " +
                        std::to_string(crc) + ", chunk says " +
                        std::to_string(chunk.uncompressed_crc) + ")");
    }
  }
}

void InflateZstdFrame(const uint8_t* data,
                      size_t size,
                      const std::string& context,
                      std::vector<uint8_t>* out) {
  const unsigned long long declared = ZSTD_getFrameContentSize(data, size);
  if (declared == ZSTD_CONTENTSIZE_ERROR) {
    throw FormatError(context + ": not a zstd frame");
  }
  if (declared == ZSTD_CONTENTSIZE_UNKNOWN) {
    throw FormatError(context + ": zstd frame without its content size");
  }
  McapChunkView frame;
  frame.uncompressed_size = declared;
  frame.compression = "zstd";
  frame.records = data;
  frame.records_size = size;
  DecompressMcapChunk(frame, context, out);
}

uint32_t McapCrc32(uint32_t crc, const uint8_t* data, size_t size) {
  return static_cast<uint32_t>(crc32_z(crc, data, size));
}

}  // namespace odomcal::bag::internal
