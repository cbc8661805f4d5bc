// Processes are started with posix_spawnp (no shell, so image paths with
// spaces or quotes are safe); stdout and stderr go to the stage's log file,
// and GLOG_logtostderr keeps COLMAP's glog files out of the system temp
// folder. A stage is marked finished only after a zero exit status.

#include "odomcal/plugin/colmap_runner.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <regex>
#include <sstream>
#include <thread>
#include <utility>

extern char** environ;

namespace odomcal {
namespace {

namespace fs = std::filesystem;

constexpr int kExitNotFound = 127;

std::string JoinQuoted(const std::vector<std::string>& argv) {
  std::string joined;
  for (const std::string& argument : argv) {
    joined += (joined.empty() ? "" : " ") + ShellQuote(argument);
  }
  return joined;
}

std::string ReadWholeFile(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

// FNV-1a, 64 bit: a digest that stays the same across builds and runs.
std::string ContentDigest(const std::string& content) {
  uint64_t hash = 14695981039346656037ull;
  for (const unsigned char c : content) {
    hash = (hash ^ c) * 1099511628211ull;
  }
  std::ostringstream text;
  text << std::hex << std::setw(16) << std::setfill('0') << hash;
  return text.str();
}

// The last line that says something: glog's stack trace after a failed
// CHECK ("*** Check failure stack trace: ***", "    @ 0x...") is skipped so
// that the "Check failed: ..." line is the one quoted.
std::string LastNonEmptyLine(const fs::path& path) {
  std::ifstream file(path);
  std::string line, last;
  while (std::getline(file, line)) {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line.compare(first, 2, "@ ") == 0 ||
        line.compare(first, 4, "*** ") == 0) {
      continue;
    }
    last = line;
  }
  return last;
}

// Runs argv with stdout/stderr appended to log_path; returns the exit code
// (128 + signal for a signal, 127 when the program cannot be started).
// Reads the lines appended to a log file since the last call.
class LogFollower {
 public:
  LogFollower(fs::path path, const OutputLineCallback& on_line)
      : path_(std::move(path)), on_line_(on_line) {}

  void Poll() {
    if (!on_line_) return;
    std::ifstream file(path_, std::ios::binary);
    if (!file) return;
    file.seekg(offset_);
    std::string chunk((std::istreambuf_iterator<char>(file)),
                      std::istreambuf_iterator<char>());
    offset_ += static_cast<std::streamoff>(chunk.size());
    pending_ += chunk;
    size_t end;
    while ((end = pending_.find_first_of("\n\r")) != std::string::npos) {
      const std::string line = pending_.substr(0, end);
      pending_.erase(0, end + 1);
      if (!line.empty()) on_line_(line);
    }
  }

  // The last line, also without its end of line.
  void Finish() {
    Poll();
    if (on_line_ && !pending_.empty()) on_line_(pending_);
    pending_.clear();
  }

 private:
  fs::path path_;
  const OutputLineCallback& on_line_;
  std::streamoff offset_ = 0;
  std::string pending_;
};

int Spawn(const std::vector<std::string>& argv,
          const fs::path& log_path,
          const OutputLineCallback& on_line = {}) {
  const int log_fd =
      ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (log_fd < 0) {
    throw ColmapError(log_path.string() + ": cannot open the log file (" +
                      std::strerror(errno) + ")");
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, log_fd, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, log_fd, STDERR_FILENO);
  posix_spawn_file_actions_addopen(
      &actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);

  std::vector<std::string> environment;
  for (char** entry = environ; *entry != nullptr; ++entry) {
    if (std::strncmp(*entry, "GLOG_logtostderr=", 17) != 0) {
      environment.emplace_back(*entry);
    }
  }
  environment.emplace_back("GLOG_logtostderr=1");
  std::vector<char*> env_pointers;
  for (std::string& entry : environment) env_pointers.push_back(entry.data());
  env_pointers.push_back(nullptr);
  std::vector<std::string> argv_copy = argv;
  std::vector<char*> argv_pointers;
  for (std::string& argument : argv_copy)
    argv_pointers.push_back(argument.data());
  argv_pointers.push_back(nullptr);

  pid_t pid = 0;
  const int spawn_error = posix_spawnp(&pid,
                                       argv_pointers[0],
                                       &actions,
                                       nullptr,
                                       argv_pointers.data(),
                                       env_pointers.data());
  posix_spawn_file_actions_destroy(&actions);
  ::close(log_fd);
  if (spawn_error != 0) {
    return kExitNotFound;
  }
  // With a listener, the log is read every quarter second while COLMAP runs.
  LogFollower follower(log_path, on_line);
  int status = 0;
  for (;;) {
    const pid_t waited = ::waitpid(pid, &status, on_line ? WNOHANG : 0);
    if (waited == pid) break;
    if (waited < 0 && errno != EINTR) {
      throw ColmapError(std::string("waitpid failed: ") + std::strerror(errno));
    }
    if (waited == 0) {
      try {
        follower.Poll();
      } catch (...) {
        // The listener threw (e.g. a Python progress callback raised): stop
        // COLMAP and reap it before the exception leaves.
        ::kill(pid, SIGTERM);
        while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
        throw;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
    }
  }
  follower.Finish();
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

}  // namespace

bool ColmapVersion::AtLeast(int major_at_least, int minor_at_least) const {
  return major > major_at_least ||
         (major == major_at_least && minor >= minor_at_least);
}

ColmapVersion ParseColmapVersion(const std::string& banner) {
  static const std::regex kPattern(R"(COLMAP\s+(\d+)\.(\d+)(?:\.(\d+))?)");
  std::smatch match;
  if (!std::regex_search(banner, match, kPattern)) {
    throw ColmapError("cannot read the COLMAP version from '" + banner + "'");
  }
  ColmapVersion version;
  version.major = std::stoi(match[1]);
  version.minor = std::stoi(match[2]);
  version.patch = match[3].matched ? std::stoi(match[3]) : 0;
  version.banner = banner;
  return version;
}

std::string FeatureExtractionPrefix(const ColmapVersion& version) {
  return version.AtLeast(3, 13) ? "FeatureExtraction" : "SiftExtraction";
}

std::string FeatureMatchingPrefix(const ColmapVersion& version) {
  return version.AtLeast(3, 13) ? "FeatureMatching" : "SiftMatching";
}

std::string ShellQuote(const std::string& argument) {
  if (!argument.empty() &&
      argument.find_first_not_of(
          "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
          "0123456789_-./=:,+") == std::string::npos) {
    return argument;
  }
  std::string quoted = "'";
  for (const char c : argument) {
    quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  }
  return quoted + "'";
}

ColmapRunner::ColmapRunner(Options options) : options_(std::move(options)) {
  std::error_code error;
  if (!fs::is_directory(options_.workspace, error)) {
    throw ColmapError(options_.workspace + ": workspace folder does not exist");
  }
  fs::create_directories(fs::path(options_.workspace) / "logs", error);
  fs::create_directories(fs::path(options_.workspace) / "stages", error);
  if (error) {
    throw ColmapError(options_.workspace +
                      ": cannot create logs/ and stages/ (" + error.message() +
                      ")");
  }
}

const ColmapVersion& ColmapRunner::Version() {
  if (version_known_) return version_;
  const fs::path log =
      fs::path(options_.workspace) / "logs" / "colmap_help.log";
  std::error_code error;
  fs::remove(log, error);
  const int code = Spawn({options_.executable, "help"}, log);
  if (code == kExitNotFound) {
    throw ColmapError("COLMAP not found: '" + options_.executable +
                      "' is not an executable on PATH (install Debian's colmap "
                      "package or pass --colmap_path)");
  }
  std::istringstream text(ReadWholeFile(log));
  std::string first_line;
  std::getline(text, first_line);
  version_ = ParseColmapVersion(first_line);
  version_known_ = true;
  return version_;
}

std::string ColmapRunner::CommandLine(
    const std::vector<std::string>& arguments) const {
  std::vector<std::string> argv = {options_.executable};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  return JoinQuoted(argv);
}

// The command line, then per list file the stage reads (the value of an
// option ending in "_list_path": image and match lists) its digest: a rerun
// whose list changed is not the same stage, even when the argv is, and
// this holds across runs (a run stopped between writing a list and running
// its stage leaves the old record behind).
std::string ColmapRunner::StageRecord(
    const std::vector<std::string>& arguments) const {
  std::string record = CommandLine(arguments) + "\n";
  for (size_t k = 0; k + 1 < arguments.size(); ++k) {
    const std::string& option = arguments[k];
    const std::string suffix = "_list_path";
    if (option.size() > suffix.size() &&
        option.compare(option.size() - suffix.size(), suffix.size(), suffix) ==
            0) {
      record += "input " + arguments[k + 1] + " " +
                ContentDigest(ReadWholeFile(arguments[k + 1])) + "\n";
    }
  }
  return record;
}

bool ColmapRunner::WillReuse(const std::string& stage,
                             const std::vector<std::string>& arguments,
                             const std::vector<std::string>& outputs) const {
  const fs::path marker =
      fs::path(options_.workspace) / "stages" / (stage + ".done");
  if (!options_.reuse_finished_stages || !reuse_allowed_ ||
      !fs::exists(marker) || ReadWholeFile(marker) != StageRecord(arguments)) {
    return false;
  }
  return std::all_of(
      outputs.begin(), outputs.end(), [](const std::string& output) {
        return fs::exists(output);
      });
}

ColmapStageResult ColmapRunner::RunStage(
    const std::string& stage,
    const std::vector<std::string>& arguments,
    const std::vector<std::string>& outputs) {
  std::vector<std::string> argv = {options_.executable};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  const std::string command_line = JoinQuoted(argv);
  const fs::path workspace(options_.workspace);
  const fs::path marker = workspace / "stages" / (stage + ".done");
  ColmapStageResult result;
  result.log_path = (workspace / "logs" / (stage + ".log")).string();
  if (WillReuse(stage, arguments, outputs)) {
    result.reused = true;
    return result;
  }
  reuse_allowed_ = false;
  std::error_code error;
  fs::remove(marker, error);
  fs::remove(result.log_path, error);
  {
    std::ofstream commands(workspace / "commands.txt", std::ios::app);
    commands << command_line << "\n";
  }
  const auto start = std::chrono::steady_clock::now();
  const int code = Spawn(argv, result.log_path, options_.on_output_line);
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  if (code == kExitNotFound) {
    throw ColmapError("COLMAP not found: '" + options_.executable +
                      "' is not an executable on PATH (install Debian's colmap "
                      "package or pass --colmap_path)");
  }
  if (code != 0) {
    const std::string last = LastNonEmptyLine(result.log_path);
    const std::string why =
        code == 134 ? " (COLMAP aborted on a failed CHECK)" : "";
    throw ColmapError("COLMAP " + (arguments.empty() ? stage : arguments[0]) +
                      " failed with exit code " + std::to_string(code) + why +
                      "; see " + result.log_path +
                      (last.empty() ? "" : " (last line: " + last + ")"));
  }
  std::ofstream(marker) << StageRecord(arguments);
  return result;
}

}  // namespace odomcal
