// rescue-motion sim --iface IFACE: serve the simulated robot's EtherCAT segment on a network
// interface, for a master on the other end of the wire (or of a veth pair). Each frame from the
// master goes through the simulated segment and back out of the same interface, with the source
// MAC marked as real slave controllers mark it (core/app/frame_server.hpp). docs/hal.md has recipes.
#include <csignal>
#include <cstdio>

#include "core/app/commands.hpp"
#include "core/app/frame_server.hpp"
#include "core/app/nic_factory.hpp"
#include "hal/raw_socket_nic.hpp"

namespace rescue::app {
namespace {

// Longest time a stop signal waits to be seen: each receive wait ends by then.
constexpr hal::Nanoseconds kStopLatency = 100 * hal::kNsPerMs;

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int signal_number) { g_stop_signal = signal_number; }

// Without SA_RESTART, so the receive wait (ppoll) returns early when a signal arrives.
bool install_stop_handlers() noexcept {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  (void)sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  return sigaction(SIGINT, &action, nullptr) == 0 && sigaction(SIGTERM, &action, nullptr) == 0;
}

void print_counters(const FrameServerCounters& served, const hal::NicStats& nic) noexcept {
  (void)std::printf("frames received: %llu\n", static_cast<unsigned long long>(served.frames_received));
  (void)std::printf("frames returned: %llu\n", static_cast<unsigned long long>(served.frames_returned));
  (void)std::printf("frames not returned: %llu\n", static_cast<unsigned long long>(served.frames_not_returned));
  (void)std::printf("frames dropped by the nic: %llu\n", static_cast<unsigned long long>(nic.frames_dropped));
  (void)std::printf("send errors: %llu\n", static_cast<unsigned long long>(served.send_errors));
  (void)std::fflush(stdout);
}

// The simulated segment (drivers/, issue 4) plugs in here once it is on main.
FrameProcessor* simulated_segment() noexcept { return nullptr; }

const OptionSpec kOptions[] = {
    {"iface", "IFACE", "network interface to serve the segment on (required)"},
};

int sim_main(const ParsedArgs& args) {
  const char* iface = args.value("iface");
  if (iface == nullptr) return fail("sim", "--iface IFACE is required (e.g. --iface eth1)");

  hal::RawSocketNic nic;
  const Status opened = nic.open(iface);
  if (!opened.ok()) return fail_nic("sim", iface, opened.error());
  FrameProcessor* segment = simulated_segment();
  // Always true until the segment plugs into simulated_segment().
  // cppcheck-suppress knownConditionTrueFalse
  if (segment == nullptr) return fail("sim", "the simulated segment is not in this build yet");
  if (!install_stop_handlers()) return fail("sim", "cannot install SIGINT/SIGTERM handlers");

  (void)std::printf("serving %zu slaves on %s\n", segment->slave_count(), iface);
  (void)std::fflush(stdout);  // scripts and tests wait for this line

  FrameServer server(nic, *segment);
  int exit_status = 0;
  while (g_stop_signal == 0) {
    const Status served = server.serve_one(nic.clock().now() + kStopLatency);
    if (!served.ok() && served.error().code != Errc::timeout) {
      exit_status = fail("sim", "serving stopped", served.error());
      break;
    }
  }
  if (g_stop_signal != 0) (void)std::printf("stopped by signal %d\n", static_cast<int>(g_stop_signal));
  print_counters(server.counters(), nic.stats());
  return exit_status;
}

}  // namespace

const CommandSpec kSimCommand{
    "sim", "sim --iface IFACE", "serve the simulated robot's EtherCAT segment on a network interface",
    "A master on the other end of the wire (or of a veth pair) sees the 23 slaves of the robot.\n"
    "Needs CAP_NET_RAW (root, or `setcap cap_net_raw+ep rescue-motion`). SIGINT or SIGTERM stop it\n"
    "and it prints its frame counters. docs/hal.md shows how to run it on a veth pair.",
    Span<const OptionSpec>(kOptions), 0, 0, sim_main};

}  // namespace rescue::app
