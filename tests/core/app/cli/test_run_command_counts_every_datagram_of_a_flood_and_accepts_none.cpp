// Issue 12, the flood (docs/protocol.md "Flood test"): while the simulated robot is enabled and holding
// in a real `rescue-motion run --listen 127.0.0.1 --key FILE`, a sender thread sends thousands of
// malformed, oversized, unauthenticated and replayed datagrams at the control port and malformed ones
// at the sensor port, as fast as it can while keeping the robot's receive queue under 64 KiB (so the
// kernel drops none and each datagram is counted under its reason; the kernel's drops are read from
// /proc/net/udp and accounted for anyway), interleaved with valid `ctl` commands from other processes.
// Proven: none of the bad datagrams is accepted; every one is counted under the reason it was built
// for; every valid command is answered; the socket handler never handled more than its budget in one
// wake-up (the firmware's own bounded-work property). Not asserted, printed: the EtherCAT handler's
// wall-clock late periods and frames late or lost. This 2-core test host runs the flood sender, the
// ctl processes and every firmware thread without real-time priority on the same CPUs, so a late
// wake-up there is host jitter, never counted as the firmware's fault (COMMON-RULES).
#include <gtest/gtest.h>

#include <dirent.h>

#include <atomic>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "core/app/bench/bench_header.hpp"
#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "hal/net/udp_socket.hpp"
#include "tests/support/authentic_answer.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::OperatorRun;

constexpr std::size_t kPerKind = 4000;  // datagrams of each kind below
constexpr std::size_t kQueueLimit = 64 * 1024;

struct UdpQueue {
  std::uint64_t rx_queue{0};
  std::uint64_t drops{0};
};

// The kernel's view of the robot's socket on 127.0.0.1:port (/proc/net/udp: rx_queue and drops).
UdpQueue kernel_queue(std::uint16_t port) {
  std::ifstream in("/proc/net/udp");
  std::string line;
  char local[32];
  (void)std::snprintf(local, sizeof local, "0100007F:%04X", static_cast<unsigned>(port));
  UdpQueue q;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string sl, address, remote, state, queues;
    fields >> sl >> address >> remote >> state >> queues;
    if (address != local) continue;
    q.rx_queue = std::stoull(queues.substr(queues.find(':') + 1), nullptr, 16);
    std::string last;
    while (fields >> last) {
    }
    q.drops = std::stoull(last);
  }
  return q;
}

std::uint64_t number_after(const std::string& text, const std::string& label) {
  const std::size_t at = text.find(label);
  return at == std::string::npos ? ~std::uint64_t{0} : std::stoull(text.substr(at + label.size()));
}

// The whole line of `text` that contains `what`.
std::string line_with(const std::string& text, const std::string& what) {
  const std::size_t at = text.find(what);
  if (at == std::string::npos) return std::string();
  const std::size_t begin = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
  return text.substr(begin, text.find('\n', at) - begin);
}

std::uint64_t unix_ns() {
  timespec ts{};
  (void)clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::uint64_t>(ts.tv_sec) * 1'000'000'000ULL + static_cast<std::uint64_t>(ts.tv_nsec);
}

// Every authentic request is two datagrams, both accepted: get_epoch, then the request itself
// (docs/protocol.md "Replay protection").
constexpr std::uint64_t kDatagramsPerRequest = 2;

std::size_t seal_status_request(const protocol::Key& key, const protocol::Header& robot, std::uint32_t sender,
                                std::uint64_t sequence, std::array<std::uint8_t, protocol::kMaxDatagram>& out) {
  protocol::Message m;
  m.header.version = protocol::kVersion;
  m.header.type = protocol::MessageType::get_status;
  m.header.sender = sender;
  m.header.sequence = sequence;
  m.header.robot = robot.robot;
  m.header.epoch = robot.epoch;
  const Result<std::size_t> size = protocol::seal(m, key, ByteSpan(out));
  return size.ok() ? size.value() : 0;
}

struct Sent {
  std::uint64_t malformed{0};  // both ports
  std::uint64_t oversized{0};
  std::uint64_t unauthenticated{0};
  std::uint64_t replayed{0};
  std::uint64_t total() const { return malformed + oversized + unauthenticated + replayed; }
};

// The flood's sender and what it needs: the key, a socket, one authentic datagram accepted once.
struct Flooder {
  explicit Flooder(const OperatorRun& run_in) : run(run_in) {
    hal::FileProblem why;
    const Result<protocol::Key> loaded = protocol::load_key_file(run.key.c_str(), why);
    if (loaded.ok()) key = loaded.value();
    other = key;
    other[0] ^= 0xFF;
    opened = socket.open("127.0.0.1", 0).ok();
    loopback = hal::parse_ipv4("127.0.0.1").value();
  }
  // Asks the robot's epoch and id (get_epoch), as ctl does; true when it answered.
  bool learn_epoch() {
    protocol::Message ask;
    ask.header.type = protocol::MessageType::get_epoch;
    ask.header.sender = 9;
    ask.header.sequence = unix_ns();
    std::array<std::uint8_t, protocol::kMaxDatagram> out{};
    const Result<std::size_t> n = protocol::seal(ask, key, ByteSpan(out));
    protocol::Message answer;
    if (!opened || !n.ok() || !socket.send_to(loopback, run.control_port, ConstByteSpan(out.data(), n.value())).ok() ||
        !test::receive_authentic(socket, key, 5000, answer) || answer.header.type != protocol::MessageType::epoch) {
      return false;
    }
    robot = answer.header;
    return true;
  }
  // Sends the datagram to replay later (after get_epoch); true when the robot answered it (accepted once).
  bool record() {
    if (!learn_epoch()) return false;
    recorded_size = seal_status_request(key, robot, 9, unix_ns(), recorded);
    return opened && recorded_size > 0 &&
           socket.send_to(loopback, run.control_port, ConstByteSpan(recorded.data(), recorded_size)).ok() &&
           socket.wait_readable(5000);
  }
  // `per_kind` datagrams of each kind; `paced`: the robot's receive queues kept under kQueueLimit.
  Sent flood(std::size_t per_kind, bool paced) {
    Sent sent;
    const std::array<std::uint8_t, 16> junk{'n', 'o', 't', ' ', 'R', 'M', 'C', 'P', 1, 2, 3, 4, 5, 6, 7, 8};
    std::array<std::uint8_t, 1400> big{};
    std::memcpy(big.data(), recorded.data(), recorded_size);  // a good header, 1400 bytes long
    std::array<std::uint8_t, protocol::kMaxDatagram> forged{};
    std::uint64_t sequence = unix_ns();
    for (std::size_t i = 0; i < per_kind; ++i) {
      if (paced && i % 8 == 0) {
        while (kernel_queue(run.control_port).rx_queue > kQueueLimit || kernel_queue(run.sensor_port).rx_queue > kQueueLimit) {
          std::this_thread::yield();
        }
      }
      if (socket.send_to(loopback, run.control_port, ConstByteSpan(junk)).ok()) ++sent.malformed;
      if (socket.send_to(loopback, run.sensor_port, ConstByteSpan(junk)).ok()) ++sent.malformed;
      if (socket.send_to(loopback, run.control_port, ConstByteSpan(big)).ok()) ++sent.oversized;
      const std::size_t n = seal_status_request(other, robot, 9, ++sequence, forged);
      if (socket.send_to(loopback, run.control_port, ConstByteSpan(forged.data(), n)).ok()) ++sent.unauthenticated;
      if (socket.send_to(loopback, run.control_port, ConstByteSpan(recorded.data(), recorded_size)).ok()) ++sent.replayed;
    }
    return sent;
  }
  std::uint64_t kernel_drops() const {
    return kernel_queue(run.control_port).drops + kernel_queue(run.sensor_port).drops;
  }

  const OperatorRun& run;
  protocol::Key key{};
  protocol::Key other{};
  hal::UdpSocket socket;
  bool opened{false};
  std::uint32_t loopback{0};
  std::array<std::uint8_t, protocol::kMaxDatagram> recorded{};
  std::size_t recorded_size{0};
  protocol::Header robot{};  // the epoch answer's header: the robot's id and epoch
};

TEST(RunCommandFlood, EveryBadDatagramIsCountedNoneAcceptedValidCommandsAnswered) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const CommandResult init = run.ctl({"init"});
  ASSERT_EQ(init.status, 0) << init.out;
  std::uint64_t valid = 1;  // init
  Flooder flooder(run);
  ASSERT_TRUE(flooder.record()) << "the original of the replayed datagram was not answered";
  ++valid;

  Sent sent;
  std::atomic<bool> done{false};
  std::thread sender([&] {
    sent = flooder.flood(kPerKind, true);
    done.store(true);
  });
  // Valid commands from other processes while the flood lasts: each answered, each accepted.
  int commands = 0;
  while (!done.load() || commands < 6 || commands % 5 != 0) {  // ends after a whole round: l_hand enabled again
    static const char* const kVerbs[][2] = {{"hold", nullptr}, {"status", nullptr}, {"disable", "l_hand"},
                                            {"enable", "l_hand"}, {"master", nullptr}};
    const auto& v = kVerbs[commands % 5];
    std::vector<std::string> args{v[0]};
    if (v[1] != nullptr) args.emplace_back(v[1]);
    const CommandResult r = run.ctl(args);
    EXPECT_EQ(r.status, 0) << v[0] << ": " << r.out;
    ++commands;
    ++valid;
  }
  sender.join();

  const CommandResult status = run.ctl({"status"});  // enabled and holding through it all
  ++valid;
  EXPECT_EQ(status.status, 0) << status.out;
  EXPECT_EQ(status.out.find(" Ready "), std::string::npos) << status.out;
  EXPECT_EQ(status.out.find(" Error "), std::string::npos) << status.out;
  const CommandResult master = run.ctl({"master"});
  ++valid;
  EXPECT_EQ(master.status, 0) << master.out;
  const CommandResult tasks = run.ctl({"tasks"});
  ++valid;
  const std::uint64_t drops = flooder.kernel_drops();
  ASSERT_EQ(run.stop(), 0) << run.output();
  const std::string out = run.output();

  const std::uint64_t datagrams = number_after(out, "rescue-motion run: datagrams ");
  const std::uint64_t accepted = number_after(out, ", accepted ");
  const std::uint64_t most = number_after(out, "most datagrams in one wake-up ");
  // Everything sent reached the socket handler or the kernel's drop counter.
  EXPECT_EQ(datagrams + drops, sent.total() + kDatagramsPerRequest * valid) << out;
  EXPECT_EQ(accepted, kDatagramsPerRequest * valid) << "a bad datagram was accepted\n" << out;
  EXPECT_LE(most, SocketHandler::kBudget) << out;
  if (drops == 0) {
    EXPECT_EQ(number_after(out, ", malformed "), sent.malformed) << out;
    EXPECT_EQ(number_after(out, ", oversized "), sent.oversized) << out;
    EXPECT_EQ(number_after(out, ", unauthenticated "), sent.unauthenticated) << out;
    EXPECT_EQ(number_after(out, ", replayed "), sent.replayed) << out;
  }
  EXPECT_EQ(number_after(out, ", out_of_range "), 0U) << out;
  EXPECT_EQ(number_after(out, ", unknown_type "), 0U) << out;

  // The figures of docs/protocol.md "Flood test".
  std::printf("flood: sent malformed %" PRIu64 " (control and sensor), oversized %" PRIu64 ", unauthenticated %" PRIu64
              ", replayed %" PRIu64 "; valid %" PRIu64 " (%d ctl during the flood); kernel drops %" PRIu64 "\n",
              sent.malformed, sent.oversized, sent.unauthenticated, sent.replayed, valid, commands, drops);
  std::printf("flood: robot counted datagrams %" PRIu64 ", accepted %" PRIu64 ", most in one wake-up %" PRIu64
              " (budget %zu)\n", datagrams, accepted, most, SocketHandler::kBudget);
  std::printf("flood: %s\n", line_with(out, " cycles; healthy joints missed ").c_str());
  std::printf("flood: ctl master:\n%s\nflood: ctl tasks:\n%s", master.out.c_str(), tasks.out.c_str());
}


// The same flood unpaced, as fast as the sender thread can: the kernel may drop some (its counter,
// not the firmware's); still none accepted, every datagram accounted for, the budget kept, and the
// robot answers the operator once the flood is over.
TEST(RunCommandFlood, UnpacedFloodIsAccountedForAndNoneAccepted) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  ASSERT_EQ(run.ctl({"init"}).status, 0);
  Flooder flooder(run);
  ASSERT_TRUE(flooder.record());
  const Sent sent = flooder.flood(kPerKind, false);
  // The flood is over once the robot's sockets have taken in all of it, however long a loaded
  // machine takes (issue 35 item 16): only then does the operator ask, never into a full queue
  // whose drops would take the operator's own datagrams. Up to 60 s, then asked anyway.
  for (int i = 0; i < 6000 && (kernel_queue(run.control_port).rx_queue > 0 || kernel_queue(run.sensor_port).rx_queue > 0);
       ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const CommandResult status = run.ctl({"--timeout", "10", "status"});
  EXPECT_EQ(status.status, 0) << status.out;
  EXPECT_EQ(status.out.find(" Ready "), std::string::npos) << status.out;
  const std::uint64_t drops = flooder.kernel_drops();
  ASSERT_EQ(run.stop(), 0) << run.output();
  const std::string out = run.output();
  const std::uint64_t valid = 3;  // init, the recorded original, status
  EXPECT_EQ(number_after(out, "rescue-motion run: datagrams ") + drops, sent.total() + kDatagramsPerRequest * valid) << out;
  EXPECT_EQ(number_after(out, ", accepted "), kDatagramsPerRequest * valid) << out;
  EXPECT_LE(number_after(out, "most datagrams in one wake-up "), SocketHandler::kBudget) << out;
  std::printf("flood (unpaced): sent %" PRIu64 ", kernel drops %" PRIu64 "\nflood (unpaced): %s\nflood (unpaced): %s\n",
              sent.total(), drops, line_with(out, "rescue-motion run: datagrams ").c_str(),
              line_with(out, "socket handler wake-ups").c_str());
}

// ---- The flood while the robot moves (issue 12 "Done means"; docs/protocol.md "Flood while moving").

// Threads of other processes at SCHED_FIFO or SCHED_RR, kernel threads and the run's own processes
// (`run_pid` and its children) left out: another program's real-time work (on a shared host, another
// engineer's run) that the firmware's real-time threads compete with for the CPUs.
int other_real_time_threads(pid_t run_pid) {
  int count = 0;
  DIR* proc = ::opendir("/proc");
  if (proc == nullptr) return 0;
  while (const dirent* entry = ::readdir(proc)) {
    const int pid = std::atoi(entry->d_name);
    if (pid <= 0 || pid == run_pid) continue;
    const std::string base = "/proc/" + std::string(entry->d_name);
    if (testing::read_text(base + "/cmdline").empty()) continue;  // a kernel thread
    const std::string stat = testing::read_text(base + "/stat");
    const std::size_t close = stat.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream fields(stat.substr(close + 2));
    std::string state;
    long ppid = 0;
    fields >> state >> ppid;
    if (ppid == run_pid) continue;
    DIR* tasks = ::opendir((base + "/task").c_str());
    if (tasks == nullptr) continue;
    while (const dirent* task = ::readdir(tasks)) {
      if (task->d_name[0] == '.') continue;
      const std::string tstat = testing::read_text(base + "/task/" + task->d_name + "/stat");
      const std::size_t tclose = tstat.rfind(')');
      if (tclose == std::string::npos) continue;
      std::istringstream tfields(tstat.substr(tclose + 2));
      std::string field;
      for (int i = 3; i <= 41 && (tfields >> field); ++i) {
        if (i == 41 && (field == "1" || field == "2")) ++count;  // SCHED_FIFO, SCHED_RR
      }
    }
    (void)::closedir(tasks);
  }
  (void)::closedir(proc);
  return count;
}

struct RobotSample {
  bool ok{false};
  std::uint64_t cycles{0};
  std::uint64_t late_periods{0};
  double hand{0.0};        // l_hand's position, rad
  double hand_speed{0.0};  // l_hand's velocity, rad/s
  std::string hand_reachable;  // "true" when the answer carried l_hand's values from the handler
  std::string hand_owner;  // the RC task whose references drove l_hand ("null": none)
};

// One `ctl --json status` and one `ctl --json master`: two authentic requests.
RobotSample sample(const OperatorRun& run) {
  RobotSample s;
  const CommandResult status = run.ctl({"--json", "status"});
  const CommandResult master = run.ctl({"--json", "master"});
  const std::string hand = testing::json_field(testing::joint_object(status.out, "l_hand"), "position_rad");
  const std::string speed = testing::json_field(testing::joint_object(status.out, "l_hand"), "velocity_rad_s");
  s.ok = status.status == 0 && master.status == 0 && !hand.empty() && !speed.empty();
  if (!s.ok) return s;
  s.hand = std::stod(hand);
  s.hand_speed = std::stod(speed);
  s.hand_reachable = testing::json_field(testing::joint_object(status.out, "l_hand"), "reachable");
  s.hand_owner = testing::json_field(testing::joint_object(status.out, "l_hand"), "owner");
  s.cycles = number_after(master.out, "\"cycles\":");
  s.late_periods = number_after(master.out, "\"late_periods\":");
  return s;
}

// The same bad datagrams as above, sent for kFloodSeconds while RC task 1 (teleop) owns the motion
// and moves l_hand back and forth between 0.2 and 0.4 rad (`ctl hand left close|open --task 1`, the
// direction turned at those ends, so it never rests at a limit). Proven: none of the bad
// datagrams is accepted and each is counted under its reason (when the kernel dropped none); no frame
// lost, no joint lost; the hand is never driven by another RC task and moves again after the flood.
// While no other program's real-time thread shares the host (CI: the test runs alone), also: the
// hand's position or speed changes between every two samples during the flood, the hand is driven by RC task
// 1 in every sample (the owner stayed the RC task), the handler's cycle counter advances between
// every two samples, the owner was never released (its heartbeat never went silent) and the motion
// intake missed at most 1 in 10 of its periods; otherwise a weaker form, the figures printed.
// The handler's late and skipped periods during the flood window (`ctl master` late periods, read
// before and after) are asserted 0 only when the run's EtherCAT handler got SCHED_FIFO (the run
// prints "ethercat: running degraded" when it did not) on a PREEMPT_RT kernel; otherwise they are
// host jitter, printed beside those of a quiet window as long just before the flood. (On this 2-core
// VM without PREEMPT_RT, as root, the handler does run at SCHED_FIFO 80 and still shows a few late
// periods per second with no flood at all: a non-real-time kernel and the hypervisor, not the firmware.)
TEST(RunCommandFlood, TheRobotKeepsMovingThroughTheFloodAndNoBadDatagramIsAccepted) {
  constexpr auto kFloodTime = std::chrono::seconds(3);
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  ASSERT_EQ(run.ctl({"init"}).status, 0) << run.output();
  ASSERT_EQ(run.ctl({"owner", "1"}).status, 0) << run.output();
  ASSERT_EQ(run.ctl({"hand", "left", "close", "--task", "1"}).status, 0) << run.output();
  std::uint64_t valid = 3;
  Flooder flooder(run);
  ASSERT_TRUE(flooder.record()) << "the original of the replayed datagram was not answered";
  ++valid;
  const RobotSample quiet = sample(run);  // a quiet window as long as the flood, for comparison
  valid += 2;
  ASSERT_TRUE(quiet.ok) << run.output();
  std::this_thread::sleep_for(std::chrono::milliseconds(400));  // the hand on its way: about 0.2 rad
  EXPECT_EQ(run.ctl({"hand", "left", "open", "--task", "1"}).status, 0);
  ++valid;
  std::this_thread::sleep_for(kFloodTime - std::chrono::milliseconds(400));
  EXPECT_EQ(run.ctl({"hand", "left", "close", "--task", "1"}).status, 0);  // from the open end again
  ++valid;
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  const RobotSample before = sample(run);
  valid += 2;
  ASSERT_TRUE(before.ok) << run.output();

  const int other_rt_before = other_real_time_threads(run.pid());
  Sent sent;
  std::atomic<bool> stop_flood{false};
  std::thread sender([&] {
    while (!stop_flood.load()) {
      const Sent round = flooder.flood(500, true);
      sent.malformed += round.malformed;
      sent.oversized += round.oversized;
      sent.unauthenticated += round.unauthenticated;
      sent.replayed += round.replayed;
    }
  });
  const auto flood_end = std::chrono::steady_clock::now() + kFloodTime;
  RobotSample last = before;
  int samples = 0;
  int moved = 0;
  int turned = 0;      // of those, samples at the position of the last one, at another speed
  std::string still;   // the first two samples that found the hand standing still, for the failure
  int driven = 0;      // samples with l_hand driven by RC task 1
  int advanced = 0;    // samples after which the handler's cycle counter had advanced
  int refused = 0;     // hand commands refused ("no RC task running": its heartbeat older than 100 ms)
  int other_owner = 0; // samples with l_hand driven by another RC task
  // Close up to 0.4 rad, open down to 0.2 rad: the hand turns round only at those ends.
  const char* direction = before.hand < 0.3 ? "close" : "open";
  while (std::chrono::steady_clock::now() < flood_end) {
    if (last.hand >= 0.4) direction = "open";
    if (last.hand <= 0.2) direction = "close";
    if (run.ctl({"hand", "left", direction, "--task", "1"}).status != 0) ++refused;
    const RobotSample now = sample(run);
    valid += 3;
    EXPECT_TRUE(now.ok);
    if (now.hand_owner == "1") ++driven;
    if (now.hand_owner != "1" && now.hand_owner != "null") ++other_owner;
    if (now.cycles > last.cycles) ++advanced;
    // Turning round at its acceleration limit, the hand passes one position twice, once either way
    // (its references are symmetric about the cycle it stops in): moving is a new position or a new
    // speed; a hand standing still shows neither.
    if (now.hand != last.hand || now.hand_speed != last.hand_speed) ++moved;
    if (now.hand == last.hand && now.hand_speed != last.hand_speed) ++turned;
    if (now.hand == last.hand && now.hand_speed == last.hand_speed && still.empty()) {
      char pair[256];
      (void)std::snprintf(pair, sizeof pair, "l_hand %.6f rad at %.6f rad/s (reachable %s) at cycle %" PRIu64
                          " and again at cycle %" PRIu64 " (reachable %s)", now.hand, now.hand_speed,
                          last.hand_reachable.c_str(), last.cycles, now.cycles, now.hand_reachable.c_str());
      still = pair;
    }
    ++samples;
    last = now;
  }
  stop_flood.store(true);
  sender.join();
  const int other_rt_after = other_real_time_threads(run.pid());
  const RobotSample flood_over = sample(run);
  valid += 2;
  // After the flood: moving again within a second (several tries when the host starves the RC task).
  RobotSample after = flood_over;
  for (int attempt = 0; attempt < 5 && after.hand == flood_over.hand; ++attempt) {
    (void)run.ctl({"hand", "left", flood_over.hand < 0.3 ? "close" : "open", "--task", "1"});
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    after = sample(run);
    valid += 3;
  }
  const std::uint64_t drops = flooder.kernel_drops();
  ASSERT_EQ(run.stop(), 0) << run.output();
  const std::string out = run.output();

  // Alone: no other program's real-time thread on the host (CI runs this test alone: `serial`). Then
  // every sample must show the hand moving, driven by RC task 1, and the handler cycling. On a host
  // shared with other real-time programs (another engineer's run at the same SCHED_FIFO priorities on
  // the same CPUs) those are the other programs' doing: the weaker form below, the figures printed.
  const bool alone = other_rt_before == 0 && other_rt_after == 0;
  EXPECT_GE(samples, 3) << "too few samples during the flood";
  EXPECT_EQ(other_owner, 0) << "l_hand driven by another RC task during the flood";
  EXPECT_GT(flood_over.cycles, before.cycles) << "the handler's cycle counter stopped";
  EXPECT_NE(after.hand, flood_over.hand) << "l_hand stood still after the flood";
  EXPECT_GT(after.cycles, flood_over.cycles);
  if (alone) {
    EXPECT_EQ(moved, samples) << "l_hand stood still between two samples during the flood: " << still;
    EXPECT_EQ(driven, samples) << "l_hand not driven by the RC task in every sample during the flood";
    EXPECT_EQ(advanced, samples) << "the handler's cycle counter stood still between two samples";
    EXPECT_EQ(refused, 0) << "an RC task's heartbeat went silent for 100 ms";
    EXPECT_EQ(after.hand_owner, "1");
  } else {
    EXPECT_GE(2 * moved, samples) << "l_hand stood still in more than half the samples during the flood";
    EXPECT_GE(2 * driven, samples) << "l_hand not driven by the RC task in more than half the samples";
  }
  // None accepted, each counted under its reason.
  EXPECT_EQ(number_after(out, "rescue-motion run: datagrams ") + drops, sent.total() + kDatagramsPerRequest * valid) << out;
  EXPECT_EQ(number_after(out, ", accepted "), kDatagramsPerRequest * valid) << "a bad datagram was accepted\n" << out;
  if (drops == 0) {
    EXPECT_EQ(number_after(out, ", malformed "), sent.malformed) << out;
    EXPECT_EQ(number_after(out, ", unauthenticated "), sent.unauthenticated) << out;
    EXPECT_EQ(number_after(out, ", replayed "), sent.replayed) << out;
  }
  EXPECT_LE(number_after(out, "most datagrams in one wake-up "), SocketHandler::kBudget) << out;
  // What the firmware controls: no joint lost; the owner kept; the intake took its references. A
  // frame late or lost (and the joint-cycles it misses) is host jitter unless the handler is
  // SCHED_FIFO on a PREEMPT_RT kernel: a sanitizer build refuses SCHED_FIFO, and under load its
  // handler is late (seen in CI's asan stage: "frames late or lost" above 0): printed then.
  if (run.handler_got_sched_fifo() && kernel_is_preempt_rt()) {
    EXPECT_NE(out.find("frames late or lost: 0;"), std::string::npos) << out;
    EXPECT_NE(out.find("healthy joints missed 0 cycles"), std::string::npos) << out;
  } else {
    const std::size_t at = out.find("frames late or lost: ");
    (void)std::printf("frames late or lost: %s (host jitter here, not asserted)\n",
                      at == std::string::npos ? "n/a" : out.substr(at + 21, out.find(';', at) - at - 21).c_str());
  }
  EXPECT_NE(out.find("\njoints_lost: 0\n"), std::string::npos) << out;
  const std::uint64_t owner_periods = number_after(out, "\nowner_periods: ");
  const std::uint64_t owner_misses = number_after(out, "\nowner_misses: ");
  EXPECT_GT(owner_periods, 0U) << out;
  if (alone) {
    EXPECT_EQ(number_after(out, "\nowner_releases: "), 0U) << "the owner's heartbeat went silent\n" << out;
    EXPECT_LE(owner_misses * 10, owner_periods) << out;
  }
  // The handler's late and skipped periods in the flood window, and in a quiet window as long before it.
  const std::uint64_t late_in_flood = flood_over.late_periods - before.late_periods;
  const std::uint64_t late_in_quiet = before.late_periods - quiet.late_periods;
  const bool handler_fifo = run.handler_got_sched_fifo();
  const bool asserted = handler_fifo && kernel_is_preempt_rt();
  if (asserted) {
    EXPECT_EQ(late_in_flood, 0U) << "late or skipped handler periods under SCHED_FIFO on a real-time kernel\n" << out;
  }

  std::printf("flood while moving: sent malformed %" PRIu64 ", oversized %" PRIu64 ", unauthenticated %" PRIu64
              ", replayed %" PRIu64 " in %lld s; valid %" PRIu64 "; kernel drops %" PRIu64 "\n",
              sent.malformed, sent.oversized, sent.unauthenticated, sent.replayed,
              static_cast<long long>(kFloodTime.count()), valid, drops);
  std::printf("flood while moving: %s (other programs' real-time threads %d before, %d after); %d samples: l_hand moved "
              "in %d (%d of them turning round at one position), driven by rc1 in %d, handler cycled in %d; %d hand commands refused; handler cycles %" PRIu64
              " -> %" PRIu64 " during the flood\n",
              alone ? "alone, every sample asserted" : "host shared with other real-time programs, weaker form", other_rt_before,
              other_rt_after, samples, moved, turned, driven, advanced, refused, before.cycles, flood_over.cycles);
  std::printf("flood while moving: handler late or skipped periods during the flood %" PRIu64 " (%s), in the quiet "
              "window before it %" PRIu64 ", whole run %" PRIu64 "; owner periods %" PRIu64 ", misses %" PRIu64
              ", releases %" PRIu64 "\n",
              late_in_flood,
              asserted       ? "SCHED_FIFO on a real-time kernel: asserted 0"
              : handler_fifo ? "SCHED_FIFO on a kernel without PREEMPT_RT: host jitter, not asserted"
                             : "no SCHED_FIFO: host jitter, not asserted",
              late_in_quiet, after.late_periods, owner_periods, owner_misses, number_after(out, "\nowner_releases: "));
  std::printf("flood while moving: %s\n", line_with(out, "rescue-motion run: datagrams ").c_str());
}

}  // namespace
}  // namespace rescue::app
