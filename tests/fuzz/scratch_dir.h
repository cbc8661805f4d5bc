// A private temporary folder for one fuzzing process.
//
// The adapters read files by path, so each fuzz input is written to a file
// here before it is parsed. The folder lives under
// std::filesystem::temp_directory_path() ($TMPDIR; scripts/fuzz.sh points it
// at /dev/shm so that the writes stay in memory), has a unique name, and is
// removed with everything in it when the ScratchDir is destroyed. A process
// that crashes leaves it behind, next to the crash input that explains why.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace odomcal {

class ScratchDir {
 public:
  // Creates the folder. Throws std::runtime_error when it cannot.
  ScratchDir();
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  // Writes `bytes` to `file_name` inside the folder, replacing the previous
  // content, and returns the file's path. Throws std::runtime_error on I/O
  // errors (a harness failure, not a finding in the parser).
  std::string Write(const std::string& file_name, std::string_view bytes) const;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The fuzz input as text, for the APIs that take strings.
inline std::string_view AsBytes(const uint8_t* data, size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace odomcal
