// Runs a shell command from a test and collects its standard output and exit status (tests only:
// allocates freely). Used by the tests that compare our output with tshark's.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>
#include <vector>

namespace rescue::test {

struct CommandOutput {
  int exit_status{-1};  // -1 when the command could not be started or did not exit normally
  std::string out;
};

inline CommandOutput run_command(const std::string& command) {
  CommandOutput result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> chunk{};
  std::size_t n = 0;
  while ((n = std::fread(chunk.data(), 1, chunk.size(), pipe)) > 0) result.out.append(chunk.data(), n);
  const int status = pclose(pipe);
  if (status != -1 && WIFEXITED(status)) result.exit_status = WEXITSTATUS(status);
  return result;
}

// True when `program` is on PATH.
inline bool program_available(const std::string& program) {
  return run_command("command -v " + program + " >/dev/null 2>&1").exit_status == 0;
}

// The lines of `text` (without their newlines).
inline std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

}  // namespace rescue::test
