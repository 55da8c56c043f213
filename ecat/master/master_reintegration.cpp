// Re-integration of restored slaves while cycling (an explicit action of the master's owner).
// A slave whose link came back kept its configuration (station address, SyncManagers, DC offset
// and delay, SYNC0), except the FMMUs the master switched off when it was lost; its process-data
// watchdog has usually taken it to SAFE-OP with an error (0x001B). So, one datagram per cycle:
//   fmmus        FPWR 0x0600: FMMU0 (outputs) and FMMU1 (inputs) as at bring-up
//   status       FPRD 0x0130: OP -> done; error -> acknowledge; SAFE-OP -> request OP;
//                below SAFE-OP -> failed (needs a bring-up: its SMs/DC may be gone)
//   acknowledge  FPWR 0x0120 = SAFE-OP + error acknowledge, then status again
//   request_op   FPWR 0x0120 = OP, then status again
// Its outputs stay all-zero until it is back in the exchange (silence_outputs_of_out_slaves).
//
// Re-arming uses the same steps from `acknowledge`: a slave the watchdog check found in SAFE-OP by
// its watchdog after the master's silence (link_monitor.hpp, item 5). It kept its FMMUs and stays
// in the exchange meanwhile; its datagrams leave room for a mailbox step like the probes.
#include <cstring>

#include "ecat/master/master.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/master/slave_config.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kAlStatusReadLength = 6;
constexpr hal::Nanoseconds kReintegrationTimeout = 3 * hal::kNsPerSec;
constexpr std::size_t kRearmRoom = 2 * kDatagramOverhead + 1 + 256 + kDatagramOverhead + kAlStatusReadLength;
constexpr std::uint16_t kOp = static_cast<std::uint16_t>(reg::AlState::op);
constexpr std::uint16_t kSafeOp = static_cast<std::uint16_t>(reg::AlState::safe_op);

}  // namespace

bool Master::reintegrate(SlaveMask slaves) noexcept {
  if (slaves == 0 || reintegrating_ != 0 || state_ != MasterState::op || options_.online_recovery) return false;
  if ((slaves & ~monitor_.restored()) != 0) return false;
  reintegrating_ = slaves;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((slaves & slave_bit(p)) != 0) re_step_[p] = ReStep::fmmus;
  }
  re_deadline_ = link_.clock().now() + kReintegrationTimeout;
  return true;
}

void Master::start_rearm(SlaveMask slaves) noexcept {
  slaves &= ~reintegrating_;
  if (slaves == 0) return;
  if (rearming_ == 0) rearm_deadline_ = link_.clock().now() + kReintegrationTimeout;
  rearming_ |= slaves;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((slaves & slave_bit(p)) != 0) re_step_[p] = ReStep::acknowledge;
  }
}

void Master::add_reintegration_datagrams(FrameBuilder& frame) noexcept {
  const std::uint8_t index = link_.index();
  rearming_ &= monitor_.in_exchange();  // one the probes took out is the monitor's (and recovery's) now
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if (((reintegrating_ | rearming_) & slave_bit(p)) == 0) continue;
    if ((rearming_ & slave_bit(p)) != 0 && frame.remaining_data_capacity() < kRearmRoom) continue;
    const std::uint16_t station = plan_[p].station_address;
    Result<DatagramSlot> added = make_error(Errc::capacity_exceeded, "no room");
    std::array<std::uint8_t, std::size_t{2} * reg::kFmmuSize> bytes{};
    switch (re_step_[p]) {
      case ReStep::fmmus: {
        fill_fmmus(p, bytes.data());
        added = frame.add(Command::FPWR, index, make_address(station, reg::fmmu(kFmmuOutputs)), 2 * reg::kFmmuSize,
                          ConstByteSpan(bytes));
        break;
      }
      case ReStep::status:
        added = frame.add(Command::FPRD, index, make_address(station, reg::kAlStatus), kAlStatusReadLength);
        break;
      case ReStep::acknowledge:
      case ReStep::request_op:
        store_le16(bytes.data(), re_step_[p] == ReStep::acknowledge ? static_cast<std::uint16_t>(kSafeOp | reg::kAlErrorBit) : kOp);
        added = frame.add(Command::FPWR, index, make_address(station, reg::kAlControl), 2, ConstByteSpan(bytes.data(), 2));
        break;
    }
    if (added.ok()) planned_[planned_count_++] = Planned{Role::reintegration, static_cast<std::uint8_t>(p)};
  }
}

void Master::on_reintegration_datagram(std::size_t p, const DatagramView& d) noexcept {
  if (p >= kMaxSlaves || ((reintegrating_ | rearming_) & slave_bit(p)) == 0 || d.wkc() != 1) return;  // no answer: same step again
  const hal::Nanoseconds now = link_.clock().now();
  const bool rearm = (rearming_ & slave_bit(p)) != 0;
  switch (re_step_[p]) {
    case ReStep::fmmus:
    case ReStep::acknowledge:
    case ReStep::request_op:
      re_step_[p] = ReStep::status;
      break;
    case ReStep::status: {
      const std::uint16_t status = load_le16(d.data().data());
      note_al_status(p, d.data().data());
      const std::uint16_t al_state = status & reg::kAlStateMask;
      if ((status & reg::kAlErrorBit) == 0 && al_state == kOp && rearm) {
        rearming_ &= ~slave_bit(p);
        monitor_.rearmed(slave_bit(p), cycle_, now);
      } else if ((status & reg::kAlErrorBit) == 0 && al_state == kOp) {
        reintegrating_ &= ~slave_bit(p);
        monitor_.reintegrated(slave_bit(p), cycle_, now);
      } else if ((status & reg::kAlErrorBit) != 0) {
        re_step_[p] = ReStep::acknowledge;
      } else if (al_state == kSafeOp) {
        re_step_[p] = ReStep::request_op;
      } else if (rearm) {
        rearming_ &= ~slave_bit(p);
        monitor_.rearm_failed(slave_bit(p), cycle_, now, status, load_le16(d.data().data() + 4));
      } else {
        reintegrating_ &= ~slave_bit(p);
        monitor_.reintegration_failed(slave_bit(p), cycle_, now, status, load_le16(d.data().data() + 4));
      }
      break;
    }
  }
}

void Master::finish_reintegration_step() noexcept {
  start_rearm(monitor_.take_rearm_requests());
  if (rearming_ != 0 && link_.clock().now() > rearm_deadline_) {
    monitor_.rearm_failed(rearming_, cycle_, link_.clock().now(), 0, 0);
    rearming_ = 0;
  }
  if (reintegrating_ == 0 || link_.clock().now() <= re_deadline_) return;
  monitor_.reintegration_failed(reintegrating_, cycle_, link_.clock().now(), 0, 0);
  reintegrating_ = 0;
}

}  // namespace rescue::ecat
