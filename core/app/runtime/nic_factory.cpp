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
    // The in-process robot in its ring configuration: both master ports on one segment and clock.
    // The main NIC opened on the tree robot is replaced by the ring robot's main port (nothing has
    // used it yet: open_ring follows open at start-up).
    if (simulated_.empty() || active_ != simulated_.data()) {
      return make_error(Errc::invalid_argument, "a simulated ring NIC needs the simulated main NIC (--nic sim)");
    }
    drivers::SimulatedRobot& robot = simulated_ring_robot(g_real_time.now());
    RESCUE_TRY(robot.status());
    ring_pair_.clear();
    drivers::SimulatedNicPair* pair = ring_pair_.emplace_back(robot.segment(), g_real_time, wait.spin);
    if (pair == nullptr) return make_error(Errc::capacity_exceeded, "no room for the ring's NIC pair");
    RESCUE_TRY(pair->status());
    simulated_.clear();
    active_ = &pair->main();
    ring_ = &pair->ring();
    return Status::success();
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
