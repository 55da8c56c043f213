// A register-level model of one EtherCAT slave controller (ESC) and of the generic part of the slave
// firmware behind it (what every slave stack does: the AL state machine with its SyncManager checks,
// mailbox and process-data buffer handling, watchdog reactions). The device application
// (drivers/sim/devices/slave_device.hpp) supplies the rest.
//
// Per frame, the segment calls, in time order:
//   advance_to(t0)      time moves on: device physics, SYNC0 pulses, watchdogs, EEPROM completion
//   begin_frame(t0)     the frame's start reached port 0: system time latched for 0x0910 reads
//   process(datagram)   the EtherCAT processing unit, once per datagram in frame order
//   end_frame(t0)       what happens at the end of the frame: AL control, SII command, mailbox and
//                       process-data events handled by the slave firmware
//   arrived_at_port(n, t)   the frame came back from the branch behind port n (n != 0)
//   frame_left()        receive-time latch committed (if the frame wrote 0x0900), DL control applied
//
// Addressing (ETG.1000.4 / ESC datasheet section I): auto-increment (ADP 0 at arrival, every ESC
// increments ADP), configured station address or alias (alias only when DL control bit 24 is set),
// broadcast (every ESC, ADP incremented), logical through FMMUs. Working counter: +1 for a read,
// +1 for a write, +1/+2/+3 for read-write (read/write/both); ARMW/FRMW: the addressed ESC reads,
// every other ESC writes. A datagram counts only if it reached at least one byte that exists and
// may be accessed that way (see drivers/sim/esc/esc_memory.hpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/span.hpp"
#include "drivers/sim/esc/esc_config.hpp"
#include "drivers/sim/esc/esc_dc.hpp"
#include "drivers/sim/esc/esc_fmmu.hpp"
#include "drivers/sim/esc/esc_memory.hpp"
#include "drivers/sim/esc/esc_sii.hpp"
#include "drivers/sim/esc/esc_sync_manager.hpp"
#include "drivers/sim/devices/slave_device.hpp"
#include "ecat/codec/frame.hpp"
#include "hal/time/clock.hpp"

namespace rescue::drivers {

// When and at which system time a slave applied its outputs (one application cycle in OP).
struct OutputLatch {
  hal::Nanoseconds segment_time{0};  // true time of the event
  std::uint64_t system_time{0};      // the slave's DC system time then (the SYNC0 time in DC mode)
  CycleTrigger trigger{CycleTrigger::sm_event};
};

struct EscCounters {
  std::uint64_t frames{0};
  std::uint64_t al_transitions{0};
  std::uint64_t al_refusals{0};
  std::uint64_t mailbox_received{0};
  std::uint64_t mailbox_sent{0};
  std::uint64_t mailbox_dropped{0};  // posts refused because the queue was full
  std::uint64_t cycles{0};
  std::uint64_t sync0_pulses{0};
  std::uint64_t watchdog_expiries{0};
};

class Esc final : public EscPdi {
 public:
  static constexpr std::size_t kMailboxQueueDepth = 4;
  static constexpr std::size_t kMaxMailboxBytes = 1024;
  // How long SAFE-OP -> OP waits for the first valid outputs before refusing (ESI default).
  static constexpr hal::Nanoseconds kSafeOpToOpTimeout = 10 * hal::kNsPerSec;

  Esc() = default;

  // Power-up at `now`: registers at reset values, EEPROM loaded from the device's SII image,
  // configuration area applied (alias, PDI configuration, device emulation), AL state INIT.
  void power_up(const EscConfig& config, SlaveDevice& device, hal::Nanoseconds now) noexcept;
  void power_down() noexcept { powered_ = false; }
  bool powered() const noexcept { return powered_; }

  // --- frame passage (see the header comment) ---
  void advance_to(hal::Nanoseconds now) noexcept;
  void begin_frame(hal::Nanoseconds sof) noexcept;
  void process(const ecat::MutableDatagramView& datagram) noexcept;
  void end_frame(hal::Nanoseconds now) noexcept;
  void arrived_at_port(unsigned port, hal::Nanoseconds t) noexcept;
  void frame_left() noexcept;

  // --- ports ---
  void set_link(unsigned port, bool up) noexcept;
  bool link(unsigned port) const noexcept { return port < kMaxEscPorts && link_[port]; }
  // Loop closed: frames are not sent out of this port but go on to the next one internally.
  bool loop_closed(unsigned port) const noexcept;

  // --- faults ---
  // A hung device application: the ESC still forwards frames and answers its registers, but AL
  // control, mailbox and process data are no longer served (and the PDI watchdog expires).
  void set_application_frozen(bool frozen) noexcept;
  bool application_frozen() const noexcept { return frozen_; }
  void inject_device_fault(std::uint16_t error_code) noexcept;
  // Every request for `state` is refused with `al_status_code` (error indication set, the slave
  // stays where it is) until set again with code 0. Survives power cycles.
  void refuse_state(AlState state, std::uint16_t al_status_code) noexcept {
    refused_state_ = state;
    refused_code_ = al_status_code;
  }
  // A frame with a broken FCS or length arrived at `port` (invalid frame counter 0x0300 + 2n).
  void count_invalid_frame(unsigned port) noexcept;
  // A frame already damaged upstream arrived at `port` (forwarded RX error counter 0x0308 + n).
  void count_forwarded_error(unsigned port) noexcept;
  // The next power-up loads an SII whose product code differs (a device of another type plugged
  // into this place: the simulator's foreign device). Survives power cycles until cleared.
  void set_foreign_identity(bool foreign) noexcept { foreign_identity_ = foreign; }
  bool foreign_identity() const noexcept { return foreign_identity_; }

  // --- observation (tests, the simulator's figures) ---
  std::uint8_t register_u8(std::uint32_t a) const noexcept { return memory_.u8(a); }
  std::uint16_t register_u16(std::uint32_t a) const noexcept { return memory_.u16(a); }
  std::uint32_t register_u32(std::uint32_t a) const noexcept { return memory_.u32(a); }
  std::uint64_t register_u64(std::uint32_t a) const noexcept { return memory_.u64(a); }
  std::uint64_t system_time_at(hal::Nanoseconds t) const noexcept { return dc_.system_time_at(memory_, t); }
  // The crystal's deviation steps to `drift_ppm` at `now` (a temperature step; the drift loop must follow).
  void change_crystal_drift(hal::Nanoseconds now, double drift_ppm) noexcept { dc_.change_crystal_drift(now, drift_ppm); }
  std::uint64_t local_time_at(hal::Nanoseconds t) const noexcept { return dc_.local_at(t); }
  const EscDc& dc() const noexcept { return dc_; }
  const EscConfig& config() const noexcept { return config_; }
  const EscCounters& counters() const noexcept { return counters_; }
  bool device_emulation() const noexcept { return device_emulation_; }
  OutputLatch last_output_latch() const noexcept { return last_latch_; }
  std::uint64_t output_latch_count() const noexcept { return latch_count_; }

  // --- EscPdi (the device's side) ---
  AlState al_state() const noexcept override { return state_; }
  Status post_mailbox(ConstByteSpan message) noexcept override;
  std::uint16_t mailbox_out_capacity() const noexcept override;
  void raise_al_error(AlState fall_back_to, std::uint16_t al_status_code) noexcept override;
  DcSyncSettings dc_sync_settings() const noexcept override;

 private:
  // Memory access by the master (register area and process RAM, SyncManager rules applied).
  bool read_range(std::uint32_t address, std::uint8_t* frame, std::uint32_t count, bool or_into_frame) noexcept;
  bool write_range(std::uint32_t address, const std::uint8_t* frame, std::uint32_t count) noexcept;
  bool write_byte_masked(std::uint32_t address, std::uint8_t value, std::uint8_t mask) noexcept;
  // Process RAM: writes take bytes from `in`, reads put them into `out` (exactly one is non-null).
  bool ram_access(std::uint32_t address, std::uint32_t count, const std::uint8_t* in, std::uint8_t* out,
                  bool or_into_frame, std::uint8_t single_byte_mask) noexcept;
  void after_register_read(std::uint32_t first, std::uint32_t end) noexcept;
  bool trigger_writes(std::uint32_t address, const std::uint8_t* frame, std::uint32_t count) noexcept;
  void process_logical(const ecat::MutableDatagramView& datagram) noexcept;
  void reload_fmmus() noexcept;
  bool logical_pass(std::uint32_t logical, std::uint8_t* frame, std::uint32_t count, bool write) noexcept;
  bool fmmu_byte_aligned(const EscFmmu& f, std::uint32_t logical, std::uint8_t* frame, std::uint32_t count,
                         bool write) noexcept;
  bool fmmu_bitwise(const EscFmmu& f, std::uint32_t logical, std::uint8_t* frame, std::uint32_t count,
                    bool write) noexcept;

  // Registers derived from state.
  void apply_configuration_area() noexcept;
  void refresh_dl_status() noexcept;
  void apply_dl_control() noexcept;
  void set_al_status(AlState state, bool error, std::uint16_t code) noexcept;
  void raise_event(std::uint16_t bit) noexcept;

  // Slave firmware (esc_al.cpp, esc_pdi.cpp).
  void handle_al_control(hal::Nanoseconds now) noexcept;
  std::uint16_t check_mailbox_sync_managers() const noexcept;
  std::uint16_t check_process_data_sync_managers() const noexcept;
  void enter_state(AlState from, AlState to) noexcept;
  void refuse(AlState stay_in, std::uint16_t code) noexcept;
  void complete_safe_op_to_op() noexcept;
  void handle_sync_manager_events(hal::Nanoseconds now) noexcept;
  // What the firmware's main loop does whenever it runs: AL control, mailbox in and out.
  void serve_application(hal::Nanoseconds now) noexcept;
  void deliver_queued_mailbox() noexcept;
  bool publish_mailbox(ConstByteSpan message) noexcept;
  void run_cycle(CycleTrigger trigger, hal::Nanoseconds when, std::uint64_t system_time) noexcept;
  void check_watchdogs(hal::Nanoseconds now) noexcept;
  hal::Nanoseconds watchdog_unit_ns() const noexcept;
  bool has_mailbox() const noexcept;
  bool dc_synchronous() const noexcept;
  EscSyncManager* sync_manager(unsigned index) noexcept {
    return index < config_.sync_manager_count ? &sync_managers_[index] : nullptr;
  }
  const EscSyncManager* sync_manager(unsigned index) const noexcept {
    return index < config_.sync_manager_count ? &sync_managers_[index] : nullptr;
  }

  EscConfig config_{};
  SlaveDevice* device_{nullptr};
  bool powered_{false};
  bool foreign_identity_{false};
  bool frozen_{false};
  hal::Nanoseconds frozen_since_{0};
  AlState refused_state_{AlState::init};
  std::uint16_t refused_code_{0};
  bool device_emulation_{false};
  hal::Nanoseconds now_{0};

  std::array<EscSyncManager, kMaxSyncManagers> sync_managers_{};
  std::array<EscFmmu, kMaxFmmus> fmmus_{};
  bool fmmus_dirty_{true};
  // Logical bits [first, end) the active FMMUs map, per direction (0: read, 1: write).
  std::array<std::uint64_t, 2> fmmu_first_bit_{};
  std::array<std::uint64_t, 2> fmmu_end_bit_{};

  // Ports.
  std::array<bool, kMaxEscPorts> link_{};
  std::array<bool, kMaxEscPorts> auto_close_latched_{};
  std::array<hal::Nanoseconds, kMaxEscPorts> arrival_{};
  std::array<bool, kMaxEscPorts> arrived_{};
  bool latch_requested_{false};
  bool dl_control_pending_{false};
  // DL control as it acts on forwarding and addressing: a write takes effect after its frame.
  std::uint32_t dl_control_{0};

  // Application layer.
  AlState state_{AlState::init};
  bool al_error_{false};
  bool al_control_unread_{false};
  bool op_pending_{false};
  hal::Nanoseconds op_pending_since_{0};
  bool outputs_received_{false};
  bool sii_pending_start_{false};

  // Mailbox out queue (messages waiting for SM1, in queue_ below) and the last one sent (for
  // repeat requests, in last_sent_).
  std::array<std::uint16_t, kMailboxQueueDepth> queue_length_{};
  std::size_t queue_head_{0};
  std::size_t queue_count_{0};
  std::uint16_t last_sent_length_{0};
  bool repeat_check_{false};

  // Watchdogs.
  bool pd_watchdog_running_{false};
  hal::Nanoseconds pd_watchdog_trigger_{0};
  bool pd_watchdog_expired_{false};
  bool pdi_watchdog_expired_{false};

  OutputLatch last_latch_{};
  std::uint64_t latch_count_{0};
  EscCounters counters_{};

  // The bulk storage last: the state above, which every frame touches, then fits in a few
  // adjacent cache lines instead of being spread between kilobytes of arrays (23 ESCs of 30 KiB
  // each do not fit in a first-level cache; docs/simulator.md, Speed).
  EscDc dc_{};
  EscSii sii_{};
  EscMemory memory_{};
  std::array<std::array<std::uint8_t, kMaxMailboxBytes>, kMailboxQueueDepth> queue_{};
  std::array<std::uint8_t, kMaxMailboxBytes> last_sent_{};
};

}  // namespace rescue::drivers
