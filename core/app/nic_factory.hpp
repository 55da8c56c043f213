// Creates, at start-up, the NIC that `--nic` chose, inside storage this object owns (no heap):
// the raw socket on a named interface, or the in-process simulated segment.
#pragma once

#include "core/app/nic_option.hpp"
#include "core/result.hpp"
#include "hal/nic.hpp"
#include "hal/raw_socket_nic.hpp"

namespace rescue::app {

class SelectedNic {
 public:
  // Opens the chosen NIC; on error nothing is open and the error says why (see RawSocketNic::open).
  Status open(const NicChoice& choice) noexcept;
  // The open NIC; nullptr before a successful open().
  hal::Nic* nic() noexcept { return active_; }

 private:
  hal::RawSocketNic raw_;
  // The simulated segment's loopback NIC (drivers/) joins here once it is on main.
  hal::Nic* active_{nullptr};
};

// Prints "rescue-motion COMMAND: cannot open NIC_TEXT: reason (kind[, OS reason])" to stderr and
// returns the exit status of a failed command.
int fail_nic(const char* command, const char* nic_text, const Error& error) noexcept;

}  // namespace rescue::app
