// Every verb of `rescue-motion ctl` (ctl_verbs(), core/app/cli/ctl_verbs.hpp: ctl refuses any other) is
// run in a command of docs/operator.md's generated transcript (toolchain/operator-transcript.sh) and
// named in `ctl --help`, and every command of the transcript uses a verb of the table; every option of
// ctl is named on the page. So a new verb cannot land without its documented example, and the page
// cannot show a verb that is gone.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/app/cli/commands.hpp"
#include "core/app/cli/ctl_verbs.hpp"

namespace rescue::app {
namespace {

std::string operator_page() {
  std::ifstream in(std::string(RESCUE_SOURCE_DIR) + "/docs/operator.md");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool option_takes_value(const std::string& name) {
  for (const OptionSpec& o : kCtlCommand.options) {
    if (name == o.name) return o.value_name != nullptr;
  }
  return false;
}

// The verbs of the `$ rescue-motion ctl ...` lines inside the page's TRANSCRIPT blocks: the first
// argument that is neither an option nor an option's value.
std::vector<std::string> transcript_verbs(const std::string& page) {
  std::vector<std::string> verbs;
  std::istringstream lines(page);
  std::string line;
  bool in_block = false;
  while (std::getline(lines, line)) {
    if (line.rfind("<!-- BEGIN TRANSCRIPT ", 0) == 0) in_block = true;
    if (line.rfind("<!-- END TRANSCRIPT ", 0) == 0) in_block = false;
    const std::string prompt = "    $ rescue-motion ctl ";
    if (!in_block || line.rfind(prompt, 0) != 0) continue;
    std::istringstream words(line.substr(prompt.size()));
    std::string word;
    while (words >> word) {
      if (word.rfind("--", 0) == 0) {
        if (option_takes_value(word.substr(2))) words >> word;
        continue;
      }
      verbs.push_back(word);
      break;
    }
  }
  return verbs;
}

TEST(CtlVerbs, EveryVerbIsRunInTheOperatorPagesTranscript) {
  const std::string page = operator_page();
  ASSERT_FALSE(page.empty()) << "docs/operator.md not found under " << RESCUE_SOURCE_DIR;
  const std::vector<std::string> shown = transcript_verbs(page);
  ASSERT_FALSE(shown.empty()) << "no `$ rescue-motion ctl` line in a TRANSCRIPT block of docs/operator.md";
  const std::set<std::string> shown_set(shown.begin(), shown.end());
  for (const CtlVerb& v : ctl_verbs()) {
    const char* verb = v.name;
    EXPECT_EQ(shown_set.count(verb), 1U) << "ctl " << verb
                                         << " has no example in docs/operator.md: add it to toolchain/operator-transcript.sh and run it";
  }
  for (const std::string& verb : shown) {
    EXPECT_TRUE(is_ctl_verb(verb.c_str())) << "docs/operator.md runs `ctl " << verb << "`, which is not a verb of ctl_verbs()";
  }
}

TEST(CtlVerbs, EveryVerbIsInTheHelpAndEveryOptionOnThePage) {
  const std::string help = kCtlCommand.details;
  for (const CtlVerb& v : ctl_verbs()) {
    const std::string verb = v.name;
    EXPECT_NE(help.find(std::string(" ") + verb + " "), std::string::npos) << "ctl --help does not name " << verb;
  }
  const std::string page = operator_page();
  for (const OptionSpec& o : kCtlCommand.options) {
    EXPECT_NE(page.find(std::string("--") + o.name), std::string::npos) << "docs/operator.md does not name --" << o.name;
  }
}

TEST(CtlVerbs, TheTableHasNoDuplicateAndKnowsNoOtherVerb) {
  std::set<std::string> seen;
  for (const CtlVerb& v : ctl_verbs()) {
    EXPECT_TRUE(seen.insert(v.name).second) << v.name;
    // Each entry is whole: its request and its printing, its arguments' bounds, a usage naming it.
    const bool own = v.run == CtlRun::own;
    EXPECT_EQ(v.build != nullptr && v.print != nullptr, !own) << v.name;
    EXPECT_EQ(v.converse != nullptr, own) << v.name;
    EXPECT_LE(v.min_args, v.max_args) << v.name;
    EXPECT_EQ(std::string(v.usage).rfind(v.name, 0), 0U) << v.name << ": " << v.usage;
  }
  EXPECT_FALSE(is_ctl_verb("reboot"));
  EXPECT_FALSE(is_ctl_verb(""));
  EXPECT_TRUE(is_ctl_verb("status"));
}

}  // namespace
}  // namespace rescue::app
