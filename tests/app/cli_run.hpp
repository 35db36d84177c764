#pragma once
// Running the needlesim binary from a test: exit code and everything it printed.
#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace needlesim::test {

struct CliResult {
  int code = -1;
  std::string out;  // stdout and stderr together
};

inline CliResult runCli(const std::string& args) {
  const std::string cmd = std::string(NEEDLESIM_BINARY) + " " + args + " 2>&1";
  CliResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), buf.size(), p)) r.out += buf.data();
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace needlesim::test
