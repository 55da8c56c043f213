// ctl states on the EtherCAT handler's side (docs/operator.md "AL states"): the operator's AL state
// for slaves out of service goes to the master, which writes AL control in the cyclic frame
// (ecat/master/slave_state_service.hpp); the handler never waits for it.
//
// A slave is in service while one of its joints is: a drive's own joint, a junction's the joints
// of every slave behind it (its state carries their frames), that the handler commands (not lost,
// not recorded lost: LostJointTracker::excluded). A request naming a slave in service is refused
// whole (in_service, the joints named), nothing written: the state of a slave in service is the
// joint manager's business, not the operator's.
//
// Per period, step() (called by EthercatHandler::cycle after the exchange):
//   - a finished request's result is answered (TaskLinks::states_results); an answer the full
//     queue cannot take now waits for the next period (never lost);
//   - with none under way, at most one request is taken (TaskLinks::states_requests), judged and
//     handed to the master (its refusals answered at once: busy, recovering, not cycling).
// No heap, no locks; bounded work (one request and one result per period).
#pragma once

#include <cstdint>

#include "core/app/links/slave_state_messages.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/robot/robot.hpp"
#include "ecat/master/master.hpp"

namespace rescue::app {

// The joints whose service a slave's AL state carries: a drive's own, a junction's behind it.
JointMask joints_carried_by(std::size_t position) noexcept;

class SlaveStateRelay {
 public:
  // `requests`, `results`: the ends of TaskLinks::states_requests / states_results (both null: step() does nothing).
  SlaveStateRelay(ecat::Master& master, MessageSource<StatesLinkRequest>* requests,
                  MessageSink<StatesLinkResult>* results) noexcept
      : master_(master), requests_(requests), results_(results) {}

  // `out_of_service`: the joints the handler does not command this period.
  void step(JointMask out_of_service) noexcept;
  bool in_flight() const noexcept { return in_flight_; }

 private:
  void answer() noexcept;

  ecat::Master& master_;
  MessageSource<StatesLinkRequest>* requests_;
  MessageSink<StatesLinkResult>* results_;
  StatesLinkResult answer_{};
  bool in_flight_{false};
  bool waiting_{false};
};

}  // namespace rescue::app
