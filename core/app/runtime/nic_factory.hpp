// Creates, at start-up, the NIC that `--nic` chose, inside storage this object owns (no heap):
// the raw socket on a named interface, or the in-process simulated segment.
#pragma once

#include "core/app/config/firmware_config.hpp"
#include "core/app/config/nic_option.hpp"
#include "core/base/result.hpp"
#include "core/containers/fixed_vector.hpp"
#include "drivers/sim/segment/simulated_nic.hpp"
#include "hal/net/nic.hpp"
#include "hal/net/raw_socket_nic.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

// How long the master's raw socket reads before it sleeps: config::kMasterReceiveSpinNs.
constexpr hal::Nanoseconds kMasterReceiveSpin = config::kMasterReceiveSpinNs;

class SelectedNic {
 public:
  // Opens the chosen NIC; on error nothing is open and the error says why (see RawSocketNic::open).
  // `receive_spin`: how long a raw socket (or the simulated robot on the wall clock) waits for a frame
  // by reading before it sleeps (the master's default; 0 sleeps at
  // once, as a normally scheduled master like SOEM's does).
  Status open(const NicChoice& choice, hal::Nanoseconds receive_spin = kMasterReceiveSpin) noexcept;
  // The clock the simulated robot runs on (default: CLOCK_MONOTONIC; a VirtualClock runs it
  // faster than real time). Set before open().
  void set_simulation_clock(hal::Clock& clock) noexcept { simulation_clock_ = &clock; }
  // The open NIC; nullptr before a successful open().
  hal::Nic* nic() noexcept { return active_; }

 private:
  hal::RawSocketNic raw_;
  FixedVector<drivers::SimulatedNic, 1> simulated_;  // the loopback NIC over the simulated robot
  hal::Clock* simulation_clock_{nullptr};
  hal::Nic* active_{nullptr};
};

// Prints "rescue-motion COMMAND: cannot open NIC_TEXT: reason (kind[, OS reason])" to stderr and
// returns the exit status of a failed command.
int fail_nic(const char* command, const char* nic_text, const Error& error) noexcept;

}  // namespace rescue::app
