// ctl reg_read on the EtherCAT handler's side (docs/operator.md "ESC registers"): the operator's
// read of a slave's ESC registers goes to the master, which sends one FPRD in the cyclic frame
// (ecat/master/register_read_service.hpp); the handler never waits for it.
//
// Per period, step() (called by EthercatHandler::cycle after the exchange):
//   - a finished read's result is answered (TaskLinks::reg_results); an answer the full queue
//     cannot take now waits for the next period (never lost);
//   - with none under way, at most one request is taken (TaskLinks::reg_requests) and judged: a
//     slave out of the exchange (lost) -> lost, nothing sent; the master's reader busy -> busy;
//     otherwise it is handed to the master.
// No heap, no locks; bounded work (one request and one result per period). Read only.
#pragma once

#include <cstdint>

#include "core/app/links/register_messages.hpp"
#include "core/concurrency/message_port.hpp"
#include "ecat/master/master.hpp"

namespace rescue::app {

class RegisterRelay {
 public:
  // `requests`, `results`: the ends of TaskLinks::reg_requests / reg_results (both null: step() does nothing).
  RegisterRelay(ecat::Master& master, MessageSource<RegReadLinkRequest>* requests,
                MessageSink<RegReadLinkResult>* results) noexcept
      : master_(master), requests_(requests), results_(results) {}

  void step() noexcept;
  bool in_flight() const noexcept { return in_flight_; }

 private:
  // Sends `answer_`, or keeps it for the next period.
  void answer() noexcept;

  ecat::Master& master_;
  MessageSource<RegReadLinkRequest>* requests_;
  MessageSink<RegReadLinkResult>* results_;
  RegReadLinkResult answer_{};  // the read in flight (its request), then its answer
  bool in_flight_{false};
  bool waiting_{false};  // answer_ waits for room in the result queue
};

}  // namespace rescue::app
