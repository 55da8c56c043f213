// Issue 24, one key path and JSON answers (docs/operator.md "Options", "--json"): `ctl --config FILE`
// (by default the package's /etc/rescue-motion/rescue-motion.conf when it exists) reads the robot's
// key_file and control_port, so `ctl keygen` makes the key `run --config FILE` loads and `ctl status`
// reaches that robot with no --key or --port; without key_file both use <state dir>/operator.key.
// With --json every answer is exactly one object on one line: keygen's, ctl's own errors (a missing
// key file, no answer, an unknown joint), and each refresh of `watch` (JSON Lines).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "tests/support/background_run.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::run_program;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// Exactly one JSON object, on one line (stderr lines of ctl's own errors start with "rescue-motion ctl:").
std::string the_object(const std::string& out) {
  std::string objects;
  for (std::size_t at = 0; at < out.size();) {
    std::size_t end = out.find('\n', at);
    if (end == std::string::npos) end = out.size();
    const std::string line = out.substr(at, end - at);
    if (!line.empty() && line[0] == '{') objects += line + "\n";
    at = end + 1;
  }
  return objects;
}

TEST(CtlKeyPath, KeygenWritesTheConfiguredKeyAndRunAndCtlUseIt) {
  testing::TempStateDir dir;
  const std::uint16_t control = testing::free_udp_port();
  std::uint16_t sensor = testing::free_udp_port();
  while (sensor == control) sensor = testing::free_udp_port();
  const std::string config = dir.path + "/robot.conf";
  const std::string key = dir.path + "/robot.key";
  std::ofstream(config) << "state_dir = " << dir.path << "/state\nkey_file = " << key << "\nlisten = 127.0.0.1\ncontrol_port = "
                        << control << "\nsensor_port = " << sensor << "\n";

  const CommandResult made = run_program({"ctl", "--json", "--config", config, "keygen"});
  ASSERT_EQ(made.status, 0) << made.out;
  EXPECT_EQ(the_object(made.out), made.out);
  EXPECT_EQ(testing::json_field(made.out, "key_file"), key) << made.out;

  test::BackgroundRun run({"run", "--config", config, "--duration", "30"}, dir.path + "/run.log");
  ASSERT_TRUE(run.wait_for("network in OP", std::chrono::seconds(30))) << run.output();
  EXPECT_TRUE(has(run.output(), "(key " + key)) << run.output();
  const CommandResult status = run_program({"ctl", "--json", "--config", config, "status"});
  ASSERT_EQ(status.status, 0) << status.out;
  EXPECT_EQ(status.out.rfind(R"({"command":"status","ok":true,"cycle":)", 0), 0U) << status.out;
  EXPECT_EQ(the_object(status.out), status.out) << "exactly one object";

  // watch --json: JSON Lines, one object per refresh.
  const CommandResult watch = run_program({"ctl", "--json", "--config", config, "watch", "--count", "2", "--interval", "0.1"});
  ASSERT_EQ(watch.status, 0) << watch.out;
  const std::string lines = the_object(watch.out);
  EXPECT_EQ(lines, watch.out);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), '\n'), 2) << lines;
  (void)::kill(run.pid(), SIGTERM);
  EXPECT_EQ(run.wait_exit(), 0) << run.output();
}

TEST(CtlKeyPath, WithoutKeyFileBothUseTheStateDirectory) {
  testing::TempStateDir dir;
  const std::string config = dir.path + "/robot.conf";
  std::ofstream(config) << "state_dir = " << dir.path << "/state\n";
  const CommandResult made = run_program({"ctl", "--json", "--config", config, "keygen"});
  ASSERT_EQ(made.status, 0) << made.out;
  EXPECT_EQ(testing::json_field(made.out, "key_file"), dir.path + "/state/operator.key") << made.out;
}

TEST(CtlJson, CtlsOwnErrorsAreOneObjectToo) {
  testing::TempStateDir dir;
  const std::string config = dir.path + "/robot.conf";
  std::ofstream(config) << "key_file = " << dir.path << "/absent.key\n";
  const CommandResult missing = run_program({"ctl", "--json", "--config", config, "status"});
  EXPECT_EQ(missing.status, 4) << "local: the key file";
  const std::string object = the_object(missing.out);
  EXPECT_EQ(testing::json_field(object, "ok"), "false") << missing.out;
  EXPECT_TRUE(has(object, "key_file of " + config)) << "the hint names where the robot looks: " << object;
  EXPECT_TRUE(has(object, "ctl keygen --key " + dir.path + "/absent.key")) << object;

  const CommandResult made = run_program({"ctl", "--key", dir.path + "/k.key", "keygen"});
  ASSERT_EQ(made.status, 0) << made.out;
  const CommandResult silent =
      run_program({"ctl", "--json", "--key", dir.path + "/k.key", "--port", "9", "--timeout", "0.2", "status"});
  EXPECT_EQ(silent.status, 3) << "unreachable";
  EXPECT_TRUE(has(the_object(silent.out), R"("command":"status","ok":false,"error":"status: unreachable: no authentic answer)"))
      << silent.out;

  const CommandResult unknown = run_program({"ctl", "--json", "--key", dir.path + "/k.key", "enable", "tail"});
  EXPECT_EQ(unknown.status, 2) << "usage";
  EXPECT_TRUE(has(the_object(unknown.out), "'tail'")) << unknown.out;
}

}  // namespace
}  // namespace rescue::app
