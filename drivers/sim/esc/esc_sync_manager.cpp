#include "drivers/sim/esc/esc_sync_manager.hpp"

#include <cstring>

#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

namespace reg = ecat::reg;
constexpr unsigned kNoBuffer = 3;
constexpr std::uint8_t kStatusWritten = 0x01;
constexpr std::uint8_t kStatusRead = 0x02;
constexpr std::uint8_t kStatusMailboxFull = 0x08;
constexpr std::uint8_t kPdiDeactivate = 0x01;

// Memory and frame never overlap (the frame is the NIC's buffer): plain copies where possible.
void copy_out(const std::uint8_t* from, std::uint8_t* frame, std::uint32_t count, bool or_into_frame) noexcept {
  if (!or_into_frame) {
    std::memcpy(frame, from, count);
    return;
  }
  for (std::uint32_t i = 0; i < count; ++i) frame[i] = static_cast<std::uint8_t>(frame[i] | from[i]);
}

void copy_in(std::uint8_t* to, const std::uint8_t* frame, std::uint32_t count, std::uint8_t single_byte_mask) noexcept {
  if (count == 1 && single_byte_mask != 0xFF) {
    to[0] = static_cast<std::uint8_t>((to[0] & ~single_byte_mask) | (frame[0] & single_byte_mask));
    return;
  }
  std::memcpy(to, frame, count);
}

}  // namespace

void EscSyncManager::reset(unsigned index) noexcept {
  *this = EscSyncManager{};
  index_ = index;
  register_base_ = reg::sync_manager(index);
}

bool EscSyncManager::fits_in_memory(const EscMemory& memory) const noexcept {
  const std::uint32_t buffers = mailbox_mode() ? 1U : 3U;
  return start_ >= kEscRegisterSpace && start_ + buffers * length_ <= memory.ram_end();
}

void EscSyncManager::load(EscMemory& memory) noexcept {
  const bool was_enabled = enabled_;
  const std::uint32_t old_start = start_;
  const std::uint32_t old_length = length_;
  const std::uint8_t old_control = control_;
  start_ = memory.u16(register_base_ + reg::kSmPhysicalStart);
  length_ = memory.u16(register_base_ + reg::kSmLength);
  control_ = memory.u8(register_base_ + reg::kSmControl);
  enabled_ = (memory.u8(register_base_ + reg::kSmActivate) & reg::kSmEnable) != 0;
  deactivated_ = (memory.u8(register_base_ + reg::kSmPdiControl) & kPdiDeactivate) != 0;
  if (was_enabled != enabled_ || old_start != start_ || old_length != length_ || old_control != control_) restart(memory);
}

void EscSyncManager::restart(EscMemory& memory) noexcept {
  full_ = false;
  written_flag_ = false;
  read_flag_ = false;
  writer_buffer_ = 0;
  newest_buffer_ = kNoBuffer;
  set_status(memory);
}

void EscSyncManager::set_status(EscMemory& memory) const noexcept {
  std::uint8_t status = 0;
  if (written_flag_) status |= kStatusWritten;
  if (read_flag_) status |= kStatusRead;
  if (mailbox_mode()) {
    if (full_) status |= kStatusMailboxFull;
  } else {
    status = static_cast<std::uint8_t>(status | (newest_buffer_ << 4U));
  }
  memory.set_u8(register_base_ + reg::kSmStatus, status);
}

unsigned EscSyncManager::free_buffer() const noexcept {
  unsigned b = (writer_buffer_ + 1U) % 3U;
  if (b == newest_buffer_) b = (b + 1U) % 3U;
  return b;
}

bool EscSyncManager::master_read(EscMemory& memory, std::uint32_t address, std::uint8_t* frame, std::uint32_t count,
                                 bool or_into_frame) noexcept {
  if (!active() || master_writes() || !fits_in_memory(memory)) return false;
  const bool reads_last_byte = address + count == start_ + length_;
  if (mailbox_mode()) {
    if (!full_) return false;
    copy_out(memory.at(address), frame, count, or_into_frame);
    if (reads_last_byte) {
      full_ = false;
      read_flag_ = true;
      written_flag_ = false;
      event_ = Event::mailbox_read;
      set_status(memory);
    }
    return true;
  }
  const unsigned buffer = newest_buffer_ == kNoBuffer ? 0U : newest_buffer_;
  copy_out(memory.at(buffer_address(buffer, address)), frame, count, or_into_frame);
  if (reads_last_byte) {
    read_flag_ = true;
    event_ = Event::buffer_read;
    set_status(memory);
  }
  return true;
}

bool EscSyncManager::master_write(EscMemory& memory, std::uint32_t address, const std::uint8_t* frame,
                                  std::uint32_t count, std::uint8_t mask_of_single_byte) noexcept {
  if (!active() || !master_writes() || !fits_in_memory(memory)) return false;
  const bool writes_last_byte = address + count == start_ + length_;
  if (mailbox_mode()) {
    if (full_) return false;
    copy_in(memory.at(address), frame, count, mask_of_single_byte);
    if (writes_last_byte) {
      full_ = true;
      written_flag_ = true;
      read_flag_ = false;
      event_ = Event::mailbox_written;
      set_status(memory);
    }
    return true;
  }
  copy_in(memory.at(buffer_address(writer_buffer_, address)), frame, count, mask_of_single_byte);
  if (writes_last_byte) {
    newest_buffer_ = writer_buffer_;
    writer_buffer_ = free_buffer();
    written_flag_ = true;
    event_ = Event::buffer_written;
    set_status(memory);
  }
  return true;
}

void EscSyncManager::set_deactivated_by_device(EscMemory& memory, bool deactivated) noexcept {
  const std::uint8_t pdi = memory.u8(register_base_ + reg::kSmPdiControl);
  memory.set_u8(register_base_ + reg::kSmPdiControl,
                static_cast<std::uint8_t>(deactivated ? (pdi | kPdiDeactivate) : (pdi & ~kPdiDeactivate)));
  if (deactivated_ != deactivated) {
    deactivated_ = deactivated;
    restart(memory);
  }
}

ConstByteSpan EscSyncManager::device_read_buffer(const EscMemory& memory) const noexcept {
  if (!fits_in_memory(memory)) return {};
  if (mailbox_mode()) return {memory.at(start_), length_};
  const unsigned buffer = newest_buffer_ == kNoBuffer ? 0U : newest_buffer_;
  return {memory.at(start_ + buffer * length_), length_};
}

void EscSyncManager::device_consumed_mailbox(EscMemory& memory) noexcept {
  full_ = false;
  written_flag_ = false;
  read_flag_ = true;
  set_status(memory);
}

ByteSpan EscSyncManager::device_write_buffer(EscMemory& memory) noexcept {
  if (!fits_in_memory(memory)) return {};
  if (mailbox_mode()) return {memory.at(start_), length_};
  writer_buffer_ = newest_buffer_ == kNoBuffer ? 0U : (newest_buffer_ + 1U) % 3U;
  return {memory.at(start_ + writer_buffer_ * length_), length_};
}

void EscSyncManager::device_published(EscMemory& memory) noexcept {
  if (mailbox_mode()) {
    full_ = true;
    written_flag_ = true;
    read_flag_ = false;
  } else {
    newest_buffer_ = writer_buffer_;
    written_flag_ = true;
  }
  set_status(memory);
}

}  // namespace rescue::drivers
