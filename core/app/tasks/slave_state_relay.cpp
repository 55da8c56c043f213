#include "core/app/tasks/slave_state_relay.hpp"

namespace rescue::app {
namespace {

using protocol::StateOutcome;
using protocol::StatesStatus;

static_assert(protocol::kStatesSlaves == ecat::kMaxSlaves, "a states result has a record per planned slave");

StateOutcome outcome_of(ecat::SlaveStateOutcome o) noexcept {
  switch (o) {
    case ecat::SlaveStateOutcome::reached: return StateOutcome::reached;
    case ecat::SlaveStateOutcome::refused: return StateOutcome::refused;
    case ecat::SlaveStateOutcome::timeout: return StateOutcome::timeout;
    case ecat::SlaveStateOutcome::not_answered:
    case ecat::SlaveStateOutcome::pending: return StateOutcome::not_answered;
  }
  return StateOutcome::not_answered;
}

StatesStatus status_of(ecat::SlaveStateService::Refusal r) noexcept {
  switch (r) {
    case ecat::SlaveStateService::Refusal::none: return StatesStatus::ok;
    case ecat::SlaveStateService::Refusal::busy: return StatesStatus::busy;
    case ecat::SlaveStateService::Refusal::recovering: return StatesStatus::recovering;
    case ecat::SlaveStateService::Refusal::bad_request:
    case ecat::SlaveStateService::Refusal::not_cycling: return StatesStatus::not_cycling;
  }
  return StatesStatus::not_cycling;
}

}  // namespace

JointMask joints_carried_by(std::size_t position) noexcept {
  if (position >= kSlaveCount) return 0;
  // A drive forwards frames in every AL state: it carries its own joint only.
  if (kSlaves[position].kind == SlaveKind::joint_drive) return joint_bit(kSlaves[position].joint);
  JointMask joints = 0;
  for (std::size_t q = 0; q < kSlaveCount; ++q) {
    // q hangs off `position` when its chain of upstream slaves passes through it (or it is it).
    std::size_t at = q;
    for (std::size_t hops = 0; hops <= kSlaveCount && at < kSlaveCount && at != position; ++hops) {
      at = kSlaves[at].upstream;
    }
    if (at == position && kSlaves[q].joint < kJointCount) joints |= joint_bit(kSlaves[q].joint);
  }
  return joints;
}

void SlaveStateRelay::answer() noexcept { waiting_ = !results_->try_send(answer_); }

void SlaveStateRelay::step(JointMask out_of_service) noexcept {
  if (requests_ == nullptr || results_ == nullptr) return;
  if (waiting_) {
    answer();
    if (waiting_) return;
  }
  if (in_flight_) {
    ecat::SlaveStateResult done;
    if (!master_.take_slave_state(done)) return;
    in_flight_ = false;
    protocol::StatesResultPayload& r = answer_.result;
    r.status = StatesStatus::ok;
    r.frames = done.frames;
    for (std::size_t p = 0; p < protocol::kStatesSlaves; ++p) {  // == ecat::kMaxSlaves
      if ((r.slaves & ecat::slave_bit(p)) == 0) continue;
      r.records[p].outcome = outcome_of(done.outcome[p]);
      r.records[p].al_status = done.al_status[p];
      r.records[p].al_code = done.al_code[p];
      if (r.records[p].outcome != StateOutcome::reached) r.status = StatesStatus::not_reached;
    }
    return answer();
  }
  StatesLinkRequest request;
  if (!requests_->try_receive(request)) return;
  answer_ = StatesLinkResult{};
  answer_.id = request.id;
  protocol::StatesResultPayload& r = answer_.result;
  r.slaves = request.states.slaves;
  r.state = request.states.state;
  JointMask carried = 0;
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if ((request.states.slaves & ecat::slave_bit(p)) != 0) carried |= joints_carried_by(p);
  }
  r.in_service = carried & ~out_of_service & kAllJoints;
  if (r.in_service != 0) {
    r.status = StatesStatus::in_service;
    return answer();
  }
  const auto refusal =
      master_.request_slave_state(request.states.slaves, static_cast<ecat::reg::AlState>(request.states.state));
  if (refusal != ecat::SlaveStateService::Refusal::none) {
    r.status = status_of(refusal);
    return answer();
  }
  in_flight_ = true;
}

}  // namespace rescue::app
