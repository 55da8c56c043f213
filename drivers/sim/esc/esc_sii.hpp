// The SII EEPROM and the ESC's EEPROM interface (registers 0x0500-0x050F).
//
// The master writes a command (0x0502 bits 8-10: 1 read, 2 write, 4 reload) together with or after
// the word address (0x0504); the command starts at the end of that frame. While it runs the busy bit
// (0x0502 bit 15) is set and the command bits read back; the interface ignores further writes. A read
// then fills 0x0508 with 4 or 8 bytes (0x0502 bit 6 says which). Errors: an address beyond the
// EEPROM or an unknown command sets bit 13 ("missing acknowledge / invalid command"), a write
// without write enable (bit 0, in the same write) sets bit 14; writing the control register
// (e.g. a NOP) clears them. At power-up the ESC checks the configuration area's CRC (word 7): a bad
// CRC sets bits 11 and 12 and leaves the alias and PDI configuration unloaded.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/span.hpp"
#include "drivers/sim/esc/esc_config.hpp"
#include "drivers/sim/esc/esc_memory.hpp"
#include "hal/time/clock.hpp"

namespace rescue::drivers {

constexpr std::size_t kMaxEepromBytes = std::size_t{8} * 1024;  // 64 kbit

class EscSii {
 public:
  // Loads `image` into the EEPROM (erased bytes read 0xFF) and resets the interface registers.
  // The EEPROM size comes from word 0x3E ((kbit + 1) * 128 bytes), at least the image's size.
  void power_up(EscMemory& memory, const EscConfig& config, ConstByteSpan image) noexcept;

  bool configuration_valid() const noexcept { return configuration_valid_; }
  std::uint16_t word(std::uint32_t address) const noexcept;
  // Overwrites one EEPROM word (a device of another identity: the simulator's foreign device).
  void set_word(std::uint32_t address, std::uint16_t value) noexcept;

  // The master wrote the interface registers 0x0502..0x050F: `written` holds the new bytes of the
  // 14-byte block, `mask` which of them the datagram wrote. Applied now unless busy.
  void on_master_write(EscMemory& memory, const std::uint8_t* written, const bool* mask) noexcept;
  // End of the frame: a command written in it starts now.
  void start_pending(EscMemory& memory, hal::Nanoseconds now) noexcept;
  // Completes a running command whose time is up.
  void update(EscMemory& memory, hal::Nanoseconds now) noexcept;
  bool busy() const noexcept { return busy_; }
  // True once after a reload command completed (the ESC then re-applies the configuration area).
  bool take_reload_done() noexcept {
    const bool done = reload_done_;
    reload_done_ = false;
    return done;
  }

 private:
  void finish(EscMemory& memory) noexcept;

  std::size_t size_{0};
  bool configuration_valid_{false};
  std::uint8_t read_bytes_{8};
  hal::Nanoseconds read_busy_ns_{0};
  hal::Nanoseconds write_busy_ns_{0};
  bool pending_{false};
  bool busy_{false};
  std::uint16_t command_{0};
  bool reload_done_{false};
  hal::Nanoseconds done_at_{0};
  // Last: the flags above are read every frame, the EEPROM only by commands.
  std::array<std::uint8_t, kMaxEepromBytes> eeprom_{};
};

}  // namespace rescue::drivers
