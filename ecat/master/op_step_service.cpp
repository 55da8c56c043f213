// SAFE-OP -> OP while cycling.
#include "ecat/master/op_step_service.hpp"

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::ecat {
namespace {

constexpr std::size_t kOpStatusBytes = kDatagramOverhead + kAlStatusReadLength;

}  // namespace

void OpStepService::start() noexcept {
  pending_ = ctx_.operated();
  for (SlaveRecord& slave : ctx_.slaves) slave.op = OpProgress{};
  deadline_ = ctx_.now() + ctx_.options.op_timeout;
}

void OpStepService::add_datagrams(CycleFrame& frame) noexcept {
  if (ctx_.state != MasterState::going_op) return;
  std::array<std::uint8_t, 2> value{};
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((pending_ & slave_bit(p)) == 0 || !frame.fits(kOpStatusBytes)) continue;
    const std::uint16_t station = ctx_.plan[p].station_address;
    const OpStep step = ctx_.slaves[p].op.step;
    const auto tag = static_cast<std::uint8_t>(p);
    if (step == OpStep::wait) {
      (void)frame.add(*this, tag, Command::FPRD, make_address(station, reg::kAlStatus), kAlStatusReadLength);
      continue;
    }
    const auto control = step == OpStep::acknowledge
                             ? static_cast<std::uint16_t>(static_cast<std::uint16_t>(reg::AlState::safe_op) | reg::kAlErrorBit)
                             : static_cast<std::uint16_t>(reg::AlState::op);
    store_le16(value.data(), control);
    (void)frame.add(*this, tag, Command::FPWR, make_address(station, reg::kAlControl), 2, ConstByteSpan(value));
  }
}

void OpStepService::on_answer(std::uint8_t p, const DatagramView& d) noexcept {
  SlaveRecord& slave = ctx_.slaves[p];
  OpProgress& op = slave.op;
  if (op.step != OpStep::wait) {  // the AL control write
    if (d.wkc() == 1) op.step = op.step == OpStep::acknowledge ? OpStep::request : OpStep::wait;
    return;
  }
  const std::uint8_t* data = d.data().data();
  const std::uint16_t status = load_le16(data);
  if (d.wkc() != 1) return;
  op.al_status = status;
  op.al_code = load_le16(data + 4);
  slave.note_al_status(data);
  if ((status & reg::kAlErrorBit) == 0 && (status & reg::kAlStateMask) == static_cast<std::uint16_t>(reg::AlState::op)) {
    pending_ &= ~slave_bit(p);
  } else if ((status & reg::kAlErrorBit) != 0) {
    ctx_.report.al_failure = AlFailure{p, reg::AlState::op, status, load_le16(data + 4), false, false};
    if (++op.refusals <= ctx_.options.al.retries) op.step = OpStep::acknowledge;
  }
}

void OpStepService::settle(CycleResult& result) noexcept {
  if (ctx_.state != MasterState::going_op) return;
  const hal::Nanoseconds now = ctx_.now();
  if (pending_ == 0) {
    ctx_.state = MasterState::op;
    ctx_.report.op_at = now;
    ctx_.monitor.start(ctx_.operated());
  } else if (now > deadline_) {
    // Stay in SAFE-OP, exchanging inputs; the report names the slave that did not follow.
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      if ((pending_ & slave_bit(p)) == 0) continue;
      if (ctx_.report.al_failure.position != p) {
        ctx_.report.al_failure = AlFailure{static_cast<std::uint8_t>(p), reg::AlState::op, 0, 0, true, false};
      }
      break;
    }
    ctx_.report.failed_step = "OP";
    ctx_.report.error = make_error(Errc::timeout, "network did not reach OP", ctx_.report.al_failure.position);
    // Keep trying (a bring-up is never given up here: the owner has the limit): every slave not in
    // OP is acknowledged and asked again, with a new deadline.
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      if ((pending_ & slave_bit(p)) == 0) continue;
      ctx_.slaves[p].op.step = OpStep::acknowledge;
      ctx_.slaves[p].op.refusals = 0;
    }
    deadline_ = now + ctx_.options.op_timeout;
  }
  result.state = ctx_.state;
}

}  // namespace rescue::ecat
