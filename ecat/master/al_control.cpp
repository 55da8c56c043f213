#include "ecat/master/al_control.hpp"

#include <cstdio>

#include "ecat/master/station_io.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kAlStatusReadLength = 6;  // 0x0130 status, 0x0132 reserved, 0x0134 code

Status write_al_control(DatagramLink& link, const NetworkPlan& plan, SlaveMask slaves, std::uint16_t value,
                        hal::Nanoseconds timeout, SlaveMask& unreachable) noexcept {
  std::array<std::uint8_t, 2> bytes{};
  store_le16(bytes.data(), value);
  return write_each_slave(
      link, plan, slaves, reg::kAlControl, ConstByteSpan(bytes),
      [&](std::size_t p, std::uint16_t wkc, ConstByteSpan) {
        if (wkc != 1) unreachable |= slave_bit(p);
      },
      timeout);
}

}  // namespace

Result<AlSnapshot> read_al_status(DatagramLink& link, const NetworkPlan& plan, SlaveMask slaves,
                                  hal::Nanoseconds frame_timeout) noexcept {
  AlSnapshot snapshot;
  const Status st = for_each_slave(
      link, plan, slaves, Command::FPRD, reg::kAlStatus, kAlStatusReadLength, [](std::size_t, ByteSpan) {},
      [&](std::size_t p, std::uint16_t wkc, ConstByteSpan data) {
        if (wkc != 1) return;
        snapshot.answered |= slave_bit(p);
        snapshot.status[p] = load_le16(data.data());
        snapshot.code[p] = load_le16(data.data() + 4);
      },
      frame_timeout);
  if (!st.ok()) return st.error();
  return snapshot;
}

Status request_al_state(DatagramLink& link, const NetworkPlan& plan, SlaveMask slaves, reg::AlState state,
                        const AlOptions& options, AlFailure& failure) noexcept {
  const auto target = static_cast<std::uint16_t>(state);
  failure = AlFailure{};
  failure.requested = state;
  SlaveMask unreachable = 0;
  RESCUE_TRY(write_al_control(link, plan, slaves, target, options.frame_timeout, unreachable));
  std::array<unsigned, kMaxSlaves> refusals{};
  SlaveMask pending = slaves;
  const hal::Nanoseconds deadline = link.clock().now() + options.state_timeout;
  for (;;) {
    if (unreachable != 0) {
      for (std::size_t p = 0; p < kMaxSlaves; ++p) {
        if ((unreachable & slave_bit(p)) == 0) continue;
        failure.position = static_cast<std::uint8_t>(p);
        failure.unreachable = true;
        return make_error(Errc::io_error, "slave does not answer", static_cast<std::uint32_t>(p));
      }
    }
    // The deadline is judged by when the status was asked for, not by when the answer was looked at:
    // a master preempted after the read must not call a slave late that answered in time.
    const hal::Nanoseconds asked_at = link.clock().now();
    const Result<AlSnapshot> snap = read_al_status(link, plan, pending, options.frame_timeout);
    if (!snap.ok()) return snap.error();
    SlaveMask acknowledge = 0;
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      if ((pending & slave_bit(p)) == 0) continue;
      if ((snap.value().answered & slave_bit(p)) == 0) {
        unreachable |= slave_bit(p);
        continue;
      }
      const std::uint16_t status = snap.value().status[p];
      if ((status & reg::kAlErrorBit) == 0 && (status & reg::kAlStateMask) == target) {
        pending &= ~slave_bit(p);
        continue;
      }
      if ((status & reg::kAlErrorBit) != 0) {
        failure.position = static_cast<std::uint8_t>(p);
        failure.al_status = status;
        failure.al_status_code = snap.value().code[p];
        if (++refusals[p] > options.retries) {
          return make_error(Errc::refused, "slave refused state", static_cast<std::uint32_t>(p), snap.value().code[p]);
        }
        acknowledge |= slave_bit(p);
      }
    }
    if (pending == 0) return Status::success();
    if (acknowledge != 0) {
      // Acknowledge the error in the state the slave fell back to, then ask again.
      for (std::size_t p = 0; p < kMaxSlaves; ++p) {
        if ((acknowledge & slave_bit(p)) == 0) continue;
        const auto ack = static_cast<std::uint16_t>((snap.value().status[p] & reg::kAlStateMask) | reg::kAlErrorBit);
        RESCUE_TRY(write_al_control(link, plan, slave_bit(p), ack, options.frame_timeout, unreachable));
      }
      RESCUE_TRY(write_al_control(link, plan, acknowledge, target, options.frame_timeout, unreachable));
    }
    if (asked_at >= deadline) {
      for (std::size_t p = 0; p < kMaxSlaves; ++p) {
        if ((pending & slave_bit(p)) == 0) continue;
        failure.position = static_cast<std::uint8_t>(p);
        failure.al_status = snap.value().status[p];
        failure.al_status_code = snap.value().code[p];
        failure.timed_out = true;
        return make_error(Errc::timeout, "state not reached in time", static_cast<std::uint32_t>(p), failure.al_status);
      }
    }
    link.clock().sleep_until(link.clock().now() + options.poll_interval);
  }
}

std::size_t describe(const AlFailure& f, const NetworkPlan& plan, char* out, std::size_t size) noexcept {
  if (size == 0) return 0;
  const char* name = f.position < kMaxSlaves ? plan[f.position].name : "?";
  const auto state = static_cast<reg::AlState>(f.al_status & reg::kAlStateMask);
  int n = 0;
  if (f.unreachable) {
    n = std::snprintf(out, size, "%s does not answer while going to %s", name, reg::to_string(f.requested));
  } else {
    n = std::snprintf(out, size, "%s %s %s: AL status %#06x (%s%s), code %#06x %s", name,
                      f.timed_out ? "did not reach" : "refused", reg::to_string(f.requested), f.al_status,
                      reg::to_string(state), (f.al_status & reg::kAlErrorBit) != 0 ? ", error" : "", f.al_status_code,
                      reg::explain_al_status_code(f.al_status_code));
  }
  if (n < 0) {
    out[0] = '\0';
    return 0;
  }
  return static_cast<std::size_t>(n) < size ? static_cast<std::size_t>(n) : size - 1;
}

}  // namespace rescue::ecat
