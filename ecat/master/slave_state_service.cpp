// The operator's AL state requests in the cycle frame (slave_state_service.hpp).
#include "ecat/master/slave_state_service.hpp"

#include "core/base/endian.hpp"

namespace rescue::ecat {
namespace {

constexpr std::size_t kStatusBytes = kDatagramOverhead + kAlStatusReadLength;

bool settable(reg::AlState s) noexcept {
  return s == reg::AlState::init || s == reg::AlState::pre_op || s == reg::AlState::safe_op || s == reg::AlState::op;
}

// A recovery state in which the online recovery writes nothing to the slave: it may be parked.
bool recovery_at_rest(RecoveryState s) noexcept {
  return s == RecoveryState::idle || s == RecoveryState::searching || s == RecoveryState::failed ||
         s == RecoveryState::refused;
}

}  // namespace

SlaveMask SlaveStateService::parked() const noexcept {
  SlaveMask mask = 0;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if (ctx_.slaves[p].parked) mask |= slave_bit(p);
  }
  return mask;
}

SlaveStateService::Refusal SlaveStateService::request(SlaveMask slaves, reg::AlState target) noexcept {
  if (state_ != State::idle) return Refusal::busy;
  if (slaves == 0 || (slaves & ~kAllSlaves) != 0 || !settable(target)) return Refusal::bad_request;
  if (ctx_.state != MasterState::op) return Refusal::not_cycling;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((slaves & slave_bit(p)) == 0) continue;
    if (ctx_.plan[p].name == nullptr) return Refusal::bad_request;
    if (!recovery_at_rest(ctx_.slaves[p].recovery.state())) return Refusal::recovering;
  }
  result_ = SlaveStateResult{};
  result_.slaves = slaves;
  result_.target = target;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((slaves & slave_bit(p)) == 0) continue;
    SlaveRecord& slave = ctx_.slaves[p];
    result_.outcome[p] = SlaveStateOutcome::pending;
    errors_[p] = 0;
    const bool by_recovery =
        target == reg::AlState::op && ctx_.options.online_recovery && (ctx_.operated() & slave_bit(p)) != 0;
    step_[p] = by_recovery ? Step::by_recovery : Step::write;
    if (by_recovery) {
      slave.parked = false;  // the online recovery takes it from here (it is out of the exchange)
    } else if (target != reg::AlState::op) {
      // Parked: whatever the recovery was waiting for (a search, a hold-off), it starts afresh
      // once the operator asks for OP.
      slave.parked = true;
      slave.recovery = RecoveryProgress{};
    }
  }
  deadline_ = ctx_.now() + kDeadline;
  state_ = State::running;
  return Refusal::none;
}

bool SlaveStateService::take(SlaveStateResult& out) noexcept {
  if (state_ != State::done) return false;
  out = result_;
  state_ = State::idle;
  return true;
}

void SlaveStateService::add_datagrams(CycleFrame& frame) noexcept {
  if (state_ != State::running) return;
  ++result_.frames;
  std::array<std::uint8_t, 2> value{};
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if (result_.outcome[p] != SlaveStateOutcome::pending || step_[p] == Step::by_recovery) continue;
    if (!frame.fits(kStatusBytes)) return;  // the next frame, then
    const std::uint16_t station = ctx_.plan[p].station_address;
    const auto tag = static_cast<std::uint8_t>(p);
    if (step_[p] == Step::read) {
      (void)frame.add(*this, tag, Command::FPRD, make_address(station, reg::kAlStatus), kAlStatusReadLength);
      continue;
    }
    const bool acknowledge = step_[p] == Step::acknowledge;
    store_le16(value.data(), static_cast<std::uint16_t>(static_cast<std::uint16_t>(result_.target) |
                                                        (acknowledge ? reg::kAlErrorBit : 0U)));
    (void)frame.add(*this, static_cast<std::uint8_t>(tag | kWriteTag), Command::FPWR,
                    make_address(station, reg::kAlControl), 2, ConstByteSpan(value));
  }
}

void SlaveStateService::on_answer(std::uint8_t tag, const DatagramView& d) noexcept {
  const std::size_t p = tag & (kWriteTag - 1U);  // the position, without the write bit
  if (state_ != State::running || p >= kMaxSlaves || result_.outcome[p] != SlaveStateOutcome::pending) return;
  if (d.wkc() != 1) return;  // not taken or not answered: the same datagram next frame
  if ((tag & kWriteTag) != 0) {
    step_[p] = Step::read;
    return;
  }
  if (d.data().size() < kAlStatusReadLength) return;
  const std::uint8_t* data = d.data().data();
  ctx_.slaves[p].note_al_status(data);
  const std::uint16_t status = load_le16(data);
  result_.al_status[p] = status;
  result_.al_code[p] = load_le16(data + 4);
  const bool error = (status & reg::kAlErrorBit) != 0;
  if (!error && (status & reg::kAlStateMask) == static_cast<std::uint16_t>(result_.target)) {
    result_.outcome[p] = SlaveStateOutcome::reached;
  } else if (error) {
    // An error left from before this request is not its answer: acknowledged, then the state asked
    // for alone (a device that emulates its state machine, a junction, copies the acknowledge bit
    // into its status: only a request without it clears the bit there, as bring-up does). An error
    // after both is the slave's refusal of the state.
    ++errors_[p];
    if (errors_[p] == 1) {
      step_[p] = Step::acknowledge;
    } else if (errors_[p] == 2) {
      step_[p] = Step::write;
    } else {
      result_.outcome[p] = SlaveStateOutcome::refused;
    }
  }
}

void SlaveStateService::settle(CycleResult& /*result*/) noexcept {
  if (state_ != State::running) return;
  const bool late = ctx_.now() > deadline_;
  bool pending = false;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if (result_.outcome[p] != SlaveStateOutcome::pending) continue;
    if (step_[p] == Step::by_recovery) {
      const SlaveRecord& slave = ctx_.slaves[p];
      // Back: in the exchange, the recovery at rest, and OP the last AL status read (not the
      // state it was parked at, before the link monitor took it out).
      const bool back = (ctx_.monitor.in_exchange() & slave_bit(p)) != 0 &&
                        slave.recovery.state() == RecoveryState::idle &&
                        (slave.al.status & (reg::kAlStateMask | reg::kAlErrorBit)) == static_cast<std::uint16_t>(reg::AlState::op);
      result_.al_status[p] = slave.al.status;
      result_.al_code[p] = slave.al.code;
      if (back) {
        result_.outcome[p] = SlaveStateOutcome::reached;
        continue;
      }
    }
    if (late) {
      result_.outcome[p] = result_.al_status[p] == 0 ? SlaveStateOutcome::not_answered : SlaveStateOutcome::timeout;
      continue;
    }
    pending = true;
  }
  if (!pending) state_ = State::done;
}

}  // namespace rescue::ecat
