// A junction slave: an ESC with four ports and no application (no mailbox, no process data), like
// the EtherCAT junction modules the robot's switch box is built from. Its SII carries its own
// identity and name so the master can tell the two junctions apart.
#pragma once

#include <array>
#include <cstdint>

#include "drivers/joint/device_identity.hpp"
#include "drivers/sim/devices/minimal_sii.hpp"
#include "drivers/sim/devices/slave_device.hpp"

namespace rescue::drivers {

class JunctionDevice final : public SlaveDevice {
 public:
  // The junction built into slot `position` of kSlaves: identity kJunctionIdentity, its own serial
  // number and commissioned station alias (drivers/joint/device_identity.hpp).
  explicit JunctionDevice(std::size_t position) noexcept;
  // A spare junction, not commissioned (station alias 0), with serial number `serial`.
  struct Spare {
    std::uint32_t serial;
  };
  explicit JunctionDevice(Spare spare) noexcept;

  ConstByteSpan sii_image() const noexcept override { return {sii_.data(), sii_length_}; }
  ProcessDataLayout process_data_layout() const noexcept override { return {2, 0, 3, 0}; }
  std::uint16_t on_state_change(AlState, AlState, EscPdi&) noexcept override { return 0; }
  void on_mailbox(ConstByteSpan, EscPdi&) noexcept override {}
  void on_cycle(ConstByteSpan, ByteSpan, const CycleContext&, EscPdi&) noexcept override {}
  void step(hal::Nanoseconds, EscPdi&) noexcept override {}
  void inject_fault(std::uint16_t) noexcept override {}

 private:
  std::array<std::uint8_t, minimal_sii_size(constexpr_length(kJunctionIdentity.name))> sii_{};
  std::size_t sii_length_{0};
};

}  // namespace rescue::drivers
