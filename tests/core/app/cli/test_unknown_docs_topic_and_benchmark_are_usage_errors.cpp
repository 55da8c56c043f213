// Issue 36 item 13: `docs nosuch` and `bench nosuch` exit alike: status 2 (the usage class, as ctl's
// exit codes), one line naming the word refused and the known ones; nothing on standard output.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

TEST(UnknownTopic, DocsAndBenchExitAsAUsageError) {
  const testing::CommandResult docs = testing::run_program({"docs", "nosuch"});
  const testing::CommandResult bench = testing::run_program({"bench", "nosuch"});
  EXPECT_EQ(docs.status, 2) << docs.out;
  EXPECT_EQ(bench.status, docs.status) << bench.out;
  EXPECT_EQ(docs.out, "rescue-motion docs: unknown topic 'nosuch' (known: fsm, tasks, shared-memory)\n");
  EXPECT_EQ(bench.out.rfind("rescue-motion bench: unknown benchmark 'nosuch' (known: nic, ", 0), 0U) << bench.out;
  // Standard output stays empty: a script reads only the error.
  EXPECT_TRUE(testing::run_program({"docs", "nosuch"}, false).out.empty());
  EXPECT_TRUE(testing::run_program({"bench", "nosuch"}, false).out.empty());
}

TEST(UnknownTopic, DocsRefusesAnUnknownFormatOrMachineAsAUsageError) {
  const testing::CommandResult format = testing::run_program({"docs", "fsm", "--format", "svg"});
  EXPECT_EQ(format.status, 2) << format.out;
  EXPECT_EQ(format.out, "rescue-motion docs: unknown --format 'svg' (known: markdown, dot)\n");
  const testing::CommandResult machine = testing::run_program({"docs", "fsm", "--machine", "nosuch"});
  EXPECT_EQ(machine.status, 2) << machine.out;
  EXPECT_EQ(machine.out, "rescue-motion docs: unknown --machine 'nosuch' (see rescue-motion docs fsm)\n");
}

}  // namespace
}  // namespace rescue::app
