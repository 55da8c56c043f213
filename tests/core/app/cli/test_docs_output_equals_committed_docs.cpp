// docs/fsm.md, docs/tasks.md and docs/shared-memory.md hold the output of `rescue-motion docs
// fsm|tasks|shared-memory` between BEGIN/END
// GENERATED markers. This
// test runs the built program and requires the committed blocks to equal what it prints now, so the
// documented tables cannot drift from the tables the firmware runs. To refresh the docs after changing
// a table, paste the command's output between the markers (the failure message prints it).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace {

std::string run(const std::string& command) {
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return out;
  char buf[4096];
  std::size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  EXPECT_EQ(pclose(pipe), 0) << command;
  return out;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Text between the line "<!-- BEGIN GENERATED: <command> -->" and the next "<!-- END GENERATED -->",
// without a surrounding ```dot fence.
std::string generated_block(const std::string& doc, const std::string& command) {
  const std::string begin = "<!-- BEGIN GENERATED: " + command + " -->\n";
  const std::size_t start = doc.find(begin);
  if (start == std::string::npos) return "(no block for: " + command + ")";
  const std::size_t body = start + begin.size();
  const std::size_t end = doc.find("<!-- END GENERATED -->", body);
  if (end == std::string::npos) return "(unterminated block for: " + command + ")";
  std::string text = doc.substr(body, end - body);
  const std::string fence_open = "```dot\n";
  const std::string fence_close = "```\n";
  if (text.compare(0, fence_open.size(), fence_open) == 0 && text.size() >= fence_open.size() + fence_close.size() &&
      text.compare(text.size() - fence_close.size(), fence_close.size(), fence_close) == 0) {
    text = text.substr(fence_open.size(), text.size() - fence_open.size() - fence_close.size());
  }
  return text;
}

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
const std::string kDoc = std::string(RESCUE_SOURCE_DIR) + "/docs/fsm.md";
const std::string kTasksDoc = std::string(RESCUE_SOURCE_DIR) + "/docs/tasks.md";
const std::string kSharedMemoryDoc = std::string(RESCUE_SOURCE_DIR) + "/docs/shared-memory.md";
const std::string kMasterDoc = std::string(RESCUE_SOURCE_DIR) + "/docs/master.md";

TEST(DocsFsm, MarkdownInDocsEqualsCommandOutput) {
  const std::string printed = run(kProgram + " docs fsm --format markdown");
  ASSERT_FALSE(printed.empty());
  EXPECT_EQ(generated_block(read_file(kDoc), "rescue-motion docs fsm --format markdown"), printed)
      << "docs/fsm.md is stale; put this between its markdown markers:\n" << printed;
}

TEST(DocsFsm, DotDiagramInDocsEqualsCommandOutput) {
  const std::string printed = run(kProgram + " docs fsm --format dot");
  ASSERT_FALSE(printed.empty());
  EXPECT_EQ(generated_block(read_file(kDoc), "rescue-motion docs fsm --format dot"), printed)
      << "docs/fsm.md is stale; put this between its dot markers:\n" << printed;
}

TEST(DocsFsm, RecoveryMachineInMasterDocEqualsCommandOutput) {
  const std::string printed = run(kProgram + " docs fsm --machine slave_recovery");
  ASSERT_NE(printed.find("### State machine `slave_recovery`"), std::string::npos) << printed;
  EXPECT_EQ(generated_block(read_file(kMasterDoc), "rescue-motion docs fsm --machine slave_recovery"), printed)
      << "docs/master.md is stale; put this between its markers:\n" << printed;
}

TEST(DocsTasks, TaskTableInDocsEqualsCommandOutput) {
  const std::string printed = run(kProgram + " docs tasks");
  ASSERT_NE(printed.find("| EtherCAT handler | SCHED_FIFO "), std::string::npos) << printed;
  // The scheduling applied (issue 36 item 9): the socket handler and the message parser run
  // SCHED_OTHER unless a configuration file sets their priority.
  EXPECT_NE(printed.find("| socket handler | SCHED_OTHER "), std::string::npos) << printed;
  EXPECT_NE(printed.find("| message parser | SCHED_OTHER "), std::string::npos) << printed;
  EXPECT_EQ(generated_block(read_file(kTasksDoc), "rescue-motion docs tasks"), printed)
      << "docs/tasks.md is stale; put this between its markers:\n" << printed;
}

TEST(DocsSharedMemory, ByteMapInDocsEqualsCommandOutput) {
  const std::string printed = run(kProgram + " docs shared-memory");
  ASSERT_NE(printed.find("| `samples` |"), std::string::npos) << printed;
  EXPECT_EQ(generated_block(read_file(kSharedMemoryDoc), "rescue-motion docs shared-memory"), printed)
      << "docs/shared-memory.md is stale; put this between its markers:\n" << printed;
}

TEST(DocsFsm, UnknownTopicOrFormatFailsWithOneLineReason) {
  EXPECT_NE(std::system((kProgram + " docs nothing >/dev/null 2>&1").c_str()), 0);
  EXPECT_NE(std::system((kProgram + " docs fsm --format pdf >/dev/null 2>&1").c_str()), 0);
  EXPECT_NE(std::system((kProgram + " docs fsm --machine nope >/dev/null 2>&1").c_str()), 0);
}

}  // namespace
