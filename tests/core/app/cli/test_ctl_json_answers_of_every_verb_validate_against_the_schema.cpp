// Every `ctl --json` answer has one shape (issue 36 item 6): each verb of ctl's table is run against the
// simulated robot (answered, refused, and ctl's own errors of each class), and every line it prints
// on stdout is validated against docs/ctl-answer.schema.json with Python's jsonschema (Debian's
// /usr/bin/python3 and python3-jsonschema, toolchain/setup.sh: another python3 first on PATH may lack it). A verb added to the table without a run here fails the test.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "core/app/cli/ctl_verbs.hpp"
#include "tests/support/json_query.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::OperatorRun;
using testing::run_program;
using Args = std::vector<std::string>;

// Validates each line of `lines` (one JSON object per line) against the schema; "" when all are
// valid, else each failure with its line.
std::string validate(const std::string& dir, const std::string& lines) {
  // Every failure of every line, with the line and its command (nothing printed: all valid).
  return testing::python_output(
      dir, "validate",
      "import json, sys, jsonschema\n"
      "schema = json.load(open(sys.argv[1]))\n"
      "jsonschema.Draft202012Validator.check_schema(schema)\n"
      "v = jsonschema.Draft202012Validator(schema)\n"
      "for n, line in enumerate(open(sys.argv[2]), 1):\n"
      "    try:\n"
      "        d = json.loads(line)\n"
      "    except ValueError as e:\n"
      "        print(f'line {n}: not JSON: {e}: {line[:200]}'); continue\n"
      "    for e in v.iter_errors(d):\n"
      "        print(f'line {n} ({d.get(\"command\")}): {e.message} at {list(e.path)}')\n",
      lines, "'" + std::string(RESCUE_SOURCE_DIR) + "/docs/ctl-answer.schema.json'");
}

TEST(CtlJsonSchema, EveryVerbsAnswersValidate) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const auto ctl = [&run](Args args) {
    args.insert(args.begin(), {"ctl", "--json", "--key", run.key, "--port", std::to_string(run.control_port)});
    return run_program(args, false);
  };
  // Per verb, the invocations (and the exit status each must end with): answered, refused, usage;
  // run in the table's order (init, ..., hand, owner), which decides what is refused.
  const std::map<std::string, std::vector<std::pair<Args, int>>> runs{
      {"status", {{{"status"}, 0}, {{"status", "extra"}, 2}}},
      {"slaves", {{{"slaves"}, 0}, {{"slaves", "-v"}, 0}}},
      {"master", {{{"master"}, 0}}},
      {"tasks", {{{"tasks"}, 0}}},
      {"diag", {{{"diag"}, 0}, {{"diag", "--reset", "l_elbow"}, 0}, {{"diag", "--reset", "tail"}, 2}}},
      {"graph", {{{"graph"}, 0}, {{"graph", "--format", "dot"}, 2}}},
      {"watch", {{{"watch", "--count", "2", "--interval", "0.05"}, 0}}},
      {"init", {{{"init"}, 0}}},
      {"enable", {{{"enable", "l_hand"}, 0}, {{"enable", "tail"}, 2}}},  // already Enabled: unchanged
      {"disable", {{{"disable", "l_hand"}, 0}}},
      {"hold", {{{"hold"}, 0}}},
      {"mode", {{{"mode", "l_hand", "csv"}, 0}, {{"mode", "l_elbow", "csv"}, 1}, {{"mode", "l_hand", "xyz"}, 2}}},
      {"clear", {{{"clear", "l_hand"}, 1}}},
      {"owner", {{{"owner"}, 0}, {{"owner", "1"}, 0}}},
      {"move", {{{"move", "left", "0.4,0.2,0.3,0,0,0", "--task", "0"}, 1}}},
      {"hand", {{{"hand", "left", "close", "--task", "1"}, 1}}},  // run before owner 1: not owner
      {"version", {{{"version"}, 0}}},
      {"upload", {{{"upload", "l_elbow", "0x1008:00"}, 0}, {{"upload", "l_elbow", "0x5FFF:00"}, 1},
                  {{"upload", "13", "0x1008:00"}, 0}, {{"upload", "junction_a", "0x1018:01"}, 1},
                  {{"upload", "23", "0x1018:01"}, 2}}},
      {"pdos", {{{"pdos"}, 0}, {{"pdos", "l_elbow"}, 0}, {{"pdos", "junction_a"}, 0}, {{"pdos", "23"}, 2}}},
      {"sdos", {{{"sdos", "l_elbow", "--values"}, 0}, {{"sdos", "13"}, 0}, {{"sdos", "junction_a"}, 1}, {{"sdos", "23"}, 2}}},
      {"sii_read", {{{"sii_read", "l_elbow"}, 0}, {{"sii_read", "0"}, 0}, {{"sii_read", "23"}, 2}}},
      {"xml", {{{"xml", "l_elbow"}, 0}, {{"xml", "junction_a"}, 0}, {{"xml", "23"}, 2}}},
      {"reg_read", {{{"reg_read", "l_elbow", "0x0130", "2"}, 0}, {{"reg_read", "0", "0x0000", "64"}, 0},
                    {{"reg_read", "l_elbow", "0x0130", "65"}, 2}}},
      {"states", {{{"states", "l_elbow", "PREOP"}, 1}, {{"states", "OP"}, 1}, {{"states", "l_elbow", "BOOT"}, 2}}},
      {"rescan", {{{"rescan"}, 0}, {{"rescan", "now"}, 2}}},
      {"download", {{{"download", "l_elbow", "0x6066:00", "100", "--type", "u16"}, 0},
                    {{"download", "l_elbow", "0x607A:00", "1000", "--type", "i32"}, 1}}},
  };
  std::string lines;
  for (const CtlVerb& verb : ctl_verbs()) {
    if (std::string(verb.name) == "keygen") continue;  // below: it writes a file
    const auto found = runs.find(verb.name);
    ASSERT_NE(found, runs.end()) << "ctl " << verb.name << " is not run here: add its invocations";
    for (const auto& [args, status] : found->second) {
      const CommandResult r = ctl(args);
      EXPECT_EQ(r.status, status) << "ctl " << args[0] << " ...: " << r.out;
      EXPECT_FALSE(r.out.empty()) << "ctl --json " << args[0] << " printed no object";
      lines += r.out;
    }
  }
  const CommandResult made = run_program({"ctl", "--json", "keygen", "--key", run.dir.path + "/second.key"}, false);
  EXPECT_EQ(made.status, 0) << made.out;
  lines += made.out;
  // ctl's own errors: unreachable, local.
  const CommandResult silent = run_program({"ctl", "--json", "--key", run.key, "--port", std::to_string(testing::free_udp_port()),
                                            "--timeout", "0.2", "status"},
                                           false);
  EXPECT_EQ(silent.status, 3) << silent.out;
  lines += silent.out;
  const CommandResult no_key = run_program({"ctl", "--json", "--key", run.dir.path + "/absent.key", "version"}, false);
  EXPECT_EQ(no_key.status, 4) << no_key.out;
  lines += no_key.out;
  EXPECT_EQ(validate(run.dir.path, lines), "") << lines;
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
