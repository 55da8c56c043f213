// One SyncManager of a simulated ESC (registers 0x0800 + 8n) and the buffer it guards.
//
//   mailbox mode (1 buffer)   the writer fills the whole buffer, writing its last byte makes it
//                             full; the reader empties it by reading the last byte. The master may
//                             write an ECAT-write mailbox only while it is empty and read an
//                             ECAT-read mailbox only while it is full; other accesses are refused
//                             (no working counter), which is how masters poll mailboxes.
//   buffered mode (3 buffers) the ESC redirects accesses to [start, start+length) into one of three
//                             buffers (start + k * length): the writer always has a free buffer,
//                             the reader always gets the newest complete one. The master's write
//                             of the last byte completes a buffer (an "SM event" for the device).
//
// An SM is active when the master enabled it (0x0806 bit 0) and the device did not deactivate it
// (0x0807 bit 0); a deactivated SM locks its memory area, a disabled one leaves it as plain memory.
// The ESC mirrors the state in the status register 0x0805: written (bit 0), read (bit 1), mailbox
// full (bit 3), last written buffer (bits 4-5, 3 = none).
#pragma once

#include <cstdint>

#include "core/base/span.hpp"
#include "drivers/sim/esc/esc_memory.hpp"

namespace rescue::drivers {

class EscSyncManager {
 public:
  // What a completed master access did, for the device side to react to at the end of the frame.
  enum class Event : std::uint8_t { none, mailbox_written, mailbox_read, buffer_written, buffer_read };

  void reset(unsigned index) noexcept;
  // Re-reads the configuration after the master wrote the SM's registers.
  void load(EscMemory& memory) noexcept;

  unsigned index() const noexcept { return index_; }
  std::uint32_t start() const noexcept { return start_; }
  std::uint32_t length() const noexcept { return length_; }
  std::uint8_t control() const noexcept { return control_; }
  bool enabled_by_master() const noexcept { return enabled_; }
  bool active() const noexcept { return enabled_ && !deactivated_ && length_ > 0; }
  // Guards accesses: enabled by the master and non-empty (active, or locked by the device).
  bool guards(std::uint32_t address) const noexcept {
    return enabled_ && length_ > 0 && address >= start_ && address < start_ + length_;
  }
  bool mailbox_mode() const noexcept { return (control_ & 0x03U) == 0x02U; }
  bool master_writes() const noexcept { return ((control_ >> 2U) & 0x03U) == 0x01U; }
  bool watchdog_trigger() const noexcept { return (control_ & 0x40U) != 0; }
  bool mailbox_full() const noexcept { return full_; }

  // Master access to [address, address + count), all inside this SM's area. Reads copy into
  // `frame` (ORed when `or_into_frame`), writes copy from it. Returns false when the SM refuses.
  bool master_read(EscMemory& memory, std::uint32_t address, std::uint8_t* frame, std::uint32_t count,
                   bool or_into_frame) noexcept;
  bool master_write(EscMemory& memory, std::uint32_t address, const std::uint8_t* frame, std::uint32_t count,
                    std::uint8_t mask_of_single_byte = 0xFF) noexcept;
  // Events of the frame so far; cleared by take_event().
  Event take_event() noexcept {
    const Event e = event_;
    event_ = Event::none;
    return e;
  }

  // Device side (PDI).
  void set_deactivated_by_device(EscMemory& memory, bool deactivated) noexcept;
  // The buffer the device reads: the mailbox, or the newest complete buffer (ECAT-write SMs).
  ConstByteSpan device_read_buffer(const EscMemory& memory) const noexcept;
  // Marks the mailbox read by the device (empty again).
  void device_consumed_mailbox(EscMemory& memory) noexcept;
  // The buffer the device fills next (ECAT-read SMs); publish with device_published().
  ByteSpan device_write_buffer(EscMemory& memory) noexcept;
  void device_published(EscMemory& memory) noexcept;

 private:
  std::uint32_t buffer_address(unsigned buffer, std::uint32_t address) const noexcept {
    return address + buffer * length_;
  }
  unsigned free_buffer() const noexcept;
  void restart(EscMemory& memory) noexcept;
  void set_status(EscMemory& memory) const noexcept;
  bool fits_in_memory(const EscMemory& memory) const noexcept;

  unsigned index_{0};
  std::uint32_t register_base_{0};
  std::uint32_t start_{0};
  std::uint32_t length_{0};
  std::uint8_t control_{0};
  bool enabled_{false};
  bool deactivated_{false};
  // Mailbox state.
  bool full_{false};
  bool written_flag_{false};
  bool read_flag_{false};
  // Buffered state: the buffer the writer fills, and the newest complete one (3 = none).
  unsigned writer_buffer_{0};
  unsigned newest_buffer_{3};
  Event event_{Event::none};
};

}  // namespace rescue::drivers
