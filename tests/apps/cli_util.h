// Helpers of the end-to-end tests of the `splam` binary (SPLAM_BINARY).
#ifndef SPLAM_TESTS_APPS_CLI_UTIL_H_
#define SPLAM_TESTS_APPS_CLI_UTIL_H_

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "io/trajectory.h"

namespace splam::cli_test {

namespace fs = std::filesystem;

struct Output {
  int status = -1;
  std::string text;  // stdout and stderr
};

// Runs a shell command and collects its standard output; *wait_status is what waitpid says of
// it (WIFEXITED, WTERMSIG), -1 when it could not start.
inline std::string Shell(const std::string& command, int* wait_status) {
  std::string text;
  *wait_status = -1;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return text;
  std::array<char, 4096> buffer;
  while (std::size_t n = fread(buffer.data(), 1, buffer.size(), pipe))
    text.append(buffer.data(), n);
  *wait_status = pclose(pipe);
  return text;
}

// Runs `splam args` (in directory `cwd` when given) and collects its output and exit status.
inline Output Splam(const std::string& args, const fs::path& cwd = {}) {
  const std::string command = (cwd.empty() ? "" : "cd '" + cwd.string() + "' && ") +
                              std::string(SPLAM_BINARY) + " " + args + " 2>&1";
  Output out;
  int status = 0;
  out.text = Shell(command, &status);
  out.status = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

inline fs::path Temp(const std::string& name) {
  const fs::path p = fs::path(::testing::TempDir()) / ("splam_cli_" + name);
  fs::remove_all(p);
  return p;
}

// Writes `text` to dir/name and returns the path.
inline std::string WriteIn(const fs::path& dir, const std::string& name, const std::string& text) {
  EXPECT_EQ(io::WriteTextFile((dir / name).string(), text).message(), "");
  return (dir / name).string();
}

inline std::string Slurp(const fs::path& p) {
  std::string text;
  EXPECT_EQ(io::ReadTextFile(p.string(), &text).message(), "") << p;
  return text;
}

// Runs splam with `args` (output discarded), sends it `signal` once `ready()` holds (polled every
// 20 ms; at the latest after 120 s), and returns its exit status (-1 when a signal ended it).
inline int SplamInterruptedWhen(const std::string& args, const std::function<bool()>& ready,
                                int signal = SIGINT) {
  const std::string command =
      std::string("exec ") + SPLAM_BINARY + " " + args + " > /dev/null 2>&1";
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto start = std::chrono::steady_clock::now();
  while (!ready() && std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(pid, signal);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs splam with `args`, its standard output and error into a pipe, and sends it each signal
// of `signals` in turn as soon as the output has said its text (the texts in the order said).
// Returns the exit status (-1 when a signal ended it).
inline int SplamSignalledWhenSaid(const std::string& args,
                                  const std::vector<std::pair<std::string, int>>& signals) {
  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) return -2;
  const std::string command = std::string("exec ") + SPLAM_BINARY + " " + args + " 2>&1";
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(pipe_fds[1], 1);
    close(pipe_fds[0]);
    close(pipe_fds[1]);
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  close(pipe_fds[1]);
  std::string said;
  std::array<char, 256> buffer;
  std::size_t from = 0;
  for (const auto& [text, signal] : signals) {
    std::size_t at = std::string::npos;
    for (ssize_t n; (at = said.find(text, from)) == std::string::npos &&
                    (n = read(pipe_fds[0], buffer.data(), buffer.size())) > 0;)
      said.append(buffer.data(), static_cast<std::size_t>(n));
    if (at == std::string::npos) break;  // it ended without saying it
    from = at + text.size();
    kill(pid, signal);
  }
  while (read(pipe_fds[0], buffer.data(), buffer.size()) > 0) {
  }
  close(pipe_fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The same, SIGINT after `after`.
inline int SplamInterrupted(const std::string& args, std::chrono::milliseconds after) {
  const auto start = std::chrono::steady_clock::now();
  return SplamInterruptedWhen(args,
                              [&] { return std::chrono::steady_clock::now() - start >= after; });
}

}  // namespace splam::cli_test

#endif  // SPLAM_TESTS_APPS_CLI_UTIL_H_
