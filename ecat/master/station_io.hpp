// Bring-up helper: the same register access on many slaves at once, one datagram per slave
// (configured-address commands), as few frames as fit. `fill(position, ByteSpan)` writes the data
// of a slave's datagram before sending (for writing commands); `read(position, wkc, ConstByteSpan)`
// gets each returned datagram. A frame that does not come back is sent again, `attempts` times and,
// during a bring-up, until the link's repeat_silence() has passed (DatagramLink::set_repeat_silence).
#pragma once

#include <array>
#include <cstdint>

#include "core/base/result.hpp"
#include "ecat/link/datagram_link.hpp"
#include "ecat/link/network_plan.hpp"

namespace rescue::ecat {

template <typename Fill, typename Read>
Status for_each_slave(DatagramLink& link, const NetworkPlan& plan, SlaveMask slaves, Command command,
                      std::uint16_t ado, std::uint16_t length, Fill&& fill, Read&& read,
                      hal::Nanoseconds timeout, unsigned attempts = 3) noexcept {
  std::size_t next = 0;
  while (next < kMaxSlaves) {
    std::size_t end = next;
    Result<FrameView> back = make_error(Errc::timeout, "no frame came back");
    std::array<std::uint8_t, kMaxSlaves> position_of{};
    const hal::Nanoseconds first_sent = link.clock().now();
    const unsigned most = link.most_sends(timeout, attempts);
    for (unsigned sends = 0; sends < most && !link.may_give_up(first_sent, sends, attempts); ++sends) {
      FrameBuilder& frame = link.begin();
      std::size_t count = 0;
      end = next;
      for (; end < kMaxSlaves; ++end) {
        if ((slaves & slave_bit(end)) == 0) continue;
        if (frame.remaining_data_capacity() < length) break;
        const Result<DatagramSlot> slot =
            frame.add(command, link.index(), make_address(plan[end].station_address, ado), length);
        if (!slot.ok()) return slot.error();
        if (writes_slave(command)) fill(end, frame.data(slot.value()));
        position_of[count++] = static_cast<std::uint8_t>(end);
      }
      if (count == 0) return Status::success();
      back = link.exchange(link.clock().now() + timeout);
      if (back.ok() || back.error().code != Errc::timeout) break;
    }
    if (!back.ok()) return back.error();
    std::size_t i = 0;
    for (const DatagramView d : back.value()) read(position_of[i++], d.wkc(), ConstByteSpan(d.data()));
    next = end;
  }
  return Status::success();
}

// Same value for every slave.
template <typename Read>
Status write_each_slave(DatagramLink& link, const NetworkPlan& plan, SlaveMask slaves, std::uint16_t ado,
                        ConstByteSpan value, Read&& read, hal::Nanoseconds timeout) noexcept {
  return for_each_slave(
      link, plan, slaves, Command::FPWR, ado, static_cast<std::uint16_t>(value.size()),
      [&](std::size_t, ByteSpan out) {
        for (std::size_t i = 0; i < value.size(); ++i) out[i] = value[i];
      },
      read, timeout);
}

}  // namespace rescue::ecat
