#include "core/app/runtime/self_check.hpp"

#include "core/app/runtime/nic_factory.hpp"
#include "core/app/runtime/stop_signal.hpp"
#include "core/memory/start_up_slot.hpp"
#include "drivers/cia402/cia402.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "ecat/capture/capture_tap.hpp"
#include "ecat/capture/capture_writer.hpp"
#include "ecat/master/al_control.hpp"
#include "ecat/master/bring_up_report.hpp"
#include "hal/files/instance_lock.hpp"

namespace rescue::app {
namespace {

constexpr const char* kPrefix = "rescue-motion run --check";
constexpr const char* kLinePrefix = "rescue-motion run --check: ";  // the report's lines

int failed(std::FILE* out, const char* what, const char* detail) noexcept {
  (void)std::fprintf(out, "%s: FAILED: %s%s%s\n", kPrefix, what, detail[0] != '\0' ? ": " : "", detail);
  return 1;
}

using hal::seconds;  // hal/time/clock.hpp

// A phase line written: out to whoever reads it now, not when the check ends (a pipe is block-buffered).
void phase_done(std::FILE* progress) noexcept {
  if (progress != nullptr) (void)std::fflush(progress);
}

// The capture of --capture: every frame of the check, written by this thread as it goes (nothing
// here is periodic); closed when the check ends, whichever way.
ecat::CaptureWriter& check_capture() noexcept {
  static ecat::CaptureWriter capture;
  return capture;
}

// The NIC (a raw one another rescue-motion drives is never touched: INIT would stop its robot), the
// ring NIC, the bus on them, the capture. 0, or the exit status (said).
int open_check_bus(const SelfCheckOptions& options, std::FILE* out, drivers::JointBus*& bus_out, hal::Clock*& clock_out) noexcept {
  if (options.nic.kind == NicKind::raw) {
    const Status locked = hal::lock_raw_interface(options.nic.interface_name.data());
    if (!locked.ok()) {
      return failed(out,
                    locked.error().code == Errc::busy ? "the interface is in use by another rescue-motion (stop the service first)"
                                                      : "cannot lock the interface",
                    locked.error().what);
    }
  }
  static SelectedNic selected;
  const Status opened = selected.open(options.nic);
  if (!opened.ok()) return failed(out, "cannot open the NIC", opened.error().what);
  if (options.ring_nic_text != nullptr) {
    const Status ring = selected.open_ring(options.ring_nic);
    if (!ring.ok()) return failed(out, "cannot open the ring NIC", ring.error().what);
  }
  hal::Clock& clock = selected.nic()->clock();
  static StartUpSlot<drivers::JointBus> bus_slot;  // not in every command's image (start_up_slot.hpp)
  if (!bus_slot.reserve()) return failed(out, "not enough memory for the bus", "");
  drivers::JointBus& bus = bus_slot.emplace(*selected.nic());
  if (selected.ring_nic() != nullptr) bus.master().use_ring(*selected.ring_nic());  // docs/redundancy.md
  bus_out = &bus;
  clock_out = &clock;
  if (options.capture_path != nullptr) {
    ecat::CaptureWriter& capture = check_capture();
    ecat::CaptureWriterOptions capture_options;
    capture_options.timestamp_offset = ecat::unix_time_offset(clock);
    if (!capture.open(options.capture_path, capture_options).ok()) {
      return failed(out, "cannot open the capture file", capture.problem().c_str());
    }
    bus.master().set_tap(ecat::capture_tap, &capture);
  }
  return 0;
}

// Cycles with every output zero until OP, then a short hold in OP. The wait for OP counts from
// here (SAFE-OP), and is never shorter than the master's own OP limit: a slave that does not
// follow is then in the master's report (the slave, its AL status code).
void cycle_to_op_and_hold(const SelfCheckOptions& options, hal::Nanoseconds master_op_timeout, drivers::JointBus& bus,
                          hal::Clock& clock, hal::Nanoseconds start, SelfCheckReport& r) noexcept {
  std::FILE* const progress = options.progress;
  const drivers::JointReferences zero{};
  drivers::JointFeedback feedback{};
  hal::Nanoseconds op_at = -1;
  const hal::Nanoseconds cycling_from = clock.now();
  const hal::Nanoseconds op_limit = options.op_timeout > master_op_timeout ? options.op_timeout : master_op_timeout + 100 * hal::kNsPerMs;
  for (;;) {
    clock.sleep_until(bus.next_wakeup());
    const drivers::JointCycleResult c = bus.cycle(zero, feedback);
    const hal::Nanoseconds now = clock.now();
    if (!c.frame_received) ++r.frames_missing;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((feedback.valid & joint_bit(j)) != 0 && (feedback.joints[j].statusword & drivers::cia402::sw::kOperationEnabled) != 0) {
        r.drive_enabled = true;
      }
    }
    if (c.state == ecat::MasterState::op && op_at < 0) {
      op_at = now;
      r.reached_op = true;
      r.op_after_s = seconds(now - start);
      if (progress != nullptr) {
        (void)std::fprintf(progress, "%s: OP after %.3f s; exchanging frames for %.3f s\n", kPrefix, r.op_after_s,
                           seconds(options.hold_in_op));
      }
      phase_done(progress);
    }
    if (op_at >= 0) ++r.cycles_in_op;
    if (stop_signal() != 0) break;
    if (op_at >= 0 && now - op_at >= options.hold_in_op) break;
    if (op_at < 0 && (c.state == ecat::MasterState::failed || now - cycling_from >= op_limit)) break;
  }
}

// The verdict line (OK, or FAILED and why) after the way back to INIT; 0 or 1.
int check_verdict(const SelfCheckOptions& options, std::FILE* out, const SelfCheckReport& r, ecat::Master& master,
                  const char* al) noexcept {
  if (stop_signal() != 0) return failed(out, "stopped by a signal", r.back_in_init ? "slaves back in INIT" : al);
  if (r.drive_enabled) return failed(out, "a drive reported Operation enabled", "with controlword 0 (check the drives)");
  if (!r.reached_op) {
    // Which slave did not follow, its AL status code, the link's counters (the master's report).
    ecat::print_bring_up_failure(out, kLinePrefix, kLinePrefix, master);
    return failed(out, "the network did not reach OP", r.back_in_init ? "slaves back in INIT" : al);
  }
  if (!r.back_in_init) return failed(out, "reached OP but the slaves did not go back to INIT", al);
  (void)std::fprintf(out,
                     "%s: OK: nic %s, %u slaves, OP after %.3f s, %llu cycles in OP (%llu frames late or lost), back "
                     "in INIT; no drive enabled\n",
                     kPrefix, options.nic_text, r.slaves, r.op_after_s, static_cast<unsigned long long>(r.cycles_in_op),
                     static_cast<unsigned long long>(r.frames_missing));
  return 0;
}

}  // namespace

int run_self_check(const SelfCheckOptions& options, std::FILE* out, SelfCheckReport* report) noexcept {
  SelfCheckReport local{};
  SelfCheckReport& r = report != nullptr ? *report : local;
  r = SelfCheckReport{};
  drivers::JointBus* opened_bus = nullptr;
  hal::Clock* opened_clock = nullptr;
  struct CaptureCloser {
    CaptureCloser() = default;
    CaptureCloser(const CaptureCloser&) = delete;
    CaptureCloser& operator=(const CaptureCloser&) = delete;
    CaptureCloser(CaptureCloser&&) = delete;
    CaptureCloser& operator=(CaptureCloser&&) = delete;
    ~CaptureCloser() {
      if (check_capture().is_open()) (void)check_capture().close();
    }
  } const closer;
  if (const int bad = open_check_bus(options, out, opened_bus, opened_clock); bad != 0) return bad;
  drivers::JointBus& bus = *opened_bus;
  hal::Clock& clock = *opened_clock;
  ecat::MasterOptions master_options;
  master_options.stop_requested = []() noexcept { return stop_signal() != 0; };
  std::FILE* const progress = options.progress;
  if (progress != nullptr) (void)std::fprintf(progress, "%s: bringing the network up (nic %s)\n", kPrefix, options.nic_text);
  phase_done(progress);
  const hal::Nanoseconds start = clock.now();
  const Status up = bus.bring_up(master_options);
  if (!up.ok()) {
    // The FAILED line is the report's first; the report's other lines follow it (bring_up_report.hpp).
    ecat::print_bring_up_failure(out, "rescue-motion run --check: FAILED: ", "rescue-motion run --check: ", bus.master());
    return 1;
  }
  r.slaves = bus.master().report().slaves_counted;
  if (progress != nullptr) {
    (void)std::fprintf(progress, "%s: %u slaves in SAFE-OP after %.3f s; to OP with every output zero\n", kPrefix,
                       r.slaves, seconds(clock.now() - start));
  }
  phase_done(progress);
  cycle_to_op_and_hold(options, master_options.op_timeout, bus, clock, start, r);

  // Back to INIT, every slave that answered at bring-up.
  if (progress != nullptr) (void)std::fprintf(progress, "%s: back to INIT\n", kPrefix);
  phase_done(progress);
  ecat::AlFailure failure{};
  const Status init = ecat::request_al_state(bus.master().link(), bus.master().plan(), bus.master().present(),
                                             ecat::reg::AlState::init, ecat::AlOptions{}, failure);
  r.back_in_init = init.ok();
  char al[160] = "";
  if (!init.ok()) (void)ecat::describe(failure, bus.master().plan(), al, sizeof al);
  return check_verdict(options, out, r, bus.master(), al);
}

}  // namespace rescue::app
