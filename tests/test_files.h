// Files as the CLI tests see them: whole contents, and a snapshot of a folder
// to show that odomcal left its inputs byte-identical.
#pragma once

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace odomcal {

inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

// Every regular file under `root`, by path, with its bytes.
inline std::map<std::string, std::string> Snapshot(
    const std::filesystem::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(root)) {
    if (entry.is_regular_file())
      files[entry.path().string()] = ReadFile(entry.path());
  }
  return files;
}

}  // namespace odomcal
