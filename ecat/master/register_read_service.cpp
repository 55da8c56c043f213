// The operator's ESC register read in the cycle frame (register_read_service.hpp).
#include "ecat/master/register_read_service.hpp"

#include <algorithm>

namespace rescue::ecat {

bool RegisterReadService::request(std::size_t position, std::uint16_t address, std::uint16_t length) noexcept {
  if (state_ != State::idle || position >= ctx_.plan.size() || position >= kMaxSlaves) return false;
  if (length == 0 || length > kMaxRegisterReadLength || std::size_t{address} + length > 0x10000U) return false;
  result_ = RegisterReadResult{};
  result_.position = static_cast<std::uint8_t>(position);
  result_.address = address;
  result_.length = length;
  state_ = State::asked;
  return true;
}

bool RegisterReadService::take(RegisterReadResult& out) noexcept {
  if (state_ != State::done) return false;
  out = result_;
  state_ = State::idle;
  return true;
}

void RegisterReadService::add_datagrams(CycleFrame& frame) noexcept {
  if (state_ != State::asked) return;
  if ((ctx_.monitor.in_exchange() & slave_bit(result_.position)) == 0) {
    result_.status = RegisterReadStatus::out_of_exchange;
    state_ = State::done;
    return;
  }
  if (!frame.fits(kDatagramOverhead + result_.length)) return;  // the next frame, then
  if (frame.add(*this, 0, Command::FPRD, make_address(ctx_.plan[result_.position].station_address, result_.address),
                result_.length)) {
    state_ = State::sent;
    ++result_.frames;
  }
}

void RegisterReadService::on_answer(std::uint8_t /*tag*/, const DatagramView& d) noexcept {
  if (state_ != State::sent) return;
  result_.wkc = d.wkc();
  if (d.wkc() != 1 || d.data().size() != result_.length) return;  // tried again next frame
  std::copy(d.data().begin(), d.data().end(), result_.data.begin());
  result_.status = RegisterReadStatus::ok;
  state_ = State::done;
}

void RegisterReadService::end_exchange(hal::Nanoseconds /*now*/) noexcept {
  if (state_ != State::sent) return;
  if (result_.frames >= kTries) {
    result_.status = RegisterReadStatus::not_answered;
    state_ = State::done;
    return;
  }
  state_ = State::asked;  // not answered in this frame (lost, or working counter 0): again
}

}  // namespace rescue::ecat
