// Test double: a slave device that is only its EEPROM (the given SII bytes) and a process-data
// layout, with no application behind it (state changes accepted, mailbox and cycles ignored). For
// tests that need a device of another make, a real device's image, or a damaged one. Tests only.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "drivers/sim/devices/minimal_sii.hpp"
#include "drivers/sim/devices/slave_device.hpp"

namespace rescue::testing {

class SiiImageDevice final : public drivers::SlaveDevice {
 public:
  explicit SiiImageDevice(std::vector<std::uint8_t> image, drivers::ProcessDataLayout layout = {2, 0, 3, 0})
      : image_(std::move(image)), layout_(layout) {}

  // A device with the minimal SII of `identity` and `name` (drivers/sim/devices/minimal_sii.hpp).
  static std::vector<std::uint8_t> minimal_image(const drivers::SiiIdentity& identity, const char* name) {
    std::vector<std::uint8_t> bytes(256);
    bytes.resize(drivers::build_minimal_sii(ByteSpan(bytes.data(), bytes.size()), identity, name).value_or(0));
    return bytes;
  }

  ConstByteSpan sii_image() const noexcept override { return {image_.data(), image_.size()}; }
  drivers::ProcessDataLayout process_data_layout() const noexcept override { return layout_; }
  std::uint16_t on_state_change(drivers::AlState, drivers::AlState, drivers::EscPdi&) noexcept override { return 0; }
  void on_mailbox(ConstByteSpan, drivers::EscPdi&) noexcept override {}
  void on_cycle(ConstByteSpan, ByteSpan, const drivers::CycleContext&, drivers::EscPdi&) noexcept override {}
  void step(hal::Nanoseconds, drivers::EscPdi&) noexcept override {}
  void inject_fault(std::uint16_t) noexcept override {}

 private:
  std::vector<std::uint8_t> image_;
  drivers::ProcessDataLayout layout_;
};

}  // namespace rescue::testing
