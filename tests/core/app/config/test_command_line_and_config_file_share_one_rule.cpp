// Issue 35, item 7: the command line and the configuration file disagreed: `--state-dir relative/dir`
// and a repeated `--duration` were accepted on the command line and refused in the file. One rule
// for both now: each option once, as each key once; a state directory or key file by an absolute path
// (the service's working directory is not the operator's), refused with the same words.
#include <gtest/gtest.h>

#include <string>

#include "core/app/config/command_line.hpp"
#include "core/app/config/config_file.hpp"
#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

constexpr OptionSpec kOptions[] = {
    {"duration", "SECONDS", "how long"},
    {"state-dir", "DIR", "where"},
    {"verbose", nullptr, "more", 'v'},
};
int no_main(const ParsedArgs&) { return 0; }
const CommandSpec kSpec{"t", "t", "t", "", Span<const OptionSpec>(kOptions), 0, 0, no_main};

Result<ParsedArgs> parse(std::initializer_list<const char*> args) {
  return parse_args(kSpec, static_cast<int>(args.size()), args.begin());
}

ConfigOutcome parse_file(const std::string& text, ConfigFile& out) {
  return parse_config(Span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), out);
}

TEST(OneRule, ARepeatedOptionIsRefusedAsARepeatedKeyIs) {
  const Result<ParsedArgs> twice = parse({"--duration", "3", "--duration", "5"});
  ASSERT_FALSE(twice.ok());
  EXPECT_STREQ(twice.error().what, "option given twice (each option once)");
  EXPECT_EQ(twice.error().detail0, 2U) << "the index of the repeat";
  EXPECT_FALSE(parse({"--duration=3", "--duration", "3"}).ok());
  EXPECT_FALSE(parse({"-v", "--verbose"}).ok());
  EXPECT_FALSE(parse({"-v", "-v"}).ok());
  const Result<ParsedArgs> once = parse({"--duration", "3", "-v"});
  ASSERT_TRUE(once.ok());
  EXPECT_STREQ(once.value().value("duration"), "3");

  ConfigFile file;
  const ConfigOutcome in_file = parse_file("duration = 3\nduration = 5\n", file);
  ASSERT_FALSE(in_file.ok);
  EXPECT_STREQ(in_file.error.what, "key given twice");
}

TEST(OneRule, AStateDirectoryOrKeyByARelativePathIsRefusedInBothWithTheSameWords) {
  EXPECT_STREQ(path_value_problem("relative/dir"), "not an absolute path");
  EXPECT_EQ(path_value_problem("/var/lib/rescue-motion"), nullptr);
  ConfigFile file;
  const ConfigOutcome in_file = parse_file("state_dir = relative/dir\n", file);
  ASSERT_FALSE(in_file.ok);
  EXPECT_STREQ(in_file.error.what, "not an absolute path");
  EXPECT_STREQ(in_file.error.allowed, kPathValueRule);

  for (const char* option : {"--state-dir", "--key"}) {
    const test::CommandOutput run = test::run_command("'" + kProgram + "' run " + option + " relative/dir --duration 0.1 2>&1");
    EXPECT_EQ(run.exit_status, 1) << run.out;
    EXPECT_NE(run.out.find(std::string(option) + " relative/dir: not an absolute path (" + kPathValueRule), std::string::npos)
        << run.out;
  }
  const test::CommandOutput twice = test::run_command("'" + kProgram + "' run --duration 1 --duration 2 2>&1");
  EXPECT_NE(twice.exit_status, 0) << twice.out;
  EXPECT_NE(twice.out.find("option given twice"), std::string::npos) << twice.out;
}

}  // namespace
}  // namespace rescue::app
