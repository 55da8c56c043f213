// ctl rescan on the EtherCAT handler's side (docs/operator.md "Rescan"): the operator's rescan goes
// to the master, which identifies the segment again in the cyclic frame and compares it with the
// plan (ecat/master/rescan_service.hpp); the handler never waits for it. It disturbs no slave, so
// nothing is refused here but what the master refuses (busy, recovering, not cycling).
//
// Per period, step() (called by EthercatHandler::cycle after the exchange): a finished rescan is
// answered (TaskLinks::rescan_results; an answer the full queue cannot take now waits for the next
// period, never lost); with none under way, at most one request is taken (TaskLinks::rescan_requests)
// and handed to the master. No heap, no locks; bounded work.
#pragma once

#include <cstdint>

#include "core/app/links/rescan_messages.hpp"
#include "core/concurrency/message_port.hpp"
#include "ecat/master/master.hpp"

namespace rescue::app {

class RescanRelay {
 public:
  // `requests`, `results`: the ends of TaskLinks::rescan_requests / rescan_results (both null: step() does nothing).
  RescanRelay(ecat::Master& master, MessageSource<RescanLinkRequest>* requests,
              MessageSink<RescanLinkResult>* results) noexcept
      : master_(master), requests_(requests), results_(results) {}

  void step() noexcept;
  bool in_flight() const noexcept { return in_flight_; }

 private:
  void answer() noexcept;
  // The master's finished rescan into answer_.
  void describe_rescan() noexcept;

  ecat::Master& master_;
  MessageSource<RescanLinkRequest>* requests_;
  MessageSink<RescanLinkResult>* results_;
  RescanLinkResult answer_{};
  bool in_flight_{false};
  bool waiting_{false};
};

}  // namespace rescue::app
