// Runs the marchcheck binary (or any shell command) as a user would and keeps its exit status and output.
#pragma once

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

struct CommandRun {
  int status;
  std::string output;  // stdout and stderr together
};

inline CommandRun run_shell(const std::string& command) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

inline CommandRun run(const std::string& args) { return run_shell(std::string(MARCHCHECK_BINARY) + " " + args); }
