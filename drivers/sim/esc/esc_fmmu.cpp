#include "drivers/sim/esc/esc_fmmu.hpp"

#include "ecat/codec/registers.hpp"

namespace rescue::drivers {

EscFmmu EscFmmu::load(const EscMemory& memory, unsigned index) noexcept {
  namespace reg = ecat::reg;
  const std::uint32_t base = reg::fmmu(index);
  EscFmmu f;
  f.logical_start = memory.u32(base + reg::kFmmuLogicalStart);
  f.length = memory.u16(base + reg::kFmmuLength);
  f.logical_start_bit = static_cast<std::uint8_t>(memory.u8(base + reg::kFmmuLogicalStartBit) & 0x07U);
  f.logical_stop_bit = static_cast<std::uint8_t>(memory.u8(base + reg::kFmmuLogicalStopBit) & 0x07U);
  f.physical_start = memory.u16(base + reg::kFmmuPhysicalStart);
  f.physical_start_bit = static_cast<std::uint8_t>(memory.u8(base + reg::kFmmuPhysicalStartBit) & 0x07U);
  f.type = static_cast<std::uint8_t>(memory.u8(base + reg::kFmmuType) & 0x03U);
  f.active = (memory.u8(base + reg::kFmmuActivate) & 0x01U) != 0 && f.length > 0 && f.type != 0;
  return f;
}

}  // namespace rescue::drivers
