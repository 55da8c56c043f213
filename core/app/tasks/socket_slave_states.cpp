// ctl states on the socket handler's side (docs/protocol.md "AL states"): the request goes to the
// EtherCAT handler's queue (TaskLinks::states_requests), one in flight at a time (relayed_request.hpp);
// its result comes back when the slaves reached the state or the master gave up, and is sent as
// states_result (no_answer past kStatesAnswerLimit).
#include "core/app/tasks/socket_handler.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;

// The answer to a request that ends here, without the EtherCAT handler's result.
protocol::StatesResultPayload states_refusal(const protocol::StatesPayload& states, protocol::StatesStatus status) noexcept {
  protocol::StatesResultPayload r;
  r.slaves = states.slaves;
  r.state = states.state;
  r.status = status;
  return r;
}

}  // namespace

void SocketHandler::answer_states(protocol::StatesResultPayload result, std::uint64_t request_sequence,
                                  std::uint32_t address, std::uint16_t port) noexcept {
  Message m;
  m.header.type = MessageType::states_result;
  result.request_sequence = request_sequence;
  m.states_result = result;
  send(m, address, port);
}

void SocketHandler::forward_states(const Message& request, const hal::UdpDatagram& from) noexcept {
  // One request at a time: another is answered at once (busy), never queued behind and never lost.
  protocol::StatesStatus refusal = protocol::StatesStatus::busy;
  if (ports_.states_requests == nullptr) {
    refusal = protocol::StatesStatus::no_answer;
  } else if (!states_.active()) {
    StatesLinkRequest r;
    r.states = request.states;
    if (states_.start(*ports_.states_requests, r, request.header.sequence, from.address, from.port,
                      now_ + kStatesAnswerLimit)) {
      states_request_ = request.states;
      return;
    }
    ++counters_.forwarded_dropped;  // cannot happen with one in flight and two slots; counted if it does
  }
  answer_states(states_refusal(request.states, refusal), request.header.sequence, from.address, from.port);
}

void SocketHandler::collect_states() noexcept {
  if (ports_.states_results == nullptr) return;
  switch (states_.collect(*ports_.states_results, states_result_, now_)) {
    case RelayedRequest<StatesLinkRequest, StatesLinkResult>::Collected::result:
      return answer_states(states_result_.result, states_.request_sequence(), states_.address(), states_.port());
    case RelayedRequest<StatesLinkRequest, StatesLinkResult>::Collected::expired:
      return answer_states(states_refusal(states_request_, protocol::StatesStatus::no_answer), states_.request_sequence(),
                           states_.address(), states_.port());
    case RelayedRequest<StatesLinkRequest, StatesLinkResult>::Collected::nothing: return;
  }
}

}  // namespace rescue::app
