// Runs the built odomcal executable in a child process, for the CLI tests
// (ODOMCAL_EXECUTABLE is the test target's compile definition): fork/exec
// without a shell, so that a test can set the child's environment or limit
// the size of the files it may write, and assertions on its one error line.
#pragma once

#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace odomcal {

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

struct RunLimits {
  std::vector<std::string> environment;  // "NAME=value", set in the child
  rlim_t max_file_size_bytes = RLIM_INFINITY;
};

inline void WriteFile(const std::filesystem::path& path,
                      const std::string& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file << bytes;
  ASSERT_TRUE(file.good()) << path;
}

// Runs the odomcal executable with `arguments`. Output goes through pipes,
// which RLIMIT_FSIZE does not limit, so only the files odomcal writes itself
// are subject to `limits.max_file_size_bytes`.
inline CommandResult RunOdomcal(const std::vector<std::string>& arguments,
                                const RunLimits& limits = {}) {
  int out_pipe[2], err_pipe[2];
  if (::pipe(out_pipe) != 0 || ::pipe(err_pipe) != 0) {
    ADD_FAILURE() << "pipe failed";
    return {};
  }
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(out_pipe[1], STDOUT_FILENO);
    ::dup2(err_pipe[1], STDERR_FILENO);
    for (const int fd : {out_pipe[0], out_pipe[1], err_pipe[0], err_pipe[1]}) {
      ::close(fd);
    }
    for (const std::string& entry : limits.environment) {
      const size_t equals = entry.find('=');
      ::setenv(
          entry.substr(0, equals).c_str(), entry.substr(equals + 1).c_str(), 1);
    }
    if (limits.max_file_size_bytes != RLIM_INFINITY) {
      // A full disk, honestly: write() fails with EFBIG past the limit
      // instead of the default SIGXFSZ, which would kill odomcal.
      const rlimit limit = {limits.max_file_size_bytes,
                            limits.max_file_size_bytes};
      ::setrlimit(RLIMIT_FSIZE, &limit);
      std::signal(SIGXFSZ, SIG_IGN);
    }
    std::vector<std::string> argv = {ODOMCAL_EXECUTABLE};
    argv.insert(argv.end(), arguments.begin(), arguments.end());
    std::vector<char*> pointers;
    for (std::string& argument : argv) pointers.push_back(argument.data());
    pointers.push_back(nullptr);
    ::execv(pointers[0], pointers.data());
    ::_exit(127);
  }
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);
  CommandResult result;
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  std::string* sinks[2] = {&result.out, &result.err};
  int open_pipes = 2;
  while (open_pipes > 0) {
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int k = 0; k < 2; ++k) {
      if (fds[k].fd < 0 || fds[k].revents == 0) continue;
      char buffer[4096];
      const ssize_t n = ::read(fds[k].fd, buffer, sizeof(buffer));
      if (n > 0) {
        sinks[k]->append(buffer, static_cast<size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        ::close(fds[k].fd);
        fds[k].fd = -1;
        --open_pipes;
      }
    }
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  result.exit_code =
      WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

// Exit code 2 and exactly `line` on stderr.
inline void ExpectBadInput(const CommandResult& run, const std::string& line) {
  EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
  EXPECT_EQ(run.err, line + "\n");
}

// Exit code 2 and one line on stderr that starts with `prefix` and contains
// every one of `parts` (for messages that quote COLMAP's or the system's
// wording).
inline void ExpectBadInputContaining(const CommandResult& run,
                                     const std::string& prefix,
                                     const std::vector<std::string>& parts) {
  EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_EQ(run.err.rfind(prefix, 0), 0u) << run.err;
  for (const std::string& part : parts) {
    EXPECT_NE(run.err.find(part), std::string::npos) << part << "\n" << run.err;
  }
}

}  // namespace odomcal
