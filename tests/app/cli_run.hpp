#pragma once
// Running the needlesim binary (or a shell line) from a test: exit code and everything it printed.
#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

namespace needlesim::test {

struct CliResult {
  int code = -1;    // exit code; -signal for a program ended by a signal
  std::string out;  // stdout and stderr together
};

inline CliResult runShell(const std::string& command) {
  const std::string cmd = command + " 2>&1";
  CliResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), buf.size(), p)) r.out += buf.data();
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (r.code >= 128) r.code = -(r.code - 128);  // sh reports a signal as 128 + its number
  return r;
}

inline CliResult runCli(const std::string& args) { return runShell(std::string(NEEDLESIM_BINARY) + " " + args); }

// Starts the CLI with `args` in a child process (stdout and stderr to `log`); its pid (to signal and wait for).
inline pid_t startCli(const std::string& args, const std::filesystem::path& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string cmd = "exec " + std::string(NEEDLESIM_BINARY) + " " + args + " > '" + log.string() + "' 2>&1";
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

}  // namespace needlesim::test
