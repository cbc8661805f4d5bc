#include "odomcal/plugin/output/output_file.h"

#include "odomcal/adapters/robot_output_marker.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace odomcal {

void CheckOutputPath(const std::string& path, bool overwrite) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (path.empty()) {
    throw OutputError("output path is empty");
  }
  const fs::path target(path);
  if (fs::exists(target, error) && !overwrite) {
    throw OutputError(path + ": exists (pass --overwrite to replace it)");
  }
  if (fs::is_directory(target, error)) {
    throw OutputError(path + ": is a directory");
  }
  if (fs::exists(target, error) && !IsOdomcalResultFile(path)) {
    throw OutputError(
        path +
        ": exists and is not an odomcal result; --overwrite replaces only "
        "odomcal's own files");
  }
  const fs::path parent =
      target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (fs::exists(parent, error) && !fs::is_directory(parent, error)) {
    throw OutputError(path + ": " + parent.string() + " is not a folder");
  }
  if (!fs::is_directory(parent, error)) {
    throw OutputError(path + ": folder " + parent.string() + " does not exist");
  }
}

bool IsOdomcalResultFile(const std::string& path) {
  namespace fs = std::filesystem;
  constexpr uintmax_t kMaxResultBytes = 64 << 20;  // results are kilobytes
  std::error_code error;
  if (!fs::is_regular_file(path, error) ||
      fs::file_size(path, error) > kMaxResultBytes) {
    return false;
  }
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  const std::string text = buffer.str();
  if (text.rfind(std::string("<!-- ") + kRobotOutputMarker, 0) == 0 ||
      text.rfind(std::string("# ") + kRobotOutputMarker, 0) == 0) {
    return true;  // a robot file (robot_description.h)
  }
  if (text.rfind("%YAML:1.0\n---\nstatus: ", 0) == 0) {
    return text.find("\nunobservable:") != std::string::npos;
  }
  const nlohmann::json json =
      nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  return json.is_object() && json.contains("schema") &&
         json["schema"].is_string() &&
         json["schema"].get<std::string>().rfind("odomcal.", 0) == 0;
}

void WriteFileAtomically(const std::string& path, const std::string& contents) {
  std::string temporary = path + ".tmp.XXXXXX";
  const int fd = mkstemp(temporary.data());
  if (fd < 0) {
    throw OutputError(path + ": cannot create a temporary file (" +
                      std::strerror(errno) + ")");
  }
  size_t written = 0;
  while (written < contents.size()) {
    const ssize_t n =
        ::write(fd, contents.data() + written, contents.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      const std::string reason = std::strerror(errno);
      ::close(fd);
      std::remove(temporary.c_str());
      throw OutputError(path + ": write failed (" + reason + ")");
    }
    written += static_cast<size_t>(n);
  }
  // mkstemp creates 0600; outputs are ordinary files.
  if (::fchmod(fd, 0644) != 0 || ::fsync(fd) != 0 || ::close(fd) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw OutputError(path + ": write failed (" + reason + ")");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw OutputError(path + ": cannot move the finished file into place (" +
                      reason + ")");
  }
}

std::string ReplaceExtension(const std::string& path,
                             const std::string& extension) {
  return std::filesystem::path(path).replace_extension(extension).string();
}

}  // namespace odomcal
