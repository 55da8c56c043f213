// Logical addressing (LRD, LWR, LRW) through the ESC's FMMUs.
#include <algorithm>

#include "drivers/sim/esc/esc.hpp"

namespace rescue::drivers {

using ecat::Command;

void Esc::process_logical(const ecat::MutableDatagramView& d) noexcept {
  const Command command = d.command();
  const ByteSpan data = d.data();
  const auto count = static_cast<std::uint32_t>(data.size());
  if (fmmus_dirty_) reload_fmmus();
  // Outside every FMMU of a direction, no FMMU of it would find an overlap: most logical
  // datagrams of a frame are for other slaves, and are passed on here at once.
  const std::uint64_t first_bit = std::uint64_t{d.address()} * 8U;
  const std::uint64_t end_bit = (std::uint64_t{d.address()} + count) * 8U;
  const auto reaches = [&](unsigned direction) {
    return first_bit < fmmu_end_bit_[direction] && end_bit > fmmu_first_bit_[direction];
  };
  // LRW: the memory takes the data as it arrives (write FMMUs first), then the frame leaves with
  // what the read FMMUs map (the same logical bytes may be both).
  bool wrote = false;
  bool read = false;
  if ((command == Command::LWR || command == Command::LRW) && reaches(1)) {
    wrote = logical_pass(d.address(), data.data(), count, true);
  }
  if ((command == Command::LRD || command == Command::LRW) && reaches(0)) {
    read = logical_pass(d.address(), data.data(), count, false);
  }
  unsigned increment = 0;
  if (read) increment += 1;
  if (wrote) increment += command == Command::LRW ? 2U : 1U;
  if (increment != 0) d.set_wkc(static_cast<std::uint16_t>(d.wkc() + increment));
}

void Esc::reload_fmmus() noexcept {
  fmmu_first_bit_.fill(~std::uint64_t{0});
  fmmu_end_bit_.fill(0);
  for (unsigned n = 0; n < config_.fmmu_count; ++n) {
    const EscFmmu& f = fmmus_[n] = EscFmmu::load(memory_, n);
    if (!f.active) continue;
    for (unsigned direction = 0; direction < 2; ++direction) {
      if ((f.type & (1U << direction)) == 0) continue;
      fmmu_first_bit_[direction] = std::min(fmmu_first_bit_[direction], f.first_bit());
      fmmu_end_bit_[direction] = std::max(fmmu_end_bit_[direction], f.end_bit());
    }
  }
  fmmus_dirty_ = false;
}

bool Esc::logical_pass(std::uint32_t logical, std::uint8_t* frame, std::uint32_t count, bool write) noexcept {
  const std::uint8_t wanted = write ? 0x02 : 0x01;
  bool any = false;
  for (unsigned n = 0; n < config_.fmmu_count; ++n) {
    const EscFmmu& f = fmmus_[n];
    if (!f.active || (f.type & wanted) == 0) continue;
    const bool ok = f.byte_aligned() ? fmmu_byte_aligned(f, logical, frame, count, write)
                                     : fmmu_bitwise(f, logical, frame, count, write);
    any = any || ok;
  }
  return any;
}

bool Esc::fmmu_byte_aligned(const EscFmmu& f, std::uint32_t logical, std::uint8_t* frame, std::uint32_t count,
                            bool write) noexcept {
  const std::uint64_t datagram_end = std::uint64_t{logical} + count;
  const std::uint64_t fmmu_end = std::uint64_t{f.logical_start} + f.length;
  const std::uint64_t first = logical > f.logical_start ? logical : f.logical_start;
  const std::uint64_t end = datagram_end < fmmu_end ? datagram_end : fmmu_end;
  if (first >= end) return false;
  const auto offset = static_cast<std::uint32_t>(first - logical);
  const auto physical = static_cast<std::uint32_t>(f.physical_start + (first - f.logical_start));
  const auto n = static_cast<std::uint32_t>(end - first);
  return write ? write_range(physical, frame + offset, n) : read_range(physical, frame + offset, n, false);
}

bool Esc::fmmu_bitwise(const EscFmmu& f, std::uint32_t logical, std::uint8_t* frame, std::uint32_t count,
                       bool write) noexcept {
  const std::uint64_t first = std::max<std::uint64_t>(f.first_bit(), std::uint64_t{logical} * 8U);
  const std::uint64_t end = std::min<std::uint64_t>(f.end_bit(), (std::uint64_t{logical} + count) * 8U);
  if (first >= end) return false;
  const std::uint64_t physical_first = std::uint64_t{f.physical_start} * 8U + f.physical_start_bit;
  bool any = false;
  // Bits are gathered per physical byte: each physical byte is accessed once (SyncManager rules
  // and read side effects apply per byte).
  std::uint64_t current = ~std::uint64_t{0};
  std::uint8_t value = 0;
  std::uint8_t mask = 0;
  bool readable = false;
  const auto flush = [&]() {
    if (write && mask != 0 && current < kEscMemorySize && write_byte_masked(static_cast<std::uint32_t>(current), value, mask)) {
      any = true;
    }
  };
  for (std::uint64_t bit = first; bit < end; ++bit) {
    const std::uint64_t physical_bit = physical_first + (bit - f.first_bit());
    const std::uint64_t physical_byte = physical_bit / 8U;
    if (physical_byte != current) {
      flush();
      current = physical_byte;
      value = 0;
      mask = 0;
      if (!write) {
        readable = current < kEscMemorySize && read_range(static_cast<std::uint32_t>(current), &value, 1, false);
        any = any || readable;
      }
    }
    const auto frame_byte = static_cast<std::uint32_t>(bit / 8U - logical);
    const auto frame_mask = static_cast<std::uint8_t>(1U << (bit % 8U));
    const auto memory_mask = static_cast<std::uint8_t>(1U << (physical_bit % 8U));
    if (write) {
      mask = static_cast<std::uint8_t>(mask | memory_mask);
      if ((frame[frame_byte] & frame_mask) != 0) value = static_cast<std::uint8_t>(value | memory_mask);
    } else if (readable) {
      frame[frame_byte] = static_cast<std::uint8_t>((value & memory_mask) != 0 ? (frame[frame_byte] | frame_mask)
                                                                               : (frame[frame_byte] & ~frame_mask));
    }
  }
  flush();
  return any;
}

}  // namespace rescue::drivers
