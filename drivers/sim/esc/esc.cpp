// The ESC hardware: power-up, ports, the EtherCAT processing unit and the master's memory access.
// The slave firmware's part lives in esc_al.cpp (AL state machine) and esc_pdi.cpp (PDI side).
#include "drivers/sim/esc/esc.hpp"

#include <algorithm>
#include <cstring>

#include "ecat/codec/command.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

namespace reg = ecat::reg;
using ecat::Command;

constexpr std::uint32_t kDlControlReset = 0x00070001;  // non-EtherCAT frames destroyed, RX FIFO 7, loops auto
constexpr std::uint16_t kWatchdogDividerReset = 0x09C2;  // 100 us units
constexpr std::uint16_t kWatchdogTimeReset = 0x03E8;     // 1000 units = 100 ms
constexpr std::uint16_t kEventDlStatus = 0x0004;
constexpr std::uint16_t kEventAlStatus = 0x0008;
constexpr std::uint32_t kDlControlAliasEnable = 0x01000000;
constexpr std::uint8_t kEscConfigDeviceEmulation = 0x01;
constexpr std::uint8_t kEscConfigEnhancedLinkAllPorts = 0x02;
constexpr std::uint8_t kSmActivateWritable = 0xC3;
constexpr std::uint16_t kForeignProductXor = 0x5A5A;  // enable, repeat, latch event ECAT/PDI

bool overlaps(std::uint32_t first, std::uint32_t end, std::uint32_t reg_first, std::uint32_t reg_count) noexcept {
  return first < reg_first + reg_count && reg_first < end;
}

}  // namespace

void Esc::power_up(const EscConfig& config, SlaveDevice& device, hal::Nanoseconds now) noexcept {
  config_ = config;
  config_.port_count = std::min<std::uint8_t>(config.port_count, kMaxEscPorts);
  config_.fmmu_count = std::min<std::uint8_t>(config.fmmu_count, kMaxFmmus);
  config_.sync_manager_count = std::min<std::uint8_t>(config.sync_manager_count, kMaxSyncManagers);
  device_ = &device;
  powered_ = true;
  frozen_ = false;
  now_ = now;
  memory_.reset(config_);

  memory_.set_u8(reg::kType, config_.type);
  memory_.set_u8(reg::kRevision, config_.revision);
  memory_.set_u16(reg::kBuild, config_.build);
  memory_.set_u8(reg::kFmmusSupported, config_.fmmu_count);
  memory_.set_u8(reg::kSyncManagersSupported, config_.sync_manager_count);
  memory_.set_u8(reg::kRamSize, config_.ram_kib);
  std::uint8_t ports = 0;
  for (unsigned p = 0; p < config_.port_count; ++p) ports = static_cast<std::uint8_t>(ports | (0x03U << (2U * p)));  // MII
  memory_.set_u8(reg::kPortDescriptor, ports);
  memory_.set_u16(reg::kEscFeatures, config_.features);
  memory_.set_u32(reg::kDlControl, kDlControlReset);
  dl_control_ = kDlControlReset;
  memory_.set_u16(reg::kWatchdogDivider, kWatchdogDividerReset);
  memory_.set_u16(reg::kWatchdogTimePdi, kWatchdogTimeReset);
  memory_.set_u16(reg::kWatchdogTimeProcessData, kWatchdogTimeReset);
  memory_.set_u16(reg::kWatchdogStatusProcessData, 0x0001);  // not expired

  for (unsigned n = 0; n < kMaxSyncManagers; ++n) sync_managers_[n].reset(n);
  fmmus_dirty_ = true;
  auto_close_latched_.fill(false);
  arrived_.fill(false);
  latch_requested_ = false;
  dl_control_pending_ = false;
  al_error_ = false;
  al_control_unread_ = false;
  op_pending_ = false;
  outputs_received_ = false;
  queue_head_ = 0;
  queue_count_ = 0;
  last_sent_length_ = 0;
  repeat_check_ = false;
  pd_watchdog_running_ = false;
  pd_watchdog_expired_ = false;
  pdi_watchdog_expired_ = false;
  latch_count_ = 0;
  last_latch_ = OutputLatch{};

  dc_.reset(memory_, config_, now);
  sii_.power_up(memory_, config_, device.sii_image());
  if (foreign_identity_) {
    // Product code (SII words 0x0A/0x0B) of another device type; the config area CRC does not cover it.
    sii_.set_word(ecat::sii::kProductCode, static_cast<std::uint16_t>(sii_.word(ecat::sii::kProductCode) ^ kForeignProductXor));
  }
  apply_configuration_area();
  memory_.set_u16(reg::kAlControl, static_cast<std::uint16_t>(AlState::init));
  state_ = AlState::init;
  set_al_status(AlState::init, false, reg::al_code::kNoError);
  if (!device_emulation_) {
    // The slave firmware keeps every SyncManager deactivated until its state needs it.
    for (unsigned n = 0; n < config_.sync_manager_count; ++n) sync_managers_[n].set_deactivated_by_device(memory_, true);
  }
  refresh_dl_status();
}

void Esc::apply_configuration_area() noexcept {
  device_emulation_ = false;
  if (!sii_.configuration_valid()) return;  // a bad CRC leaves the registers at their reset values
  memory_.set_u16(0x0140, sii_.word(0));     // PDI control, ESC configuration
  memory_.set_u16(0x0150, sii_.word(1));     // PDI configuration
  memory_.set_u16(reg::kDcSyncPulseLength, sii_.word(2));
  memory_.set_u16(0x0152, sii_.word(3));     // extended PDI configuration
  memory_.set_u16(reg::kStationAlias, sii_.word(ecat::sii::kStationAlias));
  device_emulation_ = (memory_.u8(0x0141) & kEscConfigDeviceEmulation) != 0;
}

// --- time ------------------------------------------------------------------------------------

void Esc::advance_to(hal::Nanoseconds now) noexcept {
  if (!powered_ || now < now_) return;
  hal::Nanoseconds pulse_at = 0;
  while (dc_.sync0_due(memory_, now, pulse_at)) {
    dc_.advance(pulse_at);
    const std::uint64_t system_time = dc_.fire_sync0(memory_);
    ++counters_.sync0_pulses;
    if (!frozen_ && !device_emulation_) {
      device_->step(pulse_at, *this);
      if ((state_ == AlState::safe_op || state_ == AlState::op) && dc_synchronous()) {
        run_cycle(CycleTrigger::sync0, pulse_at, system_time);
      }
    }
  }
  dc_.advance(now);
  now_ = now;
  sii_.update(memory_, now);
  if (sii_.take_reload_done()) {
    apply_configuration_area();
    refresh_dl_status();
  }
  check_watchdogs(now);
  serve_application(now);
  if (!frozen_ && !device_emulation_) device_->step(now, *this);
}

void Esc::begin_frame(hal::Nanoseconds sof) noexcept {
  ++counters_.frames;
  arrived_.fill(false);
  arrived_[0] = true;
  arrival_[0] = sof;
  latch_requested_ = false;
  dc_.on_frame_start(memory_, sof);
}

void Esc::arrived_at_port(unsigned port, hal::Nanoseconds t) noexcept {
  if (port >= kMaxEscPorts) return;
  arrived_[port] = true;
  arrival_[port] = t;
}

void Esc::frame_left() noexcept {
  if (latch_requested_) dc_.latch_receive_times(memory_, arrival_, arrived_);
  latch_requested_ = false;
  if (dl_control_pending_) apply_dl_control();
  dl_control_pending_ = false;
}

// --- ports -----------------------------------------------------------------------------------

bool Esc::loop_closed(unsigned port) const noexcept {
  if (port >= config_.port_count) return true;
  const unsigned setting = (dl_control_ >> reg::dl_control_loop_shift(port)) & 0x03U;
  switch (setting) {
    case 0: return !link_[port];                                // auto
    case 1: return !link_[port] || auto_close_latched_[port];   // auto close
    case 2: return false;                                       // always open
    default: return true;                                       // always closed
  }
}

void Esc::set_link(unsigned port, bool up) noexcept {
  if (port >= kMaxEscPorts) return;
  const bool implemented = port < config_.port_count;
  const bool now_up = up && implemented;
  if (link_[port] && !now_up) {
    auto_close_latched_[port] = true;
    const std::uint32_t counter = reg::kLostLinkCounter + port;
    if (memory_.u8(counter) < 0xFF) memory_.set_u8(counter, static_cast<std::uint8_t>(memory_.u8(counter) + 1U));
  }
  link_[port] = now_up;
  refresh_dl_status();
}

void Esc::apply_dl_control() noexcept {
  // Writing "auto close" again re-opens a port that closed on a link loss (ET1100 behaviour).
  dl_control_ = memory_.u32(reg::kDlControl);
  for (unsigned port = 0; port < config_.port_count; ++port) {
    const unsigned setting = (dl_control_ >> reg::dl_control_loop_shift(port)) & 0x03U;
    if (setting != 1 || link_[port]) auto_close_latched_[port] = false;
  }
  refresh_dl_status();
}

void Esc::refresh_dl_status() noexcept {
  std::uint16_t status = 0;
  if (sii_.configuration_valid()) status |= reg::kDlStatusPdiOperational;
  const bool pdi_alive = !device_emulation_ && !pdi_watchdog_expired_;
  if (pdi_alive) status |= reg::kDlStatusPdiWatchdog;
  if ((memory_.u8(0x0141) & kEscConfigEnhancedLinkAllPorts) != 0) status |= 0x0004;
  for (unsigned port = 0; port < kMaxEscPorts; ++port) {
    if (link_[port]) status |= static_cast<std::uint16_t>(reg::dl_status_link(port) | reg::dl_status_communication(port));
    if (loop_closed(port)) status |= reg::dl_status_loop_closed(port);
  }
  if (status != memory_.u16(reg::kDlStatus)) {
    memory_.set_u16(reg::kDlStatus, status);
    raise_event(kEventDlStatus);
  }
}

void Esc::raise_event(std::uint16_t bit) noexcept {
  memory_.set_u16(reg::kEcatEventRequest, static_cast<std::uint16_t>(memory_.u16(reg::kEcatEventRequest) | bit));
}

void Esc::set_al_status(AlState state, bool error, std::uint16_t code) noexcept {
  const auto status = static_cast<std::uint16_t>(static_cast<std::uint16_t>(state) | (error ? reg::kAlErrorBit : 0U));
  if (status != memory_.u16(reg::kAlStatus) || code != memory_.u16(reg::kAlStatusCode)) raise_event(kEventAlStatus);
  memory_.set_u16(reg::kAlStatus, status);
  memory_.set_u16(reg::kAlStatusCode, code);
}

// --- EtherCAT processing unit ------------------------------------------------------------------

void Esc::process(const ecat::MutableDatagramView& d) noexcept {
  const Command command = d.command();
  const ecat::AddressKind kind = ecat::address_kind(command);
  // Every datagram passing carries the OR of all slaves' masked ECAT events in its IRQ field.
  const auto irq = static_cast<std::uint16_t>(memory_.u16(reg::kEcatEventRequest) & memory_.u16(reg::kEcatEventMask));
  if (irq != 0) store_le16(d.raw() + 8, static_cast<std::uint16_t>(d.irq() | irq));
  if (kind == ecat::AddressKind::none) return;
  if (kind == ecat::AddressKind::logical) {
    process_logical(d);
    return;
  }

  const std::uint16_t adp = d.adp();
  bool addressed = false;
  if (kind == ecat::AddressKind::position || kind == ecat::AddressKind::broadcast) {
    addressed = kind == ecat::AddressKind::broadcast || adp == 0;
    d.set_adp(static_cast<std::uint16_t>(adp + 1U));
  } else {
    addressed = adp == memory_.u16(reg::kStationAddress) ||
                ((dl_control_ & kDlControlAliasEnable) != 0 && adp == memory_.u16(reg::kStationAlias));
  }

  // A datagram for another ESC passes by untouched (ARMW/FRMW: every other ESC writes).
  if (!addressed && command != Command::ARMW && command != Command::FRMW) return;

  const ByteSpan data = d.data();
  const std::uint32_t address = d.ado();
  const auto count = static_cast<std::uint32_t>(data.size());
  unsigned increment = 0;
  switch (command) {
    case Command::APRD: case Command::FPRD: case Command::BRD:
      if (addressed && read_range(address, data.data(), count, command == Command::BRD)) increment = 1;
      break;
    case Command::APWR: case Command::FPWR: case Command::BWR:
      if (addressed && write_range(address, data.data(), count)) increment = 1;
      break;
    case Command::APRW: case Command::FPRW: case Command::BRW: {
      if (!addressed) break;
      // The memory takes the data as it arrived; the frame leaves with what the memory held.
      std::array<std::uint8_t, ecat::kMaxDatagramDataLength> incoming{};
      std::memcpy(incoming.data(), data.data(), count);
      if (read_range(address, data.data(), count, command == Command::BRW)) increment += 1;
      if (write_range(address, incoming.data(), count)) increment += 2;
      break;
    }
    case Command::ARMW: case Command::FRMW:
      if (addressed) {
        if (read_range(address, data.data(), count, false)) increment = 1;
      } else if (write_range(address, data.data(), count)) {
        increment = 1;
      }
      break;
    default:
      break;
  }
  if (increment != 0) d.set_wkc(static_cast<std::uint16_t>(d.wkc() + increment));
}

bool Esc::read_range(std::uint32_t address, std::uint8_t* frame, std::uint32_t count, bool or_into_frame) noexcept {
  bool any = false;
  const std::uint32_t end = std::min<std::uint32_t>(address + count, kEscMemorySize);
  const std::uint32_t register_end = std::min<std::uint32_t>(end, kEscRegisterSpace);
  for (std::uint32_t a = address; a < register_end; ++a) {
    if (!memory_.readable(a)) continue;
    const std::uint8_t v = memory_.u8(a);
    std::uint8_t& f = frame[a - address];
    f = or_into_frame ? static_cast<std::uint8_t>(f | v) : v;
    any = true;
  }
  if (address < register_end) after_register_read(address, register_end);
  const std::uint32_t ram_first = std::max<std::uint32_t>(address, kEscRegisterSpace);
  if (ram_first < end && ram_access(ram_first, end - ram_first, nullptr, frame + (ram_first - address), or_into_frame, 0xFF)) {
    any = true;
  }
  return any;
}

void Esc::after_register_read(std::uint32_t first, std::uint32_t end) noexcept {
  // Reading the status registers acknowledges their ECAT events.
  std::uint16_t clear = 0;
  if (overlaps(first, end, reg::kDlStatus, 2)) clear |= kEventDlStatus;
  if (overlaps(first, end, reg::kAlStatus, 2)) clear |= kEventAlStatus;
  if (clear != 0) {
    memory_.set_u16(reg::kEcatEventRequest, static_cast<std::uint16_t>(memory_.u16(reg::kEcatEventRequest) & ~clear));
  }
  if (config_.dc_supported && overlaps(first, end, reg::kDcSync0Status, 1)) memory_.set_u8(reg::kDcSync0Status, 0);
}

bool Esc::write_range(std::uint32_t address, const std::uint8_t* frame, std::uint32_t count) noexcept {
  bool any = false;
  bool triggers = false;
  const std::uint32_t end = std::min<std::uint32_t>(address + count, kEscMemorySize);
  const std::uint32_t register_end = std::min<std::uint32_t>(end, kEscRegisterSpace);
  for (std::uint32_t a = address; a < register_end; ++a) {
    const std::uint8_t attributes = memory_.attributes(a);
    if ((attributes & esc_attr::kWritable) == 0) continue;
    if ((attributes & esc_attr::kWriteTrigger) != 0) {
      triggers = true;
      continue;
    }
    memory_.set_u8(a, frame[a - address]);
    any = true;
    if (a >= reg::kFmmuBase && a < reg::kFmmuBase + kMaxFmmus * reg::kFmmuSize) fmmus_dirty_ = true;
  }
  if (triggers && trigger_writes(address, frame, register_end - address)) any = true;
  const std::uint32_t ram_first = std::max<std::uint32_t>(address, kEscRegisterSpace);
  if (ram_first < end && ram_access(ram_first, end - ram_first, frame + (ram_first - address), nullptr, false, 0xFF)) {
    any = true;
  }
  return any;
}

bool Esc::write_byte_masked(std::uint32_t address, std::uint8_t value, std::uint8_t mask) noexcept {
  if (address >= kEscMemorySize) return false;
  if (address >= kEscRegisterSpace) return ram_access(address, 1, &value, nullptr, false, mask);
  const auto merged = static_cast<std::uint8_t>((memory_.u8(address) & ~mask) | (value & mask));
  return write_range(address, &merged, 1);
}

bool Esc::ram_access(std::uint32_t address, std::uint32_t count, const std::uint8_t* in, std::uint8_t* out,
                     bool or_into_frame, std::uint8_t single_byte_mask) noexcept {
  bool any = false;
  const std::uint32_t end = address + count;
  std::uint32_t a = address;
  while (a < end && a < memory_.ram_end()) {  // beyond the RAM: not accessed, not counted
    // The lowest-numbered SyncManager guarding `a` decides; chunks end where another SM starts.
    EscSyncManager* guard = nullptr;
    std::uint32_t chunk_end = std::min(end, memory_.ram_end());
    for (unsigned n = 0; n < config_.sync_manager_count; ++n) {
      EscSyncManager& sm = sync_managers_[n];
      if (guard == nullptr && sm.guards(a)) {
        guard = &sm;
        chunk_end = std::min(chunk_end, sm.start() + sm.length());
      } else if (sm.enabled_by_master() && sm.length() > 0 && sm.start() > a) {
        chunk_end = std::min(chunk_end, sm.start());
      }
    }
    const std::uint32_t offset = a - address;
    const std::uint32_t n = chunk_end - a;
    bool ok = true;
    if (guard != nullptr) {
      ok = in != nullptr ? guard->master_write(memory_, a, in + offset, n, single_byte_mask)
                         : guard->master_read(memory_, a, out + offset, n, or_into_frame);
    } else if (in != nullptr) {
      if (n == 1 && single_byte_mask != 0xFF) {
        memory_.set_u8(a, static_cast<std::uint8_t>((memory_.u8(a) & ~single_byte_mask) | (in[offset] & single_byte_mask)));
      } else {
        std::memcpy(memory_.at(a), in + offset, n);
      }
    } else {
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint8_t v = memory_.u8(a + i);
        out[offset + i] = or_into_frame ? static_cast<std::uint8_t>(out[offset + i] | v) : v;
      }
    }
    any = any || ok;
    a = chunk_end;
  }
  return any;
}

bool Esc::trigger_writes(std::uint32_t address, const std::uint8_t* frame, std::uint32_t count) noexcept {
  const std::uint32_t end = address + count;
  const auto written = [&](std::uint32_t a) { return a >= address && a < end; };
  const auto value = [&](std::uint32_t a) { return frame[a - address]; };
  const auto store = [&](std::uint32_t first, std::uint32_t n) {
    for (std::uint32_t a = first; a < first + n; ++a) {
      if (written(a)) memory_.set_u8(a, value(a));
    }
  };
  bool accepted = false;

  if (overlaps(address, end, reg::kDlControl, 4)) {
    store(reg::kDlControl, 4);
    dl_control_pending_ = true;
    accepted = true;
  }
  if (overlaps(address, end, reg::kAlControl, 2)) {
    // AL control behaves like a mailbox: until the slave firmware has read the last request, a
    // new one is refused (a hung application makes AL control writes fail).
    if (!al_control_unread_ || device_emulation_) {
      store(reg::kAlControl, 2);
      al_control_unread_ = true;
      accepted = true;
    }
  }
  // Error and watchdog counters, cleared as the ET1100/ET1200 datasheet says (the value written is
  // ignored): a write to any of 0x0300-0x030B clears all twelve RX and forwarded RX counters, to
  // 0x030C or 0x030D that counter, to any of 0x0310-0x0313 all four lost-link counters, to any of
  // 0x0442-0x0443 both watchdog counters. The PDI error code (0x030E) is read-only.
  const auto clear_group = [&](std::uint32_t reg_first, std::uint32_t reg_count) {
    if (!overlaps(address, end, reg_first, reg_count)) return;
    for (std::uint32_t a = reg_first; a < reg_first + reg_count; ++a) memory_.set_u8(a, 0);
    accepted = true;
  };
  clear_group(reg::kRxErrorCounter, 0x0C);
  clear_group(reg::kRxErrorCounter + 0x0CU, 1);
  clear_group(reg::kRxErrorCounter + 0x0DU, 1);
  clear_group(reg::kRxErrorCounter + 0x10U, 4);
  clear_group(0x0442, 2);
  if (overlaps(address, end, reg::kSiiControl, 14)) {
    std::array<std::uint8_t, 14> bytes{};
    std::array<bool, 14> mask{};
    for (std::uint32_t i = 0; i < 14; ++i) {
      mask[i] = written(reg::kSiiControl + i);
      if (mask[i]) bytes[i] = value(reg::kSiiControl + i);
    }
    sii_.on_master_write(memory_, bytes.data(), mask.data());
    accepted = true;
  }
  // Most trigger writes are the reference time (0x0910): skip the SyncManager block at once.
  const unsigned sm_count = config_.sync_manager_count;
  const bool reaches_sync_managers = overlaps(address, end, reg::sync_manager(0), 8U * sm_count);
  for (unsigned n = 0; reaches_sync_managers && n < sm_count; ++n) {
    const std::uint32_t base = reg::sync_manager(n);
    if (!overlaps(address, end, base, 8)) continue;
    EscSyncManager& sm = sync_managers_[n];
    // Start, length and control are write-protected while the master has the SM enabled.
    if (!sm.enabled_by_master() && overlaps(address, end, base, 5)) {
      store(base, 5);
      accepted = true;
    }
    const std::uint32_t activate = base + reg::kSmActivate;
    if (written(activate)) {
      const std::uint8_t old = memory_.u8(activate);
      memory_.set_u8(activate, static_cast<std::uint8_t>((old & ~kSmActivateWritable) | (value(activate) & kSmActivateWritable)));
      if (((old ^ memory_.u8(activate)) & reg::kSmRepeat) != 0) repeat_check_ = true;
      accepted = true;
    }
    sm.load(memory_);
  }
  if (config_.dc_supported) {
    if (overlaps(address, end, reg::kDcReceiveTimePort0, 4)) {
      latch_requested_ = true;
      accepted = true;
    }
    if (written(reg::kDcSystemTime) && written(reg::kDcSystemTime + 3)) {
      const unsigned bytes = written(reg::kDcSystemTime + 7) ? 8U : 4U;
      std::array<std::uint8_t, 8> received{};
      for (unsigned i = 0; i < bytes; ++i) received[i] = value(reg::kDcSystemTime + i);
      dc_.on_system_time_write(memory_, load_le64(received.data()), bytes, arrival_[0]);
      accepted = true;
    } else if (overlaps(address, end, reg::kDcSystemTime, 8)) {
      accepted = true;  // a partial write reaches the register but carries no usable time
    }
    if (overlaps(address, end, reg::kDcSpeedCounterStart, 2)) {
      store(reg::kDcSpeedCounterStart, 2);
      dc_.on_speed_counter_start_write(memory_);
      accepted = true;
    }
    if (overlaps(address, end, reg::kDcStartTime, 8)) {
      store(reg::kDcStartTime, 8);
      dc_.on_start_time_write(memory_);
      accepted = true;
    }
    if (written(reg::kDcActivation)) {
      memory_.set_u8(reg::kDcActivation, value(reg::kDcActivation));
      dc_.on_activation_write(memory_, arrival_[0]);
      accepted = true;
    }
  }
  return accepted;
}

// --- faults -------------------------------------------------------------------------------------

void Esc::set_application_frozen(bool frozen) noexcept {
  if (frozen && !frozen_) frozen_since_ = now_;
  frozen_ = frozen;
  if (!frozen && pdi_watchdog_expired_) {
    pdi_watchdog_expired_ = false;
    refresh_dl_status();
  }
}

void Esc::count_invalid_frame(unsigned port) noexcept {
  if (port >= kMaxEscPorts) return;
  const std::uint32_t counter = reg::kRxErrorCounter + 2U * port;
  if (memory_.u8(counter) < 0xFF) memory_.set_u8(counter, static_cast<std::uint8_t>(memory_.u8(counter) + 1U));
}

void Esc::count_forwarded_error(unsigned port) noexcept {
  if (port >= kMaxEscPorts) return;
  const std::uint32_t counter = reg::kForwardedRxErrorCounter + port;
  if (memory_.u8(counter) < 0xFF) memory_.set_u8(counter, static_cast<std::uint8_t>(memory_.u8(counter) + 1U));
}

void Esc::inject_device_fault(std::uint16_t error_code) noexcept {
  if (powered_ && device_ != nullptr) device_->inject_fault(error_code);
}

}  // namespace rescue::drivers
