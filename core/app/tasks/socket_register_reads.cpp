// ctl reg_read on the socket handler's side (docs/protocol.md "Register reads"): the request goes to
// the EtherCAT handler's queue (TaskLinks::reg_requests), one in flight at a time; its result comes
// back a period or more later and is sent as reg_result (no_answer past kRegAnswerLimit).
#include "core/app/tasks/socket_handler.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;

// The answer to a read that ends here, without the EtherCAT handler's result.
protocol::RegResultPayload reg_refusal(const protocol::RegReadPayload& read, protocol::RegStatus status) noexcept {
  protocol::RegResultPayload r;
  r.slave = read.slave;
  r.address = read.address;
  r.length = read.length;
  r.status = status;
  return r;
}

}  // namespace

void SocketHandler::answer_register_read(protocol::RegResultPayload result, std::uint64_t request_sequence,
                                         std::uint32_t address, std::uint16_t port) noexcept {
  Message m;
  m.header.type = MessageType::reg_result;
  result.request_sequence = request_sequence;
  m.reg_result = result;
  send(m, address, port);
}

void SocketHandler::forward_register_read(const Message& request, const hal::UdpDatagram& from) noexcept {
  if (reg_.active || ports_.reg_requests == nullptr) {
    // One read at a time: this one is answered at once, never queued behind and never lost.
    const auto status = ports_.reg_requests == nullptr ? protocol::RegStatus::no_answer : protocol::RegStatus::busy;
    return answer_register_read(reg_refusal(request.reg_read, status), request.header.sequence, from.address, from.port);
  }
  RegReadLinkRequest r;
  r.id = ++reg_ids_;
  r.read = request.reg_read;
  if (!ports_.reg_requests->try_send(r)) {
    ++counters_.forwarded_dropped;  // cannot happen with one in flight and two slots; counted if it does
    return answer_register_read(reg_refusal(request.reg_read, protocol::RegStatus::busy), request.header.sequence,
                                from.address, from.port);
  }
  reg_.active = true;
  reg_.id = r.id;
  reg_.request_sequence = request.header.sequence;
  reg_.read = request.reg_read;
  reg_.address = from.address;
  reg_.port = from.port;
  reg_.deadline = now_ + kRegAnswerLimit;
}

void SocketHandler::collect_register_read() noexcept {
  RegReadLinkResult result;
  while (ports_.reg_results != nullptr && ports_.reg_results->try_receive(result)) {
    if (!reg_.active || result.id != reg_.id) continue;  // the answer to a read already answered no_answer
    reg_.active = false;
    answer_register_read(result.result, reg_.request_sequence, reg_.address, reg_.port);
  }
  if (reg_.active && now_ > reg_.deadline) {
    reg_.active = false;
    answer_register_read(reg_refusal(reg_.read, protocol::RegStatus::no_answer), reg_.request_sequence, reg_.address,
                         reg_.port);
  }
}

}  // namespace rescue::app
