// rescue-motion sim --iface IFACE: serve the simulated robot's EtherCAT segment on a network
// interface, for a master on the other end of the wire (or of a veth pair). Each frame from the
// master goes through the simulated segment and back out of the same interface, with the source
// MAC marked as real slave controllers mark it (core/app/sim/frame_server.hpp). docs/hal.md has recipes.
// Fault commands (drivers/sim/segment/fault_command.hpp: "cut l_elbow", "restore l_elbow", "freeze ...", "drop 3")
// can be typed on standard input while it serves; docs/simulator.md lists them. One more, of the host
// rather than the segment: "stall MS" holds every reply back for MS ms and sends them together.
// And a question, not a fault: "clocks TAG" prints every slave's true clock offset (test over veth).
// With --ring-iface B it serves the robot's ring configuration (core/robot/robot_ring.hpp,
// docs/redundancy.md): IFACE is the master's main port, B its ring port; a frame from either is
// sent back out of the interface of the port it comes back to.
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "core/app/cli/commands.hpp"
#include "core/app/config/task_table.hpp"
#include "core/app/sim/frame_server.hpp"
#include "core/app/runtime/nic_factory.hpp"
#include "core/app/sim/simulated_robot_instance.hpp"
#include "core/app/runtime/stop_signal.hpp"
#include "drivers/sim/segment/fault_command.hpp"
#include "hal/net/raw_socket_nic.hpp"
#include "hal/rt/rt_setup.hpp"

namespace rescue::app {
namespace {

// Longest wait for a frame before the simulated slaves catch up with the time on their own. They
// run SYNC0 pulses and drive models as hardware does; without these steps the first frame after an
// idle spell made them simulate the whole spell first (8.8 ms of work after 5 s idle with SYNC0 at
// 1 ms, 127 ms after 60 s: the master's first frames timed out). With them, at most 2 ms are left
// to simulate. A stop signal is seen at the end of each wait too.
constexpr hal::Nanoseconds kIdleStep = 2 * hal::kNsPerMs;
// The simulator stands for hardware, which answers within microseconds whatever else the host
// runs: served at a real-time priority above the master's EtherCAT task (80), a busy host cannot
// hold a frame back for milliseconds. Masters do not retry every read: SOEM's ec_configdc takes a
// port receive time that timed out (2 ms) as unchanged, and computes wrong propagation delays.
constexpr std::int64_t kDefaultPriority = 90;
// And on the EtherCAT task's CPU by default, where docs/deploy.md puts a real NIC's interrupt: a host
// that stalls that CPU stalls the master with it, as it would stall the master's own NIC handling.
// Left to the scheduler, a master pinned at real-time priority had the kernel wake the simulator on
// the other CPU (a woken real-time task leaves a CPU whose running real-time task is pinned), where a
// virtual machine's stalls of that CPU held frames 1-4 ms (docs/hal.md "The simulator's CPU").
int default_cpu() noexcept { return table_cpu_on_this_machine(task_spec(TaskId::ethercat_handler).cpu); }

void print_counters(const FrameServerCounters& served, const hal::NicStats& nic) noexcept {
  (void)std::printf("frames received: %llu\n", static_cast<unsigned long long>(served.frames_received));
  (void)std::printf("frames served at their receive timestamp: %llu\n", static_cast<unsigned long long>(served.frames_timestamped));
  (void)std::printf("frames returned: %llu\n", static_cast<unsigned long long>(served.frames_returned));
  (void)std::printf("frames not returned: %llu\n", static_cast<unsigned long long>(served.frames_not_returned));
  (void)std::printf("frames dropped by the nic: %llu\n", static_cast<unsigned long long>(nic.frames_dropped));
  (void)std::printf("send errors: %llu\n", static_cast<unsigned long long>(served.send_errors));
  (void)std::fflush(stdout);
}

// Frames the host read after an idle step had already moved the segment past their arrival: each
// entered at the segment's time (SimulatedSegment::process), one late frame rather than one in its past.
void print_segment_counters(const drivers::SimulatedSegment& segment) noexcept {
  (void)std::printf("frames taken late: %llu\n", static_cast<unsigned long long>(segment.counters().taken_late));
  (void)std::fflush(stdout);
}

// How far apart the two copies of a ring frame reached the simulator (ring copy's receive time minus
// the main copy's: the master's two sends), and how long after its arrival each copy was read: the
// master's part and the host's part of the DC error over veth (docs/redundancy.md).
class CopySpacing {
 public:
  // A ring copy within this of the last main copy is taken as its twin (a cycle is 1 ms or more).
  static constexpr hal::Nanoseconds kPairWindow = 500 * hal::kNsPerUs;

  void ring_copy_served(const FrameServer& main, const FrameServer& ring) noexcept {
    const hal::Nanoseconds spacing = ring.last_arrival() - main.last_arrival();
    if (spacing < 0 || spacing >= kPairWindow) return;
    min_ = pairs_ == 0 ? spacing : std::min(min_, spacing);
    max_ = std::max(max_, spacing);
    sum_ += spacing;
    std::size_t bucket = 0;
    while (bucket + 1 < kBucketTops.size() && spacing > kBucketTops[bucket]) ++bucket;
    ++buckets_[bucket];
    read_delay_max_ = std::max({read_delay_max_, main.last_read_delay(), ring.last_read_delay()});
    ++pairs_;
  }

  void print() const noexcept {
    if (pairs_ == 0) {
      (void)std::printf("copy spacing: n/a (no pair of copies)\n");
      return;
    }
    (void)std::printf("copy spacing: %llu pairs, ring copy after the main copy min %.1f us, mean %.1f us, max %.1f us; "
                      "read at most %.1f us after the arrival\n",
                      static_cast<unsigned long long>(pairs_), us(min_), us(sum_) / static_cast<double>(pairs_), us(max_),
                      us(read_delay_max_));
    (void)std::printf("copy spacing spread: <=5 us %llu, <=20 us %llu, <=100 us %llu, more %llu\n",
                      static_cast<unsigned long long>(buckets_[0]), static_cast<unsigned long long>(buckets_[1]),
                      static_cast<unsigned long long>(buckets_[2]), static_cast<unsigned long long>(buckets_[3]));
  }

 private:
  static double us(hal::Nanoseconds ns) noexcept { return static_cast<double>(ns) / static_cast<double>(hal::kNsPerUs); }
  static constexpr std::array<hal::Nanoseconds, 4> kBucketTops{5'000, 20'000, 100'000, kPairWindow};
  std::array<std::uint64_t, 4> buckets_{};
  std::uint64_t pairs_{0};
  hal::Nanoseconds min_{0};
  hal::Nanoseconds max_{0};
  hal::Nanoseconds sum_{0};
  hal::Nanoseconds read_delay_max_{0};
};

// Fault commands from standard input, one per line, applied between frames.
class FaultConsole {
 public:
  // Reads what is available without waiting; applies every complete line.
  void poll_once(drivers::SimulatedSegment& segment, FrameServer& server, hal::Nanoseconds now, FrameServer* ring_server = nullptr) noexcept {
    if (closed_) return;
    pollfd p{STDIN_FILENO, POLLIN, 0};
    if (::poll(&p, 1, 0) <= 0) return;
    const ssize_t got = ::read(STDIN_FILENO, line_.data() + length_, line_.size() - length_);
    if (got <= 0) {
      closed_ = true;  // end of input (or no terminal): stop looking
      return;
    }
    length_ += static_cast<std::size_t>(got);
    std::size_t start = 0;
    for (std::size_t i = 0; i < length_; ++i) {
      if (line_[i] != '\n') continue;
      apply(line_.data() + start, i - start, segment, server, ring_server, now);
      start = i + 1;
    }
    if (start == 0 && length_ == line_.size()) start = length_;  // an endless line: dropped
    for (std::size_t i = start; i < length_; ++i) line_[i - start] = line_[i];
    length_ -= start;
  }

 private:
  static void apply(const char* text, std::size_t length, drivers::SimulatedSegment& segment, FrameServer& server,
                    FrameServer* ring_server, hal::Nanoseconds now) noexcept {
    if (length > 7 && std::strncmp(text, "clocks ", 7) == 0) {
      print_clocks(text + 7, length - 7, segment, now);
      return;
    }
    // "stall MS" (1..1000): the host's part, not the segment's: replies held back MS ms, then bunched.
    if (length > 6 && std::strncmp(text, "stall ", 6) == 0) {
      unsigned ms = 0;
      std::size_t i = 6;
      for (; i < length && text[i] >= '0' && text[i] <= '9' && ms <= 1000; ++i) ms = ms * 10 + static_cast<unsigned>(text[i] - '0');
      if (i == length && ms >= 1 && ms <= 1000) {
        server.stall_until(now + static_cast<hal::Nanoseconds>(ms) * hal::kNsPerMs);
        if (ring_server != nullptr) ring_server->stall_until(now + static_cast<hal::Nanoseconds>(ms) * hal::kNsPerMs);
        (void)std::printf("fault: ok %.*s\n", static_cast<int>(length), text);
      } else {
        (void)std::printf("fault: refused %.*s: stall takes 1..1000 (ms)\n", static_cast<int>(length), text);
      }
      (void)std::fflush(stdout);
      return;
    }
    const Result<drivers::FaultCommand> command = drivers::parse_fault_command(text, length, segment);
    Status applied = command.ok() ? drivers::apply_fault_command(command.value(), segment, now) : Status(command.error());
    if (applied.ok()) {
      (void)std::printf("fault: ok %.*s\n", static_cast<int>(length), text);
    } else {
      (void)std::printf("fault: refused %.*s: %s\n", static_cast<int>(length), text, applied.error().what);
    }
    (void)std::fflush(stdout);
  }

  // "clocks TAG": each slave's system time against position 0's (the DC reference of the robot's
  // configurations) at this instant, in ns, in position order: the true offsets a drive's SYNC0 edge
  // follows, which no register shows (0x092C is what a clock's own loop measures). One line,
  // "clocks TAG: o0 o1 ...", TAG echoed so that a caller can find its answer; a question, not a fault.
  static void print_clocks(const char* tag, std::size_t length, const drivers::SimulatedSegment& segment,
                           hal::Nanoseconds now) noexcept {
    std::array<std::int64_t, drivers::kMaxSegmentSlaves> offsets{};
    (void)segment.true_clock_offsets(now, Span<std::int64_t>(offsets.data(), offsets.size()));
    (void)std::printf("clocks %.*s:", static_cast<int>(length), tag);
    for (std::size_t p = 0; p < segment.slave_count(); ++p) (void)std::printf(" %lld", static_cast<long long>(offsets[p]));
    (void)std::printf("\n");
    (void)std::fflush(stdout);
  }

  std::array<char, 256> line_{};
  std::size_t length_{0};
  bool closed_{false};
};

int serve_tree(drivers::SimulatedSegment& segment, hal::RawSocketNic& nic) noexcept {
  static SegmentFrameProcessor processor(segment);
  static FrameServer server(nic, processor);  // static: it holds the frames of a stall (25 KiB)
  FaultConsole faults;
  int exit_status = 0;
  while (stop_signal() == 0) {
    faults.poll_once(segment, server, nic.clock().now());
    const Status served = server.serve_one(nic.clock().now() + kIdleStep);
    if (!served.ok() && served.error().code != Errc::timeout) {
      exit_status = fail("sim", "serving stopped", served.error());
      break;
    }
  }
  if (stop_signal() != 0) (void)std::printf("stopped by signal %d\n", stop_signal());
  print_counters(server.counters(), nic.stats());
  print_segment_counters(segment);
  return exit_status;
}

// Both master ports in one thread: poll() on the two sockets, then each ready one served at once.
int serve_ring(drivers::SimulatedSegment& segment, hal::RawSocketNic& main_nic, hal::RawSocketNic& ring_nic) noexcept {
  static RingPortFrameProcessor main_port(segment, drivers::MasterPort::main, ring_nic);
  static RingPortFrameProcessor ring_port(segment, drivers::MasterPort::ring, main_nic);
  static FrameServer main_server(main_nic, main_port);
  static FrameServer ring_server(ring_nic, ring_port);
  FaultConsole faults;
  CopySpacing spacing;
  int exit_status = 0;
  while (stop_signal() == 0 && exit_status == 0) {
    faults.poll_once(segment, main_server, main_nic.clock().now(), &ring_server);
    std::array<pollfd, 2> sockets{{{main_nic.fd(), POLLIN, 0}, {ring_nic.fd(), POLLIN, 0}}};
    const int ready = ::poll(sockets.data(), sockets.size(), static_cast<int>(kIdleStep / hal::kNsPerMs));
    const hal::Nanoseconds now = main_nic.clock().now();
    if (ready <= 0) {
      main_port.idle(now);
      continue;
    }
    const std::array<FrameServer*, 2> servers{&main_server, &ring_server};
    for (std::size_t i = 0; i < servers.size(); ++i) {
      if ((sockets[i].revents & (POLLIN | POLLERR)) == 0) continue;
      const std::uint64_t before = servers[i]->counters().frames_received;
      const Status served = servers[i]->serve_one(now);  // the frame is queued: no wait
      if (!served.ok() && served.error().code != Errc::timeout) {
        exit_status = fail("sim", "serving stopped", served.error());
        break;
      }
      if (i == 1 && servers[i]->counters().frames_received != before) spacing.ring_copy_served(main_server, ring_server);
    }
  }
  if (stop_signal() != 0) (void)std::printf("stopped by signal %d\n", stop_signal());
  (void)std::printf("main port:\n");
  print_counters(main_server.counters(), main_nic.stats());
  (void)std::printf("ring port:\n");
  print_counters(ring_server.counters(), ring_nic.stats());
  (void)std::printf("frames sent back on the other port: %llu from main, %llu from ring\n",
                    static_cast<unsigned long long>(main_port.sent_on_other_port()),
                    static_cast<unsigned long long>(ring_port.sent_on_other_port()));
  const std::uint64_t other_port_errors = main_port.other_port_send_errors() + ring_port.other_port_send_errors();
  (void)std::printf("send errors on the other port: %llu\n", static_cast<unsigned long long>(other_port_errors));
  spacing.print();
  print_segment_counters(segment);
  return exit_status;
}

const OptionSpec kOptions[] = {
    {"iface", "IFACE", "network interface to serve the segment on (required)"},
    {"ring-iface", "IFACE", "serve the robot's ring configuration: IFACE is the master's ring port (--iface its main port)"},
    {"priority", "N", "SCHED_FIFO priority 1..99 while serving, 0 for normal scheduling (default 90)"},
    {"cpu", "N|any", "serve on CPU N (default: the EtherCAT task's CPU, where a real NIC's interrupt goes); any: wherever the scheduler puts it"},
    {"through-qdisc", nullptr, "send replies through the interface's queueing discipline (e.g. `tc qdisc ... netem` delay and reordering); default: bypass it, as hardware has none"},
};

int sim_main(const ParsedArgs& args) {
  const char* iface = args.value("iface");
  if (iface == nullptr) return fail("sim", "--iface IFACE is required (e.g. --iface eth1)");
  const Result<std::int64_t> priority = args.integer("priority", kDefaultPriority, 0, 99);
  if (!priority.ok()) return fail("sim", "--priority must be 0..99", priority.error());

  int cpu = default_cpu();
  const char* cpu_text = args.value("cpu");
  if (cpu_text != nullptr && std::strcmp(cpu_text, "any") == 0) {
    cpu = -1;
  } else {
    const long online = ::sysconf(_SC_NPROCESSORS_ONLN);
    const Result<std::int64_t> chosen = args.integer("cpu", cpu, 0, online > 0 ? online - 1 : 0);
    if (!chosen.ok()) return fail("sim", "--cpu must be `any` or a CPU of this machine (0 to the number online - 1)", chosen.error());
    cpu = static_cast<int>(chosen.value());
  }

  hal::RawSocketSettings settings;
  settings.qdisc_bypass = !args.has("through-qdisc");
  // Each frame passes the segment at the instant it was sent (FrameServer::serve_one).
  settings.receive_timestamps = true;
  const char* ring_iface = args.value("ring-iface");
  if (ring_iface != nullptr && std::strcmp(ring_iface, iface) == 0) {
    return fail("sim", "--ring-iface must name another interface than --iface (the master's two ports)");
  }
  static hal::RawSocketNic nic;  // static, like the server that refers to it
  const Status opened = nic.open(iface, settings);
  if (!opened.ok()) return fail_nic("sim", iface, opened.error());
  static hal::RawSocketNic ring_nic;
  if (ring_iface != nullptr) {
    const Status ring_opened = ring_nic.open(ring_iface, settings);
    if (!ring_opened.ok()) return fail_nic("sim", ring_iface, ring_opened.error());
  }
  drivers::SimulatedRobot& robot = ring_iface != nullptr ? simulated_ring_robot(nic.clock().now()) : simulated_robot(nic.clock().now());
  if (!robot.status().ok()) return fail("sim", "cannot build the simulated robot", robot.status().error());
  if (!install_stop_handlers()) return fail("sim", "cannot install SIGINT/SIGTERM handlers");
  // Best effort, each item reported: without privilege the simulator still serves, only slower
  // to answer on a loaded host.
  hal::RtConfig rt;
  rt.prefault_stack_bytes = std::size_t{256} * 1024;
  rt.fifo_priority = static_cast<int>(priority.value());
  rt.cpu = cpu;
  hal::apply_rt_config(rt).print(stdout);

  std::size_t powered = 0;
  for (std::size_t p = 0; p < robot.segment().slave_count(); ++p) powered += robot.segment().esc(p).powered() ? 1U : 0U;
  if (ring_iface != nullptr) {
    (void)std::printf("serving %zu slaves in a ring on %s (main) and %s (ring)\n", powered, iface, ring_iface);
  } else {
    (void)std::printf("serving %zu slaves on %s (and a spare one behind the last, unplugged: `extra-slave` plugs it in)\n",
                      powered, iface);
  }
  (void)std::fflush(stdout);  // scripts and tests wait for this line
  return ring_iface != nullptr ? serve_ring(robot.segment(), nic, ring_nic) : serve_tree(robot.segment(), nic);
}

}  // namespace

const CommandSpec kSimCommand{
    "sim", "sim --iface IFACE [--ring-iface IFACE2] [--priority N] [--cpu N|any] [...]",
    "serve the simulated robot's EtherCAT segment on a network interface",
    "A master on the other end of the wire (or of a veth pair) sees the 23 slaves of the robot.\n"
    "With --ring-iface the robot is cabled as a ring (one line through every slave, closed back to\n"
    "IFACE2, the master's second port; docs/redundancy.md): `cut ring` cuts the ring-return cable.\n"
    "Needs CAP_NET_RAW (root, or `setcap cap_net_raw+ep rescue-motion`). It serves at SCHED_FIFO\n"
    "priority 90 with its memory locked when allowed, on the EtherCAT task's CPU (where a real NIC's\n"
    "interrupt goes; each item is reported), so that it answers as fast as hardware on a busy host.\n"
    "Standard input takes fault commands (docs/simulator.md) and `clocks TAG`, which prints every\n"
    "slave's true clock offset from position 0's in ns (`clocks TAG: o0 o1 ...`).\n"
    "SIGINT or SIGTERM stop it and it prints its frame counters.\n"
    "docs/hal.md shows how to run it on a veth pair.",
    Span<const OptionSpec>(kOptions), 0, 0, sim_main};

}  // namespace rescue::app
