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

#include <atomic>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "core/app/control/protocol_auth.hpp"
#include "core/app/control/protocol_codec.hpp"
#include "core/app/control/socket_handler.hpp"
#include "hal/net/udp_socket.hpp"
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

std::size_t seal_status_request(const protocol::Key& key, std::uint32_t sender, std::uint64_t sequence,
                                std::array<std::uint8_t, protocol::kMaxDatagram>& out) {
  protocol::Message m;
  m.header.version = protocol::kVersion;
  m.header.type = protocol::MessageType::get_status;
  m.header.sender = sender;
  m.header.sequence = sequence;
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
    const Result<protocol::Key> loaded = protocol::load_key_file(run.key.c_str());
    if (loaded.ok()) key = loaded.value();
    other = key;
    other[0] ^= 0xFF;
    opened = socket.open("127.0.0.1", 0).ok();
    loopback = hal::parse_ipv4("127.0.0.1").value();
  }
  // Sends the datagram to replay later; true when the robot answered it (accepted once).
  bool record() {
    recorded_size = seal_status_request(key, 9, unix_ns(), recorded);
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
      const std::size_t n = seal_status_request(other, 9, ++sequence, forged);
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
  EXPECT_EQ(datagrams + drops, sent.total() + valid) << out;
  EXPECT_EQ(accepted, valid) << "a bad datagram was accepted\n" << out;
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
  const CommandResult status = run.ctl({"status"});
  EXPECT_EQ(status.status, 0) << status.out;
  EXPECT_EQ(status.out.find(" Ready "), std::string::npos) << status.out;
  const std::uint64_t drops = flooder.kernel_drops();
  ASSERT_EQ(run.stop(), 0) << run.output();
  const std::string out = run.output();
  const std::uint64_t valid = 3;  // init, the recorded original, status
  EXPECT_EQ(number_after(out, "rescue-motion run: datagrams ") + drops, sent.total() + valid) << out;
  EXPECT_EQ(number_after(out, ", accepted "), valid) << out;
  EXPECT_LE(number_after(out, "most datagrams in one wake-up "), SocketHandler::kBudget) << out;
  std::printf("flood (unpaced): sent %" PRIu64 ", kernel drops %" PRIu64 "\nflood (unpaced): %s\nflood (unpaced): %s\n",
              sent.total(), drops, line_with(out, "rescue-motion run: datagrams ").c_str(),
              line_with(out, "socket handler wake-ups").c_str());
}

}  // namespace
}  // namespace rescue::app
