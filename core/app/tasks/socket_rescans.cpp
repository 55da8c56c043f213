// ctl rescan on the socket handler's side (docs/protocol.md "Rescan"): the request goes to the
// EtherCAT handler's queue (TaskLinks::rescan_requests), one in flight at a time (relayed_request.hpp);
// its result comes back once the master identified the segment again, and is sent as rescan_result
// (no_answer past kRescanAnswerLimit).
#include "core/app/tasks/socket_handler.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;
using Rescan = RelayedRequest<RescanLinkRequest, RescanLinkResult>;

}  // namespace

void SocketHandler::answer_rescan(const protocol::RescanResultPayload& result, protocol::RescanStatus status,
                                  std::uint64_t request_sequence, std::uint32_t address, std::uint16_t port) noexcept {
  Message m;
  m.header.type = MessageType::rescan_result;
  m.rescan_result = result;
  m.rescan_result.status = status;
  m.rescan_result.request_sequence = request_sequence;
  send(m, address, port);
}

void SocketHandler::forward_rescan(const Message& request, const hal::UdpDatagram& from) noexcept {
  // One rescan at a time: another is answered at once (busy), never queued behind and never lost.
  protocol::RescanStatus refusal = protocol::RescanStatus::busy;
  if (ports_.rescan_requests == nullptr) {
    refusal = protocol::RescanStatus::no_answer;
  } else if (!rescan_.active()) {
    if (rescan_.start(*ports_.rescan_requests, RescanLinkRequest{}, request.header.sequence, from.address, from.port,
                      now_ + kRescanAnswerLimit)) {
      return;
    }
    ++counters_.forwarded_dropped;  // cannot happen with one in flight and two slots; counted if it does
  }
  answer_rescan(protocol::RescanResultPayload{}, refusal, request.header.sequence, from.address, from.port);
}

void SocketHandler::collect_rescan() noexcept {
  if (ports_.rescan_results == nullptr) return;
  switch (rescan_.collect(*ports_.rescan_results, rescan_result_, now_)) {
    case Rescan::Collected::result:
      return answer_rescan(rescan_result_.result, rescan_result_.result.status, rescan_.request_sequence(),
                           rescan_.address(), rescan_.port());
    case Rescan::Collected::expired:
      return answer_rescan(protocol::RescanResultPayload{}, protocol::RescanStatus::no_answer, rescan_.request_sequence(),
                           rescan_.address(), rescan_.port());
    case Rescan::Collected::nothing: return;
  }
}

}  // namespace rescue::app
