// The grid printed from the joint DFA's table (what docs/fsm.md shows) is the design brief's section 5
// table, character for character.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "fsm/machines/joint_status_dfa.hpp"
#include "fsm/engine/table_docs.hpp"

namespace rescue::fsm {
namespace {

std::string printed_grid() {
  char* buf = nullptr;
  std::size_t len = 0;
  FILE* out = open_memstream(&buf, &len);
  EXPECT_NE(out, nullptr);
  write_markdown_grid(out, ViewOf<JointStatusDfa>::view());
  std::fclose(out);
  std::string text(buf, len);
  std::free(buf);
  return text;
}

TEST(JointDfaDocs, PrintedGridEqualsTheBriefsTable) {
  const std::string path = std::string(RESCUE_SHARED_DIR) + "/DESIGN-BRIEF.md";
  std::ifstream in(path);
  if (!in) GTEST_SKIP() << "design brief not found at " << path << " (../shared is not part of the repository)";
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string brief = ss.str();
  const std::size_t start = brief.find("| from \\ input |");
  ASSERT_NE(start, std::string::npos) << "the brief has no joint DFA table";
  // The table runs until the first line that does not start with '|'.
  std::size_t end = start;
  while (end < brief.size() && brief[end] == '|') end = brief.find('\n', end) + 1;
  EXPECT_EQ(printed_grid(), brief.substr(start, end - start));
}

TEST(JointDfaDocs, GridHasOneLinePerStatePlusHeader) {
  const std::string grid = printed_grid();
  int lines = 0;
  for (char c : grid) lines += c == '\n' ? 1 : 0;
  EXPECT_EQ(lines, 2 + static_cast<int>(kJointStateCount));
}

}  // namespace
}  // namespace rescue::fsm
