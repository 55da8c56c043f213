// The network card under the EtherCAT master. Two implementations are chosen at start-up
// (`--nic sim|raw:IFACE`): a Linux AF_PACKET raw socket on a named interface (hal/net/raw_socket_nic)
// and the in-process simulated segment (drivers/, loopback). The master sees only this interface.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "hal/time/clock.hpp"

namespace rescue::hal {

struct NicStats {
  std::uint64_t frames_sent{0};
  std::uint64_t frames_received{0};
  std::uint64_t send_errors{0};
  std::uint64_t receive_timeouts{0};
  std::uint64_t frames_dropped{0};  // received but not EtherCAT, or too long for the buffer
};

class Nic {
 public:
  Nic() = default;
  Nic(const Nic&) = delete;
  Nic& operator=(const Nic&) = delete;
  Nic(Nic&&) = delete;
  Nic& operator=(Nic&&) = delete;
  virtual ~Nic() = default;

  // Sends one complete Ethernet frame (destination MAC onwards, no FCS), at most 1514 bytes.
  virtual Status send(ConstByteSpan frame) noexcept = 0;

  // Receives the next EtherCAT frame into `buffer`, waiting at most until `deadline` on the
  // NIC's clock. Returns the frame's length, or Errc::timeout when none arrived in time.
  // Frames of other EtherTypes are dropped (and counted), never returned.
  virtual Result<std::size_t> receive(ByteSpan buffer, Nanoseconds deadline) noexcept = 0;

  // The clock that receive deadlines refer to (virtual time for the simulator).
  virtual Clock& clock() noexcept = 0;

  // When the frame the last successful receive() returned reached this NIC, on clock(): the
  // kernel's receive timestamp where the NIC takes them (RawSocketSettings::receive_timestamps),
  // which a busy host does not delay as it delays the reader. Errc::unsupported when the NIC takes
  // none, Errc::not_found when that frame came without one: the caller then reads clock() itself.
  virtual Result<Nanoseconds> last_receive_time() const noexcept {
    return make_error(Errc::unsupported, "this NIC takes no receive timestamps");
  }

  virtual const char* name() const noexcept = 0;
  virtual NicStats stats() const noexcept = 0;
};

}  // namespace rescue::hal
