// Replay protection that fails closed, end to end (docs/protocol.md "Replay protection",
// docs/security.md): an authentic datagram recorded on its way to a real `rescue-motion run` is
// accepted once; after a restart of the robot it is refused and counted as replayed, with the old
// replay-window file deleted, replaced by garbage, or made unwritable (a directory at its name and
// at its temporary name) - nothing on disk decides it. Sent to a second robot holding the same key
// (another --robot-id) it is refused and counted as wrong_robot; `ctl --robot` refuses to talk to
// the wrong robot. Counts are read from `ctl --json master`.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "hal/net/udp_socket.hpp"
#include "tests/support/authentic_answer.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::json_field;
using testing::read_text;
using testing::rescue_binary;
using testing::run_program;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::uint64_t unix_ns() {
  timespec ts{};
  (void)clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::uint64_t>(ts.tv_sec) * 1'000'000'000ULL + static_cast<std::uint64_t>(ts.tv_nsec);
}

// `rescue-motion run --state-dir DIR --key KEY --robot-id ID` on 127.0.0.1, stopped by SIGTERM.
class Robot {
 public:
  Robot(const std::string& state_dir, const std::string& key_in, unsigned robot_id)
      : key(key_in), control_port(testing::free_udp_port()), log(state_dir + ".log") {
    std::uint16_t sensor = testing::free_udp_port();
    while (sensor == control_port) sensor = testing::free_udp_port();
    const std::string control = std::to_string(control_port);
    const std::string sensor_text = std::to_string(sensor);
    const std::string id = std::to_string(robot_id);
    (void)std::remove(log.c_str());  // a restart's in_op() must not read the previous run's log
    pid_ = ::fork();
    if (pid_ == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      (void)::dup2(fd, 1);
      (void)::dup2(fd, 2);
      const std::vector<const char*> argv{rescue_binary().c_str(), "run", "--state-dir", state_dir.c_str(), "--key",
                                          key.c_str(), "--robot-id", id.c_str(), "--listen", "127.0.0.1",
                                          "--control-port", control.c_str(), "--sensor-port", sensor_text.c_str(),
                                          "--duration", "60", nullptr};
      ::execv(rescue_binary().c_str(), const_cast<char* const*>(argv.data()));
      ::_exit(127);
    }
  }
  Robot(const Robot&) = delete;
  Robot& operator=(const Robot&) = delete;
  ~Robot() { (void)stop(); }
  bool in_op() const {
    for (int i = 0; i < 3000; ++i) {
      if (has(read_text(log), "network in OP")) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  CommandResult ctl(std::vector<std::string> args) const {
    args.insert(args.begin(), {"ctl", "--key", key, "--port", std::to_string(control_port)});
    return run_program(args);
  }
  // `ctl --json master`'s counter `name` (a rejection reason, or datagrams_accepted).
  std::uint64_t counted(const std::string& name) const {
    const CommandResult master = ctl({"--json", "master"});
    EXPECT_EQ(master.status, 0) << master.out;
    const std::string value = json_field(master.out, name);
    return value.empty() ? ~std::uint64_t{0} : std::stoull(value);
  }
  int stop() {
    if (pid_ > 0) {
      (void)::kill(pid_, SIGTERM);
      int status = 0;
      (void)::waitpid(pid_, &status, 0);
      status_ = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
      pid_ = -1;
    }
    return status_;
  }

  std::string key;
  std::uint16_t control_port;
  std::string log;

 private:
  pid_t pid_{-1};
  int status_{-1};
};

// A station of our own: asks the epoch, sends one authentic get_status, keeps its bytes.
struct Recorder {
  explicit Recorder(const std::string& key_path) {
    hal::FileProblem why;
    const Result<protocol::Key> loaded = protocol::load_key_file(key_path.c_str(), why);
    EXPECT_TRUE(loaded.ok()) << why.c_str();
    if (loaded.ok()) key = loaded.value();
    EXPECT_TRUE(socket.open("127.0.0.1", 0).ok());
    loopback = hal::parse_ipv4("127.0.0.1").value();
  }
  // The next authentic datagram from the robot at `port` within 500 ms.
  // An answer that must come waits long (a loaded host delays the robot's socket handler, which runs at
  // normal priority); one that must not come is waited for 1 s.
  bool answer(std::uint16_t port, protocol::Message& out, int timeout_ms = 5000) {
    return test::receive_authentic(socket, key, timeout_ms, out, port);
  }
  bool send(std::uint16_t port, ConstByteSpan bytes) { return socket.send_to(loopback, port, bytes).ok(); }
  std::array<std::uint8_t, protocol::kMaxDatagram> seal(const protocol::Message& m, std::size_t& size) const {
    std::array<std::uint8_t, protocol::kMaxDatagram> out{};
    const Result<std::size_t> n = protocol::seal(m, key, ByteSpan(out));
    size = n.ok() ? n.value() : 0;
    return out;
  }
  // get_epoch, then a get_status of sender 7 in that epoch; true when the robot answered it.
  bool record(std::uint16_t port) {
    protocol::Message ask;
    ask.header.type = protocol::MessageType::get_epoch;
    ask.header.sender = 7;
    ask.header.sequence = unix_ns();
    std::size_t n = 0;
    const auto asked = seal(ask, n);
    protocol::Message epoch;
    if (n == 0 || !send(port, ConstByteSpan(asked.data(), n)) || !answer(port, epoch)) return false;
    protocol::Message request;
    request.header.type = protocol::MessageType::get_status;
    request.header.sender = 7;
    request.header.sequence = unix_ns();
    request.header.robot = epoch.header.robot;
    request.header.epoch = epoch.header.epoch;
    recorded = seal(request, recorded_size);
    protocol::Message status;
    return recorded_size > 0 && send(port, ConstByteSpan(recorded.data(), recorded_size)) && answer(port, status) &&
           status.header.type == protocol::MessageType::status;
  }
  // Sends the recorded datagram again; true when the robot answered it (it must not).
  bool replay(std::uint16_t port) {
    protocol::Message m;
    return send(port, ConstByteSpan(recorded.data(), recorded_size)) && answer(port, m, 1000);
  }

  protocol::Key key{};
  hal::UdpSocket socket;
  std::uint32_t loopback{0};
  std::array<std::uint8_t, protocol::kMaxDatagram> recorded{};
  std::size_t recorded_size{0};
};

class RecordedDatagram : public ::testing::Test {
 protected:
  void SetUp() override {
    key_ = dir_.path + "/operator.key";
    ASSERT_EQ(run_program({"ctl", "keygen", "--key", key_}).status, 0);
    state_ = dir_.path + "/robot";
    ASSERT_EQ(::mkdir(state_.c_str(), 0700), 0);
  }
  testing::TempStateDir dir_;
  std::string key_;
  std::string state_;
};

TEST_F(RecordedDatagram, IsRefusedAfterARestartWithTheWindowFileDeletedDamagedOrUnwritable) {
  Recorder station(key_);
  {
    Robot robot(state_, key_, 1);
    ASSERT_TRUE(robot.in_op()) << read_text(robot.log);
    ASSERT_TRUE(station.record(robot.control_port)) << read_text(robot.log);
    EXPECT_FALSE(station.replay(robot.control_port)) << "replayed within the run";
    EXPECT_EQ(robot.counted("replayed"), 1U);
    EXPECT_EQ(robot.stop(), 0) << read_text(robot.log);
  }
  const std::string window = state_ + "/replay-window.bin";
  struct Damage {
    const char* name;
    void (*apply)(const std::string& window);
  };
  const Damage damages[] = {
      {"deleted", [](const std::string& w) { (void)std::remove(w.c_str()); }},
      {"garbage",
       [](const std::string& w) {
         FILE* f = std::fopen(w.c_str(), "w");
         ASSERT_NE(f, nullptr);
         (void)std::fputs("RMRW not a window at all", f);
         (void)std::fclose(f);
       }},
      {"unwritable",
       [](const std::string& w) {
         (void)std::remove(w.c_str());
         ASSERT_EQ(::mkdir(w.c_str(), 0700), 0);
         ASSERT_EQ(::mkdir((w + ".tmp").c_str(), 0700), 0);
       }},
  };
  for (const Damage& damage : damages) {
    damage.apply(window);
    Robot robot(state_, key_, 1);
    ASSERT_TRUE(robot.in_op()) << damage.name << "\n" << read_text(robot.log);
    EXPECT_FALSE(station.replay(robot.control_port)) << damage.name << ": a recorded datagram was answered after a restart";
    EXPECT_EQ(robot.counted("replayed"), 1U) << damage.name;
    // The only datagrams accepted: the get_epoch and get_master of the two `ctl master` here.
    EXPECT_EQ(robot.counted("datagrams_accepted"), 4U) << damage.name;
    EXPECT_EQ(robot.stop(), 0) << read_text(robot.log);
  }
}

TEST_F(RecordedDatagram, IsRefusedAsWrongRobotByASecondRobotWithTheSameKey) {
  Recorder station(key_);
  {
    Robot a(state_, key_, 1);
    ASSERT_TRUE(a.in_op()) << read_text(a.log);
    ASSERT_TRUE(station.record(a.control_port)) << read_text(a.log);
    EXPECT_EQ(a.stop(), 0);
  }
  const std::string other = dir_.path + "/robot-b";
  ASSERT_EQ(::mkdir(other.c_str(), 0700), 0);
  Robot b(other, key_, 2);
  ASSERT_TRUE(b.in_op()) << read_text(b.log);
  EXPECT_FALSE(station.replay(b.control_port)) << "robot A's datagram was answered by robot B";
  EXPECT_EQ(b.counted("wrong_robot"), 1U);
  EXPECT_EQ(b.counted("replayed"), 0U) << "counted under its own reason";
  // ctl that expects robot 1 refuses robot 2, naming both.
  const CommandResult wrong = b.ctl({"--robot", "1", "--timeout", "1", "status"});
  EXPECT_EQ(wrong.status, 3) << "unreachable: " << wrong.out;
  EXPECT_TRUE(has(wrong.out, "is robot 2, not robot 1")) << wrong.out;
  EXPECT_EQ(b.ctl({"--robot", "2", "status"}).status, 0);
  EXPECT_EQ(b.stop(), 0) << read_text(b.log);
}

}  // namespace
}  // namespace rescue::app
