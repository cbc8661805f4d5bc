#include "scratch_dir.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace odomcal {

ScratchDir::ScratchDir() {
  std::string pattern =
      (std::filesystem::temp_directory_path() / "odomcal_fuzz_XXXXXX").string();
  // mkdtemp, not a name of our own: several fuzzing jobs may run at once.
  if (mkdtemp(pattern.data()) == nullptr) {
    throw std::runtime_error("cannot create " + pattern + ": " +
                             std::strerror(errno));
  }
  path_ = pattern;
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;  // a destructor must not throw
  std::filesystem::remove_all(path_, ignored);
}

std::string ScratchDir::Write(const std::string& file_name,
                              std::string_view bytes) const {
  const std::string file_path = path_ + "/" + file_name;
  std::ofstream stream(file_path, std::ios::binary | std::ios::trunc);
  stream.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  stream.close();
  if (!stream) {
    throw std::runtime_error("cannot write " + file_path);
  }
  return file_path;
}

}  // namespace odomcal
