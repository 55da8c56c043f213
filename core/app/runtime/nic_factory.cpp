#include "core/app/runtime/nic_factory.hpp"

#include <cstdio>
#include <cstring>

#include "core/app/sim/simulated_robot_instance.hpp"

namespace rescue::app {
namespace {

hal::MonotonicClock g_real_time;

}  // namespace

Status SelectedNic::open(const NicChoice& choice, hal::Nanoseconds receive_spin) noexcept {
  ReceiveWaitChoice wait;
  wait.spin = receive_spin;
  return open(choice, wait);
}

Status SelectedNic::open(const NicChoice& choice, const ReceiveWaitChoice& wait) noexcept {
  const hal::Nanoseconds receive_spin = wait.spin;
  active_ = nullptr;
  if (choice.kind == NicKind::raw) {
    hal::RawSocketSettings settings;
    settings.receive_spin = receive_spin;
    settings.receive_wait = wait.wait;
    settings.adaptive_lead = wait.adaptive_lead;
    RESCUE_TRY(raw_.open(choice.interface_name.data(), settings));
    active_ = &raw_;
    return Status::success();
  }
  drivers::SimulatedRobot& robot = simulated_robot(g_real_time.now());  // the simulated robot runs on CLOCK_MONOTONIC
  RESCUE_TRY(robot.status());
  simulated_.clear();
  // The wall clock's simulated robot answers within the model's round trip (the spin).
  active_ = simulated_.emplace_back(robot.segment(), g_real_time, receive_spin);
  return Status::success();
}

Status SelectedNic::open_ring(const NicChoice& choice, const ReceiveWaitChoice& wait) noexcept {
  ring_ = nullptr;
  if (active_ == nullptr) return make_error(Errc::invalid_argument, "the ring NIC opens after the main one");
  if (choice.kind == NicKind::sim) {
    return make_error(Errc::unsupported,
                      "the in-process simulated robot has no ring port yet (the simulator's ring, issue 34 item 1); "
                      "serve the ring with `sim --iface A --ring-iface B` and use --nic raw:A --ring-nic raw:B");
  }
  if (active_ != &raw_) return make_error(Errc::invalid_argument, "a raw ring NIC needs a raw main NIC");
  hal::RawSocketSettings settings;
  settings.receive_spin = wait.spin;
  settings.receive_wait = wait.wait;
  settings.adaptive_lead = wait.adaptive_lead;
  RESCUE_TRY(ring_raw_.open(choice.interface_name.data(), settings));
  ring_ = &ring_raw_;
  return Status::success();
}

int fail_nic(const char* command, const char* nic_text, const Error& error) noexcept {
  if (error.code == Errc::io_error && error.detail0 != 0) {
    // Start-up only, one thread: strerror's static buffer is not shared with anyone.
    const char* os_reason = std::strerror(static_cast<int>(error.detail0));  // NOLINT(concurrency-mt-unsafe)
    (void)std::fprintf(stderr, "rescue-motion %s: cannot open %s: %s (%s: %s)\n", command, nic_text, error.what,
                       to_string(error.code), os_reason);
  } else {
    (void)std::fprintf(stderr, "rescue-motion %s: cannot open %s: %s (%s)\n", command, nic_text, error.what,
                       to_string(error.code));
  }
  return 1;
}

}  // namespace rescue::app
