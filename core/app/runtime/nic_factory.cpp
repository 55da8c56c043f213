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
