// ctl's contract for scripts (docs/operator.md "Exit status", issue 36 items 5, 6, 8; issue 35 item 4):
// one exit status per class of outcome, the same for every verb (0 ok, 1 refused, 2 usage,
// 3 unreachable, 4 local, 5 an answer that does not fit), and the robot's text escaped so that it
// can neither end a JSON string early nor drive the terminal. The robot here is a fake one in this
// process that holds the key and answers what the test chooses (a hostile peer holding the key).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "hal/net/udp_socket.hpp"
#include "tests/support/json_query.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;
using testing::CommandResult;
using testing::run_program;

// The robot's side of the exchange: the epoch answer, then `answer` (its type and payload as the test
// set them; the header and the reply's echo filled in here) to every other request.
class FakeRobot {
 public:
  FakeRobot(const protocol::Key& key, const Message& answer) : key_(key), answer_(answer) {
    EXPECT_TRUE(socket_.open("127.0.0.1", 0).ok());
    thread_ = std::thread([this] { serve(); });
  }
  FakeRobot(const FakeRobot&) = delete;
  FakeRobot& operator=(const FakeRobot&) = delete;
  ~FakeRobot() {
    stop_ = true;
    thread_.join();
  }
  std::uint16_t port() const { return socket_.local_port(); }

 private:
  void serve() {
    std::array<hal::UdpDatagram, 1> in{};
    while (!stop_) {
      if (!socket_.wait_readable(20) || socket_.receive_batch(Span<hal::UdpDatagram>(in)) != 1) continue;
      const Result<protocol::FrameView> f = protocol::parse_frame(ConstByteSpan(in[0].bytes.data(), in[0].size));
      if (!f.ok() || !protocol::verify_frame(f.value(), key_).ok()) continue;
      const protocol::Header& asked = f.value().header;
      Message out = answer_;
      if (asked.type == MessageType::get_epoch) {
        out = Message{};
        out.header.type = MessageType::epoch;
        out.epoch.request_sequence = asked.sequence;
      } else if (out.header.type == MessageType::reply) {
        out.reply.request_sequence = asked.sequence;
        out.reply.request_type = asked.type;
      }
      out.header.sender = 0;
      out.header.robot = 1;
      out.header.epoch = 7;
      out.header.sequence = ++sequence_;
      std::array<std::uint8_t, protocol::kMaxDatagram> bytes{};
      const Result<std::size_t> n = protocol::seal(out, key_, ByteSpan(bytes));
      if (n.ok()) (void)socket_.send_to(in[0].address, in[0].port, ConstByteSpan(bytes.data(), n.value()));
    }
  }

  protocol::Key key_;
  Message answer_;
  hal::UdpSocket socket_;
  std::atomic<bool> stop_{false};
  std::uint64_t sequence_{0};
  std::thread thread_;
};

// stdout alone (the JSON answer), and the exit status.
CommandResult stdout_of(const std::vector<std::string>& args) { return run_program(args, false); }

class CtlContract : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(protocol::init_crypto().ok());
    key_file = dir.path + "/operator.key";
    ASSERT_EQ(run_program({"ctl", "keygen", "--key", key_file}).status, 0);
    hal::FileProblem why;
    const Result<protocol::Key> loaded = protocol::load_key_file(key_file.c_str(), why);
    ASSERT_TRUE(loaded.ok()) << why.c_str();
    key = loaded.value();
  }
  std::vector<std::string> ctl(std::uint16_t port, std::vector<std::string> args) const {
    args.insert(args.begin(), {"ctl", "--key", key_file, "--port", std::to_string(port), "--timeout", "1"});
    return args;
  }
  std::string query(const std::string& json, const std::string& expr) const { return testing::json_query(dir.path, json, expr); }

  testing::TempStateDir dir;
  std::string key_file;
  protocol::Key key{};
};

Message hostile_refusal(const char* text) {
  Message m;
  m.header.type = MessageType::reply;
  m.reply.outcome = protocol::Outcome::refused;
  m.reply.reason = protocol::RefusalReason::state_machine;
  protocol::set_text(m.reply.text, text);
  return m;
}

TEST_F(CtlContract, ARobotsTextCannotTurnARefusalIntoAnAcceptedJsonAnswer) {
  FakeRobot robot(key, hostile_refusal(R"(x","accepted":true,"reason":"none)"));
  const CommandResult json = stdout_of(ctl(robot.port(), {"--json", "disable", "l_hand"}));
  EXPECT_EQ(json.status, 1) << "refused: " << json.out;
  EXPECT_EQ(query(json.out, "d['accepted']"), "false") << json.out;
  EXPECT_EQ(query(json.out, "d['ok']"), "false") << json.out;
  EXPECT_EQ(query(json.out, "d['reason']"), "\"state machine refusal\"") << json.out;
  EXPECT_EQ(query(json.out, "d['detail']"), R"("x\",\"accepted\":true,\"reason\":\"none")") << json.out;
  EXPECT_EQ(query(json.out, "d['joints']"), "[]") << "a list is an array: " << json.out;
}

TEST_F(CtlContract, ARobotsTextReachesTheTerminalAsPrintableAsciiOnly) {
  // The robot's own encoder sends what is not printable ASCII as '?' (docs/protocol.md "Text
  // fields"), and ctl's decoder refuses such a byte on the wire: no escape sequence gets through.
  FakeRobot robot(key, hostile_refusal("\x1b]0;owned\x07\x1b[2J\\"));
  const CommandResult text = stdout_of(ctl(robot.port(), {"disable", "l_hand"}));
  EXPECT_EQ(text.status, 1);
  EXPECT_EQ(text.out, "disable: refused: state machine refusal: ?]0;owned??[2J\\\\\n");
  for (const char c : text.out) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7F)) << static_cast<int>(c);
}

TEST_F(CtlContract, EachClassOfOutcomeHasItsOwnExitStatus) {
  Message version;
  version.header.type = MessageType::version;
  protocol::set_text(version.version.program, "v1");
  protocol::set_text(version.version.build_type, "Debug");
  FakeRobot answers_version(key, version);
  // 0: answered. 5: an authentic answer of another type than the request asks for.
  EXPECT_EQ(run_program(ctl(answers_version.port(), {"version"})).status, 0);
  const CommandResult misfit = stdout_of(ctl(answers_version.port(), {"--json", "status"}));
  EXPECT_EQ(misfit.status, 5) << misfit.out;
  EXPECT_EQ(query(misfit.out, "d['exit']"), "\"bad_answer\"") << misfit.out;
  // 1: refused by the robot.
  FakeRobot refuses(key, hostile_refusal("no"));
  EXPECT_EQ(run_program(ctl(refuses.port(), {"enable"})).status, 1);
  // 2: usage, for every verb alike: an argument too many, one missing, one that does not parse, an
  // option of another verb, an unknown verb, an unknown option; none of them asks the robot.
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"status", "extra"}, {"version", "1"}, {"mode", "l_hand"}, {"clear"},
                                             {"enable", "tail"}, {"owner", "7"}, {"status", "--moved"},
                                             {"watch", "--interval", "-1"}, {"reboot"}, {"status", "--nosuch"}}) {
    const CommandResult r = run_program(ctl(refuses.port(), args));
    EXPECT_EQ(r.status, 2) << args[7] << ": " << r.out;
  }
  // ... and the JSON says which class.
  const CommandResult usage = stdout_of(ctl(refuses.port(), {"--json", "status", "extra"}));
  EXPECT_EQ(query(usage.out, "[d['ok'], d['exit'], d['command']]"), R"([false, "usage", "status"])") << usage.out;
  // 3: unreachable: nothing answers on that port.
  const std::uint16_t silent = testing::free_udp_port();
  // (ctl() already gives --timeout 1: an option given twice is a usage error, issue 35 item 7.)
  const CommandResult none = stdout_of(ctl(silent, {"--json", "status"}));
  EXPECT_EQ(none.status, 3) << none.out;
  EXPECT_EQ(query(none.out, "d['exit']"), "\"unreachable\"") << none.out;
  // 4: local: the key file is missing; a bad argument is still usage without one.
  const std::vector<std::string> no_key{"ctl", "--key", dir.path + "/absent.key", "--port", std::to_string(silent)};
  std::vector<std::string> args = no_key;
  args.emplace_back("status");
  EXPECT_EQ(run_program(args).status, 4);
  args = no_key;
  args.insert(args.end(), {"enable", "tail"});
  EXPECT_EQ(run_program(args).status, 2);
}

}  // namespace
}  // namespace rescue::app
