// Issue 36 item 10: `run --check` is not silent while it works: a line per phase (bringing the
// network up, SAFE-OP, OP, back to INIT), each flushed when written, so a pipe has it before the
// verdict; stdout keeps its one verdict line.
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "core/app/runtime/self_check.hpp"
#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

// Where `what` begins in `text`, npos when absent.
std::size_t at(const std::string& text, const char* what) { return text.find(what); }

void expect_phases_in_order(const std::string& text) {
  const std::size_t up = at(text, "rescue-motion run --check: bringing the network up (nic sim)\n");
  const std::size_t safe_op = at(text, " slaves in SAFE-OP after ");
  const std::size_t op = at(text, "rescue-motion run --check: OP after ");
  const std::size_t init = at(text, "rescue-motion run --check: back to INIT\n");
  ASSERT_NE(up, std::string::npos) << text;
  ASSERT_NE(safe_op, std::string::npos) << text;
  ASSERT_NE(op, std::string::npos) << text;
  ASSERT_NE(init, std::string::npos) << text;
  EXPECT_LT(up, safe_op);
  EXPECT_LT(safe_op, op);
  EXPECT_LT(op, init);
}

TEST(RunCheckProgress, EachPhaseLineIsInThePipeBeforeTheStreamIsClosed) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  ASSERT_EQ(::fcntl(fds[0], F_SETFL, O_NONBLOCK), 0);
  // A stream on a pipe is block-buffered: only a flush per line puts the lines in the pipe now.
  std::FILE* progress = ::fdopen(fds[1], "w");
  ASSERT_NE(progress, nullptr);
  std::FILE* verdict = std::tmpfile();
  ASSERT_NE(verdict, nullptr);
  SelfCheckOptions options;
  options.progress = progress;
  ASSERT_EQ(run_self_check(options, verdict, nullptr), 0);
  std::string piped;
  char buffer[4096];
  for (ssize_t n = ::read(fds[0], buffer, sizeof buffer); n > 0; n = ::read(fds[0], buffer, sizeof buffer)) {
    piped.append(buffer, static_cast<std::size_t>(n));
  }
  expect_phases_in_order(piped);
  // The verdict stays apart: one line on its own stream.
  std::rewind(verdict);
  char line[512];
  ASSERT_NE(std::fgets(line, sizeof line, verdict), nullptr);
  EXPECT_EQ(std::string(line).rfind("rescue-motion run --check: OK: nic sim", 0), 0U) << line;
  EXPECT_EQ(std::fgets(line, sizeof line, verdict), nullptr) << "one verdict line only";
  (void)std::fclose(verdict);
  (void)std::fclose(progress);
  (void)::close(fds[0]);
}

TEST(RunCheckProgress, TheCommandPrintsThePhasesOnStderrAndTheVerdictLast) {
  const std::string binary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
  const test::CommandOutput both = test::run_command(binary + " run --check 2>&1");
  ASSERT_EQ(both.exit_status, 0) << both.out;
  expect_phases_in_order(both.out);
  EXPECT_LT(at(both.out, "back to INIT\n"), at(both.out, "rescue-motion run --check: OK: ")) << both.out;
  const test::CommandOutput only_stdout = test::run_command(binary + " run --check 2>/dev/null");
  EXPECT_EQ(at(only_stdout.out, "bringing the network up"), std::string::npos) << only_stdout.out;
  EXPECT_NE(at(only_stdout.out, "rescue-motion run --check: OK: "), std::string::npos) << only_stdout.out;
}

}  // namespace
}  // namespace rescue::app
