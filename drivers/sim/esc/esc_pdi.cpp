// The PDI side of the ESC: what the slave firmware does at the end of each frame and as time
// passes (mailbox delivery, application cycles, watchdogs), and the EscPdi services the device uses.
#include <algorithm>
#include <cstring>

#include "drivers/sim/esc/esc.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

namespace reg = ecat::reg;
namespace al = ecat::reg::al_code;
constexpr std::uint8_t kRepeatAck = 0x02;

}  // namespace

void Esc::end_frame(hal::Nanoseconds now) noexcept {
  if (!powered_) return;
  sii_.start_pending(memory_, now);
  if (device_emulation_) {
    // No application: AL status follows AL control (state and acknowledge bits), SyncManager
    // events go nowhere.
    if (al_control_unread_) {
      const auto control = static_cast<std::uint16_t>(memory_.u16(reg::kAlControl) & 0x001FU);
      const auto requested = static_cast<AlState>(control & reg::kAlStateMask);
      state_ = requested;
      set_al_status(requested, (control & reg::kAlErrorBit) != 0, memory_.u16(reg::kAlStatusCode));
      al_control_unread_ = false;
    }
    for (unsigned n = 0; n < config_.sync_manager_count; ++n) (void)sync_managers_[n].take_event();
    return;
  }
  handle_sync_manager_events(now);
  serve_application(now);
}

void Esc::serve_application(hal::Nanoseconds now) noexcept {
  if (!powered_ || frozen_ || device_emulation_) return;
  if (al_control_unread_) {
    al_control_unread_ = false;
    handle_al_control(now);
  }
  // A complete message in the SM0 mailbox (possibly written while the application hung).
  EscSyncManager* in = sync_manager(0);
  // has_mailbox() (two SII words) last: the SM state rules out most calls first.
  if (in != nullptr && in->mailbox_full() && in->active() && in->mailbox_mode() && in->master_writes() && has_mailbox()) {
    const ConstByteSpan message = in->device_read_buffer(memory_);
    ++counters_.mailbox_received;
    device_->on_mailbox(message, *this);
    in->device_consumed_mailbox(memory_);
  }
  deliver_queued_mailbox();
}

void Esc::handle_sync_manager_events(hal::Nanoseconds now) noexcept {
  const ProcessDataLayout layout = device_->process_data_layout();
  const bool cyclic_state = state_ == AlState::safe_op || state_ == AlState::op;
  for (unsigned n = 0; n < config_.sync_manager_count; ++n) {
    EscSyncManager& sm = sync_managers_[n];
    const EscSyncManager::Event event = sm.take_event();
    if (event == EscSyncManager::Event::none) continue;
    if (event == EscSyncManager::Event::buffer_written && sm.watchdog_trigger()) {
      // The process-data watchdog is ESC hardware: it runs whatever the application does.
      pd_watchdog_running_ = true;
      pd_watchdog_trigger_ = now;
      pd_watchdog_expired_ = false;
      memory_.set_u16(reg::kWatchdogStatusProcessData, 0x0001);
    }
    if (frozen_) continue;
    switch (event) {
      case EscSyncManager::Event::buffer_written:
        if (n != layout.output_sm) break;
        outputs_received_ = true;
        if (op_pending_) complete_safe_op_to_op();
        if (cyclic_state && !dc_synchronous()) run_cycle(CycleTrigger::sm_event, now, dc_.system_time_at(memory_, now));
        break;
      case EscSyncManager::Event::buffer_read:
        if (n == layout.input_sm && layout.output_bytes == 0 && cyclic_state && !dc_synchronous()) {
          run_cycle(CycleTrigger::inputs_read, now, dc_.system_time_at(memory_, now));
        }
        break;
      default:  // mailbox events: served by serve_application()
        break;
    }
  }
  if (repeat_check_ && !frozen_ && has_mailbox()) {
    // Mailbox repeat: the master toggled SM1's repeat bit; the firmware re-posts its last message
    // and acknowledges by toggling its own bit.
    repeat_check_ = false;
    const std::uint32_t activate = reg::sync_manager(1) + reg::kSmActivate;
    const std::uint32_t pdi = reg::sync_manager(1) + reg::kSmPdiControl;
    const bool requested = (memory_.u8(activate) & reg::kSmRepeat) != 0;
    const bool acknowledged = (memory_.u8(pdi) & kRepeatAck) != 0;
    if (requested != acknowledged) {
      EscSyncManager* out = sync_manager(1);
      if (out != nullptr && out->active() && !out->mailbox_full() && last_sent_length_ > 0) {
        (void)publish_mailbox(ConstByteSpan(last_sent_.data(), last_sent_length_));
      }
      memory_.set_u8(pdi, static_cast<std::uint8_t>(requested ? (memory_.u8(pdi) | kRepeatAck) : (memory_.u8(pdi) & ~kRepeatAck)));
    }
  }
}

std::uint16_t Esc::mailbox_out_capacity() const noexcept {
  const EscSyncManager* out = sync_manager(1);
  if (out == nullptr || !has_mailbox()) return 0;
  return static_cast<std::uint16_t>(std::min<std::uint32_t>(out->length(), kMaxMailboxBytes));
}

Status Esc::post_mailbox(ConstByteSpan message) noexcept {
  EscSyncManager* out = sync_manager(1);
  if (out == nullptr || !has_mailbox() || !out->active()) return make_error(Errc::refused, "mailbox not active");
  if (message.empty() || message.size() > mailbox_out_capacity()) {
    return make_error(Errc::invalid_argument, "mailbox message length", static_cast<std::uint32_t>(message.size()),
                      mailbox_out_capacity());
  }
  if (queue_count_ == 0 && !out->mailbox_full()) {
    (void)publish_mailbox(message);
    return Status::success();
  }
  if (queue_count_ == kMailboxQueueDepth) {
    ++counters_.mailbox_dropped;
    return make_error(Errc::capacity_exceeded, "mailbox queue full", static_cast<std::uint32_t>(kMailboxQueueDepth));
  }
  const std::size_t slot = (queue_head_ + queue_count_) % kMailboxQueueDepth;
  std::memcpy(queue_[slot].data(), message.data(), message.size());
  queue_length_[slot] = static_cast<std::uint16_t>(message.size());
  ++queue_count_;
  return Status::success();
}

bool Esc::publish_mailbox(ConstByteSpan message) noexcept {
  EscSyncManager* out = sync_manager(1);
  if (out == nullptr) return false;
  const ByteSpan buffer = out->device_write_buffer(memory_);
  if (buffer.size() < message.size()) return false;
  std::memcpy(buffer.data(), message.data(), message.size());
  std::memset(buffer.data() + message.size(), 0, buffer.size() - message.size());
  out->device_published(memory_);
  if (message.data() != last_sent_.data()) std::memcpy(last_sent_.data(), message.data(), message.size());
  last_sent_length_ = static_cast<std::uint16_t>(message.size());
  ++counters_.mailbox_sent;
  return true;
}

void Esc::deliver_queued_mailbox() noexcept {
  const EscSyncManager* out = sync_manager(1);
  while (queue_count_ > 0 && out != nullptr && out->active() && !out->mailbox_full()) {
    (void)publish_mailbox(ConstByteSpan(queue_[queue_head_].data(), queue_length_[queue_head_]));
    queue_head_ = (queue_head_ + 1) % kMailboxQueueDepth;
    --queue_count_;
  }
}

void Esc::run_cycle(CycleTrigger trigger, hal::Nanoseconds when, std::uint64_t system_time) noexcept {
  const ProcessDataLayout layout = device_->process_data_layout();
  ConstByteSpan outputs{};
  ByteSpan inputs{};
  EscSyncManager* out_sm = layout.output_bytes > 0 ? sync_manager(layout.output_sm) : nullptr;
  EscSyncManager* in_sm = layout.input_bytes > 0 ? sync_manager(layout.input_sm) : nullptr;
  if (out_sm != nullptr && out_sm->active()) {
    const ConstByteSpan buffer = out_sm->device_read_buffer(memory_);
    outputs = buffer.first(std::min<std::size_t>(buffer.size(), layout.output_bytes));
  }
  if (in_sm != nullptr && in_sm->active()) {
    const ByteSpan buffer = in_sm->device_write_buffer(memory_);
    inputs = buffer.first(std::min<std::size_t>(buffer.size(), layout.input_bytes));
  }
  const CycleContext context{when, system_time, state_, trigger};
  device_->on_cycle(outputs, inputs, context, *this);
  if (in_sm != nullptr && !inputs.empty()) in_sm->device_published(memory_);
  ++counters_.cycles;
  if (state_ == AlState::op && !outputs.empty()) {
    last_latch_ = OutputLatch{when, system_time, trigger};
    ++latch_count_;
  }
}

hal::Nanoseconds Esc::watchdog_unit_ns() const noexcept {
  return (hal::Nanoseconds{memory_.u16(reg::kWatchdogDivider)} + 2) * 40;
}

void Esc::check_watchdogs(hal::Nanoseconds now) noexcept {
  if (pd_watchdog_running_ && !pd_watchdog_expired_) {
    const hal::Nanoseconds limit = watchdog_unit_ns() * memory_.u16(reg::kWatchdogTimeProcessData);
    if (limit > 0 && now - pd_watchdog_trigger_ >= limit) {
      pd_watchdog_expired_ = true;
      memory_.set_u16(reg::kWatchdogStatusProcessData, 0x0000);
      if (memory_.u8(0x0442) < 0xFF) memory_.set_u8(0x0442, static_cast<std::uint8_t>(memory_.u8(0x0442) + 1U));
      ++counters_.watchdog_expiries;
      // The firmware's reaction: outputs are no longer valid, fall back to SAFE-OP with an error.
      if (!frozen_ && !device_emulation_ && state_ == AlState::op) raise_al_error(AlState::safe_op, al::kSyncManagerWatchdog);
    }
  }
  if (frozen_ && !device_emulation_ && !pdi_watchdog_expired_) {
    const hal::Nanoseconds limit = watchdog_unit_ns() * memory_.u16(reg::kWatchdogTimePdi);
    if (limit > 0 && now - frozen_since_ >= limit) {
      pdi_watchdog_expired_ = true;
      if (memory_.u8(0x0443) < 0xFF) memory_.set_u8(0x0443, static_cast<std::uint8_t>(memory_.u8(0x0443) + 1U));
      refresh_dl_status();
    }
  }
  if (op_pending_ && !frozen_ && now - op_pending_since_ >= kSafeOpToOpTimeout) {
    op_pending_ = false;
    refuse(AlState::safe_op, al::kSyncManagerWatchdog);
  }
}

bool Esc::dc_synchronous() const noexcept {
  const std::uint8_t activation = memory_.u8(reg::kDcActivation);
  return config_.dc_supported && (activation & reg::kDcActivateCyclic) != 0 && (activation & reg::kDcActivateSync0) != 0;
}

DcSyncSettings Esc::dc_sync_settings() const noexcept {
  DcSyncSettings s;
  if (!config_.dc_supported) return s;
  const std::uint8_t activation = memory_.u8(reg::kDcActivation);
  s.cyclic_active = (activation & reg::kDcActivateCyclic) != 0;
  s.sync0_active = (activation & reg::kDcActivateSync0) != 0;
  s.sync1_active = (activation & reg::kDcActivateSync1) != 0;
  s.start_time = memory_.u64(reg::kDcStartTime);
  s.sync0_cycle_ns = memory_.u32(reg::kDcSync0CycleTime);
  s.sync1_cycle_ns = memory_.u32(reg::kDcSync1CycleTime);
  return s;
}

}  // namespace rescue::drivers
