#include "core/app/tasks/register_relay.hpp"

#include <algorithm>

namespace rescue::app {
namespace {

protocol::RegStatus status_of(ecat::RegisterReadStatus s) noexcept {
  switch (s) {
    case ecat::RegisterReadStatus::ok: return protocol::RegStatus::ok;
    case ecat::RegisterReadStatus::not_answered: return protocol::RegStatus::not_answered;
    case ecat::RegisterReadStatus::out_of_exchange: return protocol::RegStatus::lost;
  }
  return protocol::RegStatus::not_answered;
}

}  // namespace

void RegisterRelay::answer() noexcept {
  waiting_ = !results_->try_send(answer_);
}

void RegisterRelay::step() noexcept {
  if (requests_ == nullptr || results_ == nullptr) return;
  if (waiting_) {
    answer();
    if (waiting_) return;
  }
  if (in_flight_) {
    ecat::RegisterReadResult done;
    if (!master_.take_register_read(done)) return;
    in_flight_ = false;
    protocol::RegResultPayload& r = answer_.result;
    r.status = status_of(done.status);
    r.wkc = done.wkc;
    r.frames = done.frames;
    r.data = {};
    if (r.status == protocol::RegStatus::ok) {
      std::copy(done.data.begin(), done.data.begin() + std::min<std::size_t>(done.length, r.data.size()), r.data.begin());
    }
    return answer();
  }
  RegReadLinkRequest request;
  if (!requests_->try_receive(request)) return;
  answer_ = RegReadLinkResult{};
  answer_.id = request.id;
  protocol::RegResultPayload& r = answer_.result;
  r.slave = request.read.slave;
  r.address = request.read.address;
  r.length = request.read.length;
  const bool in_exchange = request.read.slave < ecat::kMaxSlaves &&
                           (master_.monitor().in_exchange() & ecat::slave_bit(request.read.slave)) != 0;
  if (!in_exchange) {
    r.status = protocol::RegStatus::lost;
    return answer();
  }
  if (!master_.request_register_read(request.read.slave, request.read.address, request.read.length)) {
    r.status = protocol::RegStatus::busy;
    return answer();
  }
  in_flight_ = true;
}

}  // namespace rescue::app
