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

// How the master's raw socket waits for its frame (hal::RawSocketSettings::ReceiveWait). sleep: the
// least CPU per cycle of the three on the veth link (docs/timing.md "CPU per cycle": median 49 us
// against spin's 66 and adaptive's 72, SOEM at the same priority and CPU 52).
constexpr hal::RawSocketSettings::ReceiveWait kMasterReceiveWait = hal::RawSocketSettings::ReceiveWait::sleep;
struct ReceiveWaitChoice {
  hal::RawSocketSettings::ReceiveWait wait{kMasterReceiveWait};
  hal::Nanoseconds spin{kMasterReceiveSpin};
  hal::Nanoseconds adaptive_lead{config::kMasterAdaptiveLeadNs};
};

class SelectedNic {
 public:
  // Opens the chosen NIC; on error nothing is open and the error says why (see RawSocketNic::open).
  // `receive_spin`: how long a raw socket (or the simulated robot on the wall clock) waits for a frame
  // by reading before it sleeps (the master's default; 0 sleeps at
  // once, as a normally scheduled master like SOEM's does).
  Status open(const NicChoice& choice, hal::Nanoseconds receive_spin = kMasterReceiveSpin) noexcept;
  // The same with the raw socket's whole receive wait chosen (the simulated robot takes its spin).
  Status open(const NicChoice& choice, const ReceiveWaitChoice& wait) noexcept;
  // --ring-nic (cable redundancy, docs/redundancy.md): opens the second master port after open().
  // raw: a second raw socket on another interface (its own receive wait as the main one's). sim: the
  // in-process simulated robot's ring port. THE SEAM for the simulator's ring (issue 34, item 1): when
  // drivers/sim's robot exposes its ring hal::Nic, open_ring takes it from the same robot as open()
  // took the main one; until then `--ring-nic sim` is refused with that reason, never run on one port.
  Status open_ring(const NicChoice& choice, const ReceiveWaitChoice& wait = ReceiveWaitChoice{}) noexcept;
  // The open NIC; nullptr before a successful open().
  hal::Nic* nic() noexcept { return active_; }
  // The ring NIC; nullptr without a successful open_ring().
  hal::Nic* ring_nic() noexcept { return ring_; }
  // The raw socket when that is the open NIC, else nullptr (its receive-wait figures).
  const hal::RawSocketNic* raw() const noexcept { return active_ == &raw_ ? &raw_ : nullptr; }

 private:
  hal::RawSocketNic raw_;
  FixedVector<drivers::SimulatedNic, 1> simulated_;  // the loopback NIC over the simulated robot
  hal::Nic* active_{nullptr};
  hal::RawSocketNic ring_raw_;
  hal::Nic* ring_{nullptr};
};

// Prints "rescue-motion COMMAND: cannot open NIC_TEXT: reason (kind[, OS reason])" to stderr and
// returns the exit status of a failed command.
int fail_nic(const char* command, const char* nic_text, const Error& error) noexcept;

}  // namespace rescue::app
