// The reader of COLMAP's binary model files (colmap_model_binary.cc and
// colmap_model_rigs_binary.cc); internal: not installed. It knows the file
// size and its own offset: every field read first checks that its bytes
// remain, counts are compared with the remaining bytes before anything is
// reserved, and failures name the path, the byte offset and the record.
// Little-endian integers are assembled byte by byte, independent of the
// host's byte order.
#pragma once

#include "odomcal/adapters/colmap_model_internal.h"
#include "odomcal/adapters/format_error.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>

namespace odomcal::internal {

class BinaryReader {
 public:
  explicit BinaryReader(const std::string& path) : path_(path) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) {
      throw FormatError(path + ": cannot open for reading: is a directory");
    }
    errno = 0;
    stream_.open(path, std::ios::binary);
    if (!stream_.is_open()) {
      throw FormatError(path + ": cannot open for reading" + OpenReason());
    }
    size_ = std::filesystem::file_size(path, error);
    if (error) {
      throw FormatError(path +
                        ": cannot determine the file size: " + error.message());
    }
  }

  const std::string& path() const { return path_; }
  uint64_t offset() const { return offset_; }
  uint64_t remaining() const { return size_ - offset_; }
  void set_record(std::string record) { record_ = std::move(record); }

  uint8_t ReadU8(const char* what) {
    return static_cast<uint8_t>(ReadLittleEndian(1, what));
  }
  uint32_t ReadU32(const char* what) {
    return static_cast<uint32_t>(ReadLittleEndian(4, what));
  }
  int32_t ReadI32(const char* what) {
    const uint32_t bits = ReadU32(what);
    int32_t value = 0;
    std::memcpy(&value, &bits, sizeof(value));
    return value;
  }
  uint64_t ReadU64(const char* what) { return ReadLittleEndian(8, what); }

  double ReadFiniteDouble(const char* what) {
    const uint64_t start = offset_;
    const uint64_t bits = ReadLittleEndian(8, what);
    double value = 0.0;
    std::memcpy(&value, &bits, sizeof(value));
    if (!std::isfinite(value)) {
      FailAt(start, std::string(what) + " is not finite");
    }
    return value;
  }

  // A uint64 count of items that take at least `min_item_bytes` each; fails
  // unless that many items fit in the rest of the file.
  uint64_t ReadCount(const char* what, uint64_t min_item_bytes) {
    const uint64_t start = offset_;
    const uint64_t count = ReadU64(what);
    if (count > remaining() / min_item_bytes) {
      FailAt(start,
             std::string(what) + " is " + std::to_string(count) + ", but the " +
                 std::to_string(remaining()) +
                 " remaining bytes hold at most " +
                 std::to_string(remaining() / min_item_bytes) +
                 " (garbled or truncated file)");
    }
    return count;
  }

  // Bytes up to a '\0', which is consumed.
  std::string ReadNullTerminated(const char* what) {
    const uint64_t start = offset_;
    std::string text;
    while (true) {
      if (remaining() == 0) {
        FailAt(start,
               std::string("truncated: ") + what +
                   " has no terminating '\\0' before the end of the file");
      }
      const char c = static_cast<char>(ReadU8(what));
      if (c == '\0') return text;
      text.push_back(c);
    }
  }

  void ExpectEnd() {
    record_.clear();
    if (remaining() != 0) {
      Fail(std::to_string(remaining()) +
           " unexpected bytes after the last record (garbled count?)");
    }
  }

  [[noreturn]] void Fail(const std::string& what) const {
    FailAt(offset_, what);
  }

  [[noreturn]] void FailAt(uint64_t offset, const std::string& what) const {
    throw FormatError(path_ + ": byte " + std::to_string(offset) + ": " +
                      (record_.empty() ? "" : record_ + ": ") + what);
  }

 private:
  uint64_t ReadLittleEndian(int num_bytes, const char* what) {
    if (remaining() < static_cast<uint64_t>(num_bytes)) {
      Fail(std::string("truncated: ") + what + " needs " +
           std::to_string(num_bytes) + " bytes, " +
           std::to_string(remaining()) + " remain");
    }
    unsigned char bytes[8] = {};
    stream_.read(reinterpret_cast<char*>(bytes), num_bytes);
    if (stream_.gcount() != num_bytes)
      Fail(std::string("read error at ") + what);
    offset_ += num_bytes;
    uint64_t value = 0;
    for (int i = num_bytes - 1; i >= 0; --i) value = (value << 8) | bytes[i];
    return value;
  }

  std::string path_;
  std::ifstream stream_;
  uint64_t size_ = 0;
  uint64_t offset_ = 0;
  std::string record_;
};

// "camera 3 of 10".
inline std::string BinaryRecordName(const char* kind,
                                    uint64_t index,
                                    uint64_t count) {
  return std::string(kind) + " " + std::to_string(index + 1) + " of " +
         std::to_string(count);
}

}  // namespace odomcal::internal
