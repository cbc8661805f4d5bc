// Processes are started with posix_spawnp (no shell, so image paths with
// spaces or quotes are safe); stdout and stderr go to the stage's log file,
// and GLOG_logtostderr keeps COLMAP's glog files out of the system temp
// folder. A stage is marked finished only after a zero exit status.

#include "odomcal/plugin/colmap/colmap_runner.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
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

// Reads the lines appended to a log file since the last call.
class LogFollower {
 public:
  explicit LogFollower(fs::path path) : path_(std::move(path)) {}

  // The complete lines appended since the last call, to `on_line`; nothing
  // is read without a listener, so a later one gets every line.
  void Poll(const OutputLineCallback& on_line) {
    if (!on_line) return;
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
      if (!line.empty()) on_line(line);
    }
  }

  // The rest, the last line also without its end of line.
  void Finish(const OutputLineCallback& on_line) {
    Poll(on_line);
    if (on_line && !pending_.empty()) on_line(pending_);
    pending_.clear();
  }

 private:
  fs::path path_;
  std::streamoff offset_ = 0;
  std::string pending_;
};

// Starts argv with stdout/stderr appended to log_path; -1 when the program
// cannot be started.
pid_t Spawn(const std::vector<std::string>& argv, const fs::path& log_path) {
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
  env_pointers.reserve(environment.size() + 1);
  for (std::string& entry : environment) env_pointers.push_back(entry.data());
  env_pointers.push_back(nullptr);
  std::vector<std::string> argv_copy = argv;
  std::vector<char*> argv_pointers;
  argv_pointers.reserve(argv_copy.size() + 1);
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
  return spawn_error != 0 ? -1 : pid;
}

// The exit code of a waitpid status: 128 + signal for a signal.
int ExitCode(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

// Runs argv to the end; returns the exit code, 127 when the program cannot
// be started.
int RunToEnd(const std::vector<std::string>& argv, const fs::path& log_path) {
  const pid_t pid = Spawn(argv, log_path);
  if (pid < 0) return kExitNotFound;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      throw ColmapError(std::string("waitpid failed: ") + std::strerror(errno));
    }
  }
  return ExitCode(status);
}

std::string NotFoundMessage(const std::string& executable,
                            ColmapProgram program) {
  if (program == ColmapProgram::kGlomap) {
    return "GLOMAP not found: '" + executable +
           "' is not an executable on PATH (--mapper global runs COLMAP's "
           "global_mapper from COLMAP 4.0, and the standalone glomap before: "
           "install either, or pass --glomap_path)";
  }
  return "COLMAP not found: '" + executable +
         "' is not an executable on PATH (install Debian's colmap package or "
         "pass --colmap_path)";
}

// When `path` was last written, on the steady clock (now if unknown).
std::chrono::steady_clock::time_point LastWrite(const fs::path& path) {
  const auto steady_now = std::chrono::steady_clock::now();
  struct stat info;
  if (::stat(path.c_str(), &info) != 0) return steady_now;
  const auto written = std::chrono::system_clock::time_point(
      std::chrono::duration_cast<std::chrono::system_clock::duration>(
          std::chrono::seconds(info.st_mtim.tv_sec) +
          std::chrono::nanoseconds(info.st_mtim.tv_nsec)));
  const auto ago = std::chrono::system_clock::now() - written;
  return ago > std::chrono::system_clock::duration::zero()
             ? steady_now - std::chrono::duration_cast<
                                std::chrono::steady_clock::duration>(ago)
             : steady_now;
}

}  // namespace

bool ColmapVersion::AtLeast(int major_at_least, int minor_at_least) const {
  return major > major_at_least ||
         (major == major_at_least && minor >= minor_at_least);
}

std::string ColmapVersion::ToString() const {
  return std::to_string(major) + "." + std::to_string(minor) + "." +
         std::to_string(patch);
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

ColmapOptionNames ColmapOptionNamesFor(const ColmapVersion& version) {
  ColmapOptionNames names;
  names.extraction_max_num_features = "SiftExtraction.max_num_features";
  if (version.AtLeast(3, 13)) {
    names.extraction_use_gpu = "FeatureExtraction.use_gpu";
    names.extraction_num_threads = "FeatureExtraction.num_threads";
    names.matching_use_gpu = "FeatureMatching.use_gpu";
    names.matching_num_threads = "FeatureMatching.num_threads";
    names.mapper_image_list_path = "Mapper.image_list_path";
    names.mapper_random_seed = {"default_random_seed", "Mapper.random_seed"};
  } else {
    names.extraction_use_gpu = "SiftExtraction.use_gpu";
    names.extraction_num_threads = "SiftExtraction.num_threads";
    names.matching_use_gpu = "SiftMatching.use_gpu";
    names.matching_num_threads = "SiftMatching.num_threads";
    names.mapper_image_list_path = "image_list_path";
    names.mapper_random_seed = {"random_seed"};
  }
  return names;
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
  const int code = RunToEnd({options_.executable, "help"}, log);
  if (code == kExitNotFound) {
    throw ColmapError(
        NotFoundMessage(options_.executable, ColmapProgram::kColmap));
  }
  std::istringstream text(ReadWholeFile(log));
  std::string first_line;
  std::getline(text, first_line);
  version_ = ParseColmapVersion(first_line);
  version_known_ = true;
  return version_;
}

const std::string& ColmapRunner::Executable(ColmapProgram program) const {
  return program == ColmapProgram::kGlomap ? options_.glomap_executable
                                           : options_.executable;
}

std::string ColmapRunner::CommandLine(const std::vector<std::string>& arguments,
                                      ColmapProgram program) const {
  std::vector<std::string> argv = {Executable(program)};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  return JoinQuoted(argv);
}

// The command line, then per list file the stage reads (the value of an
// option ending in "_list_path": image and match lists) its digest: a rerun
// whose list changed is not the same stage, even when the argv is, and
// this holds across runs (a run stopped between writing a list and running
// its stage leaves the old record behind).
std::string ColmapRunner::StageRecord(const std::vector<std::string>& arguments,
                                      ColmapProgram program) const {
  std::string record = CommandLine(arguments, program) + "\n";
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
                             const std::vector<std::string>& outputs,
                             ColmapProgram program) const {
  const fs::path marker =
      fs::path(options_.workspace) / "stages" / (stage + ".done");
  if (!options_.reuse_finished_stages || !reuse_allowed_ ||
      !fs::exists(marker) ||
      ReadWholeFile(marker) != StageRecord(arguments, program)) {
    return false;
  }
  return std::all_of(
      outputs.begin(), outputs.end(), [](const std::string& output) {
        return fs::exists(output);
      });
}

struct RunningStage::State {
  std::string stage;
  std::string program;  // the COLMAP command, e.g. "mapper"
  ColmapProgram program_kind = ColmapProgram::kColmap;
  std::string executable;
  fs::path marker;
  std::string record;  // what the marker gets once the stage succeeded
  ColmapStageResult result;
  std::chrono::steady_clock::time_point start;
  pid_t pid = -1;  // -1: not running (reused, ended, or never started)
  bool ended = false;
  int exit_code = 0;
  std::string start_error;  // e.g. the log could not be opened
  std::unique_ptr<LogFollower> follower;
  bool* runner_reuse_allowed = nullptr;  // the runner's chain (see Finish)
};

RunningStage::RunningStage(std::unique_ptr<State> state)
    : state_(std::move(state)) {}
RunningStage::RunningStage(RunningStage&&) noexcept = default;
RunningStage& RunningStage::operator=(RunningStage&& other) noexcept {
  Stop();
  state_ = std::move(other.state_);
  return *this;
}
RunningStage::~RunningStage() { Stop(); }

void RunningStage::Stop() noexcept {
  if (!state_ || state_->pid < 0) return;
  ::kill(state_->pid, SIGTERM);
  int status = 0;
  while (::waitpid(state_->pid, &status, 0) < 0 && errno == EINTR) {
  }
  state_->pid = -1;
}

const std::string& RunningStage::stage() const { return state_->stage; }

bool RunningStage::Poll(const OutputLineCallback& on_line) {
  return Reap(on_line, WNOHANG);
}

bool RunningStage::Reap(const OutputLineCallback& on_line, int wait_options) {
  State& state = *state_;
  if (state.ended) return true;
  int status = 0;
  const pid_t waited = ::waitpid(state.pid, &status, wait_options);
  if (waited < 0 && errno != EINTR) {
    state.pid = -1;  // not ours any more: never signalled again
    throw ColmapError(std::string("waitpid failed: ") + std::strerror(errno));
  }
  if (waited != state.pid) {
    // A listener that throws (e.g. a Python progress callback raised) leaves
    // COLMAP to the destructor, which stops it.
    state.follower->Poll(on_line);
    return false;
  }
  state.pid = -1;
  state.ended = true;
  state.exit_code = ExitCode(status);
  // Noticed late when nobody polled for a while: COLMAP's last log line
  // tells when it ended.
  const auto end = std::max(state.start,
                            std::min(std::chrono::steady_clock::now(),
                                     LastWrite(state.result.log_path)));
  state.result.seconds =
      std::chrono::duration<double>(end - state.start).count();
  state.follower->Finish(on_line);
  return true;
}

void RunningStage::WaitForEnd(const OutputLineCallback& on_line) {
  if (!on_line) {
    while (!Reap(on_line, 0)) {
    }
    return;
  }
  while (!Poll(on_line)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
  }
}

double RunningStage::seconds() const { return state_->result.seconds; }

std::chrono::steady_clock::time_point RunningStage::started() const {
  return state_->start;
}

ColmapStageResult RunningStage::Finish() {
  const State& state = *state_;
  if (!state.ended) {
    throw std::logic_error("RunningStage::Finish before the stage ended");
  }
  if (state.result.reused) return state.result;
  // Ran anew: every stage started from now on runs anew too. (Not at the
  // start: stages started side by side do not depend on each other, and a
  // stage dropped unfinished leaves the chain as it was.)
  *state.runner_reuse_allowed = false;
  if (!state.start_error.empty()) throw ColmapError(state.start_error);
  if (state.exit_code == kExitNotFound) {
    throw ColmapError(NotFoundMessage(state.executable, state.program_kind));
  }
  if (state.exit_code != 0) {
    const std::string last = LastNonEmptyLine(state.result.log_path);
    const std::string why =
        state.exit_code == 134 ? " (COLMAP aborted on a failed CHECK)" : "";
    const char* name =
        state.program_kind == ColmapProgram::kGlomap ? "GLOMAP " : "COLMAP ";
    throw ColmapError(name + state.program + " failed with exit code " +
                      std::to_string(state.exit_code) + why + "; see " +
                      state.result.log_path +
                      (last.empty() ? "" : " (last line: " + last + ")"));
  }
  std::ofstream(state.marker) << state.record;
  return state.result;
}

RunningStage ColmapRunner::StartStage(const std::string& stage,
                                      const std::vector<std::string>& arguments,
                                      const std::vector<std::string>& outputs,
                                      ColmapProgram program) {
  auto state = std::make_unique<RunningStage::State>();
  const fs::path workspace(options_.workspace);
  state->stage = stage;
  state->program = arguments.empty() ? stage : arguments[0];
  state->program_kind = program;
  state->executable = Executable(program);
  state->marker = workspace / "stages" / (stage + ".done");
  state->result.log_path = (workspace / "logs" / (stage + ".log")).string();
  state->ended = true;
  if (WillReuse(stage, arguments, outputs, program)) {
    state->result.reused = true;
    return RunningStage(std::move(state));
  }
  state->runner_reuse_allowed = &reuse_allowed_;
  std::error_code error;
  fs::remove(state->marker, error);
  fs::remove(state->result.log_path, error);
  state->record = StageRecord(arguments, program);
  {
    std::ofstream commands(workspace / "commands.txt", std::ios::app);
    commands << CommandLine(arguments, program) << "\n";
  }
  std::vector<std::string> argv = {Executable(program)};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  state->start = std::chrono::steady_clock::now();
  try {
    state->pid = Spawn(argv, state->result.log_path);
  } catch (const ColmapError& failure) {
    state->start_error = failure.what();
    return RunningStage(std::move(state));
  }
  if (state->pid < 0) {
    state->exit_code = kExitNotFound;  // Finish says COLMAP is missing
    return RunningStage(std::move(state));
  }
  state->follower = std::make_unique<LogFollower>(state->result.log_path);
  state->ended = false;
  return RunningStage(std::move(state));
}

ColmapStageResult ColmapRunner::RunStage(
    const std::string& stage,
    const std::vector<std::string>& arguments,
    const std::vector<std::string>& outputs,
    ColmapProgram program) {
  RunningStage running = StartStage(stage, arguments, outputs, program);
  running.WaitForEnd(options_.on_output_line);
  return running.Finish();
}

}  // namespace odomcal
