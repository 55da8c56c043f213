// The AL state machine of the slave firmware (ETG.1000.6 section 6.4, as EtherCAT slave stacks
// implement it): requests from AL control are checked, refused with an AL status code and the
// error indication, or carried out with the SyncManagers switched on and off as each state needs.
//
//   INIT -> PRE-OP    mailbox SyncManagers must match the device's mailbox (else 0x0016)
//   PRE-OP -> SAFE-OP mailbox again (else 0x0016, back to INIT), process-data SyncManagers
//                     (size/direction/enable: 0x001D outputs, 0x001E inputs; overlap or no room
//                     for three buffers: 0x0017, back to PRE-OP), then the device's own checks
//   SAFE-OP -> OP     SyncManagers again, then waits for the first valid outputs (SM event) before
//                     asking the device; without outputs for 10 s: 0x001B, stays in SAFE-OP
//   downward          always carried out
//   refuse_state()    (fault injection) every upward request for that state refused with its code
//   INIT -> BOOT      0x0013 (no bootstrap); other jumps (INIT -> SAFE-OP, PRE-OP -> OP, ...) 0x0011;
//                     unknown states 0x0012
// While the error indication is set, requests without the acknowledge bit are ignored, except a
// request for INIT; an acknowledge clears it.
#include "drivers/sim/esc/esc.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

namespace reg = ecat::reg;
namespace al = ecat::reg::al_code;
constexpr std::uint32_t kMinMailboxBytes = 34;  // the smallest mailbox slave stacks accept

int rank(AlState s) noexcept {
  switch (s) {
    case AlState::init: case AlState::boot: return 1;
    case AlState::pre_op: return 2;
    case AlState::safe_op: return 3;
    case AlState::op: return 4;
    default: return 0;
  }
}

bool is_state(unsigned v) noexcept { return v == 1 || v == 2 || v == 3 || v == 4 || v == 8; }

bool areas_overlap(std::uint32_t a, std::uint32_t a_length, std::uint32_t b, std::uint32_t b_length) noexcept {
  return a < b + b_length && b < a + a_length;
}

}  // namespace

bool Esc::has_mailbox() const noexcept {
  return sii_.word(ecat::sii::kStdRxMailboxSize) != 0 && sii_.word(ecat::sii::kStdTxMailboxSize) != 0;
}

std::uint16_t Esc::check_mailbox_sync_managers() const noexcept {
  if (!has_mailbox()) return al::kNoError;
  const EscSyncManager* out = sync_manager(0);
  const EscSyncManager* in = sync_manager(1);
  if (out == nullptr || in == nullptr) return al::kInvalidMailboxConfig;
  const auto fits = [&](const EscSyncManager& sm, bool master_writes, std::uint16_t max_bytes) {
    return sm.enabled_by_master() && sm.mailbox_mode() && sm.master_writes() == master_writes &&
           sm.length() >= kMinMailboxBytes && sm.length() <= max_bytes && sm.start() >= kEscRegisterSpace &&
           sm.start() + sm.length() <= memory_.ram_end();
  };
  if (!fits(*out, true, sii_.word(ecat::sii::kStdRxMailboxSize)) || !fits(*in, false, sii_.word(ecat::sii::kStdTxMailboxSize)) ||
      areas_overlap(out->start(), out->length(), in->start(), in->length())) {
    return al::kInvalidMailboxConfig;
  }
  return al::kNoError;
}

std::uint16_t Esc::check_process_data_sync_managers() const noexcept {
  const ProcessDataLayout layout = device_->process_data_layout();
  struct Area {
    std::uint32_t start;
    std::uint32_t length;
  };
  std::array<Area, 4> areas{};
  std::size_t area_count = 0;
  if (has_mailbox()) {
    for (unsigned n = 0; n < 2; ++n) {
      const EscSyncManager* sm = sync_manager(n);  // never null for n < 2; optimised builds cannot tell
      if (sm != nullptr) areas[area_count++] = Area{sm->start(), sm->length()};
    }
  }
  const auto check = [&](std::uint8_t index, std::uint16_t bytes, bool master_writes, std::uint16_t refusal) {
    if (bytes == 0) return al::kNoError;
    const EscSyncManager* sm = sync_manager(index);
    if (sm == nullptr || !sm->enabled_by_master() || sm->length() != bytes || sm->master_writes() != master_writes ||
        sm->mailbox_mode()) {
      return refusal;
    }
    const std::uint32_t room = 3U * sm->length();  // three buffers
    if (sm->start() < kEscRegisterSpace || sm->start() + room > memory_.ram_end()) return al::kInvalidSyncManagerConfig;
    for (std::size_t i = 0; i < area_count; ++i) {
      if (areas_overlap(sm->start(), room, areas[i].start, areas[i].length)) return al::kInvalidSyncManagerConfig;
    }
    areas[area_count++] = Area{sm->start(), room};
    return al::kNoError;
  };
  const std::uint16_t outputs = check(layout.output_sm, layout.output_bytes, true, al::kInvalidOutputConfig);
  if (outputs != al::kNoError) return outputs;
  return check(layout.input_sm, layout.input_bytes, false, al::kInvalidInputConfig);
}

void Esc::handle_al_control(hal::Nanoseconds now) noexcept {
  const std::uint16_t control = memory_.u16(reg::kAlControl);
  const unsigned requested = control & reg::kAlStateMask;
  const bool acknowledge = (control & reg::kAlErrorBit) != 0;
  if (acknowledge) {
    al_error_ = false;
  } else if (al_error_) {
    if (requested != static_cast<unsigned>(AlState::init)) return;  // ignored until acknowledged
    al_error_ = false;
  }
  if (!is_state(requested)) {
    refuse(state_, al::kUnknownState);
    return;
  }
  const auto to = static_cast<AlState>(requested);
  const AlState from = state_;
  op_pending_ = false;  // a new request replaces one still waiting for outputs
  if (to == from) {
    set_al_status(state_, false, al::kNoError);
    return;
  }
  const bool downward = to == AlState::init || (rank(to) < rank(from) && to != AlState::boot);
  if (downward) {
    enter_state(from, to);
    (void)device_->on_state_change(from, to, *this);
    return;
  }
  if (refused_code_ != al::kNoError && to == refused_state_) return refuse(from, refused_code_);  // fault injection
  if (from == AlState::init && to == AlState::pre_op) {
    std::uint16_t refusal = check_mailbox_sync_managers();
    if (refusal == al::kNoError) refusal = device_->on_state_change(from, to, *this);
    if (refusal != al::kNoError) return refuse(AlState::init, refusal);
    enter_state(from, to);
  } else if (from == AlState::pre_op && to == AlState::safe_op) {
    std::uint16_t refusal = check_mailbox_sync_managers();
    if (refusal != al::kNoError) return refuse(AlState::init, refusal);
    refusal = check_process_data_sync_managers();
    if (refusal == al::kNoError) refusal = device_->on_state_change(from, to, *this);
    if (refusal != al::kNoError) return refuse(AlState::pre_op, refusal);
    enter_state(from, to);
  } else if (from == AlState::safe_op && to == AlState::op) {
    std::uint16_t refusal = check_mailbox_sync_managers();
    if (refusal != al::kNoError) return refuse(AlState::init, refusal);
    refusal = check_process_data_sync_managers();
    if (refusal != al::kNoError) return refuse(AlState::pre_op, refusal);
    if (device_->process_data_layout().output_bytes > 0 && !outputs_received_) {
      op_pending_ = true;  // SAFE-OP -> OP completes with the first valid outputs
      op_pending_since_ = now;
      return;
    }
    complete_safe_op_to_op();
  } else if (from == AlState::init && to == AlState::boot) {
    refuse(AlState::init, al::kBootstrapNotSupported);
  } else {
    refuse(from, al::kInvalidStateChange);
  }
}

void Esc::complete_safe_op_to_op() noexcept {
  op_pending_ = false;
  const std::uint16_t refusal = device_->on_state_change(AlState::safe_op, AlState::op, *this);
  if (refusal != al::kNoError) return refuse(AlState::safe_op, refusal);
  enter_state(AlState::safe_op, AlState::op);
}

void Esc::enter_state(AlState from, AlState to) noexcept {
  const ProcessDataLayout layout = device_->process_data_layout();
  const auto process_data = [&](bool on) {
    if (layout.output_bytes > 0 && sync_manager(layout.output_sm) != nullptr) {
      sync_manager(layout.output_sm)->set_deactivated_by_device(memory_, !on);
    }
    if (layout.input_bytes > 0 && sync_manager(layout.input_sm) != nullptr) {
      sync_manager(layout.input_sm)->set_deactivated_by_device(memory_, !on);
    }
  };
  if (rank(to) < rank(AlState::safe_op) && rank(from) >= rank(AlState::safe_op)) {
    process_data(false);
    outputs_received_ = false;
  }
  if (to == AlState::init || to == AlState::boot) {
    for (unsigned n = 0; n < 2 && n < config_.sync_manager_count; ++n) sync_managers_[n].set_deactivated_by_device(memory_, true);
    queue_count_ = 0;
  }
  if (from == AlState::init && to == AlState::pre_op && has_mailbox()) {
    for (unsigned n = 0; n < 2; ++n) sync_managers_[n].set_deactivated_by_device(memory_, false);
  }
  if (from == AlState::pre_op && to == AlState::safe_op) {
    outputs_received_ = false;
    process_data(true);
  }
  state_ = to;
  ++counters_.al_transitions;
  set_al_status(to, false, al::kNoError);
}

void Esc::refuse(AlState stay_in, std::uint16_t code) noexcept {
  const AlState from = state_;
  if (rank(stay_in) < rank(from)) {
    enter_state(from, stay_in);
    (void)device_->on_state_change(from, stay_in, *this);
  }
  state_ = stay_in;
  al_error_ = true;
  ++counters_.al_refusals;
  set_al_status(stay_in, true, code);
}

void Esc::raise_al_error(AlState fall_back_to, std::uint16_t al_status_code) noexcept {
  if (!powered_ || device_emulation_) return;
  op_pending_ = false;
  refuse(rank(fall_back_to) < rank(state_) ? fall_back_to : state_, al_status_code);
}

}  // namespace rescue::drivers
