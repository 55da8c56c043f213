// The boundary between a simulated EtherCAT slave controller (ESC, drivers/sim/esc/esc.hpp) and the device
// application behind it: what a real slave's microcontroller sees through the ESC's PDI (process data
// interface). The ESC model owns everything on the EtherCAT side (registers, SyncManagers, FMMUs,
// SII interface, distributed clocks) plus the generic part of the slave firmware (the AL state
// machine with its SyncManager checks, the mailbox and process-data buffer handling, as the
// EtherCAT slave stack code does on real devices). A SlaveDevice supplies the device-specific part:
//
//   SII image          the EEPROM content (identity, mailbox, categories); read at power-up
//   process data       how many bytes SM2 (outputs) and SM3 (inputs) carry under the current mapping
//   AL state changes   accept or refuse (with an AL status code) a transition the ESC already checked
//   mailbox            receives each message the master wrote into SM0; answers via EscPdi::post_mailbox
//   application cycle  consumes outputs, produces inputs; runs at SYNC0 (DC mode), on the SM2 event
//                      (SM-synchronous mode) or on the SM3 event (inputs only)
//   time               stepped in segment time, monotonically, before every event
//
// Calls come from one thread (the one driving the segment), never re-entrantly, never with the heap.
#pragma once

#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/codec/registers.hpp"
#include "hal/time/clock.hpp"

namespace rescue::drivers {

using AlState = ecat::reg::AlState;

// Where the device's cyclic process data lives and how big it is under the current PDO assignment.
// The ESC checks the master's SyncManager configuration against it on PRE-OP -> SAFE-OP (as slave
// stacks do): a wrong SM length or direction is refused with AL status code 0x001D/0x001E.
struct ProcessDataLayout {
  std::uint8_t output_sm{2};       // SyncManager written by the master (RxPDOs)
  std::uint16_t output_bytes{0};   // 0: the device has no outputs
  std::uint8_t input_sm{3};        // SyncManager read by the master (TxPDOs)
  std::uint16_t input_bytes{0};    // 0: the device has no inputs
};

// What started an application cycle.
enum class CycleTrigger : std::uint8_t {
  sync0,     // DC SYNC0 event (0x0981 cyclic + SYNC0 active): outputs latched at the same instant on all slaves
  sm_event,  // the master completed a write of the outputs SyncManager (SM-synchronous mode)
  inputs_read,  // the master read the inputs SyncManager (devices without outputs, no DC)
};

struct CycleContext {
  hal::Nanoseconds now{0};         // segment (true) time of the event
  std::uint64_t system_time{0};    // the ESC's DC system time at the event (0x0910 semantics)
  AlState state{AlState::init};    // SAFE-OP: outputs are not valid (ignore them); OP: apply them
  CycleTrigger trigger{CycleTrigger::sm_event};
};

// The DC SYNC settings the master wrote (0x0980-0x09A7), for devices that check them on
// PRE-OP -> SAFE-OP (e.g. refusing a cycle time they cannot follow with 0x0035).
struct DcSyncSettings {
  bool cyclic_active{false};       // 0x0981 bit 0
  bool sync0_active{false};        // 0x0981 bit 1
  bool sync1_active{false};        // 0x0981 bit 2
  std::uint64_t start_time{0};     // 0x0990 as written (system time of the first SYNC0)
  std::uint32_t sync0_cycle_ns{0}; // 0x09A0
  std::uint32_t sync1_cycle_ns{0}; // 0x09A4
};

// The ESC as the device application sees it (its PDI side).
class EscPdi {
 public:
  EscPdi() = default;
  EscPdi(const EscPdi&) = delete;
  EscPdi& operator=(const EscPdi&) = delete;
  EscPdi(EscPdi&&) = delete;
  EscPdi& operator=(EscPdi&&) = delete;
  virtual ~EscPdi() = default;

  virtual AlState al_state() const noexcept = 0;

  // Posts one mailbox message (mailbox header included) for the master to read from SM1. Messages
  // are queued while SM1 is full and delivered in order. Fails with capacity_exceeded when the queue
  // is full, invalid_argument when the message is longer than the SM1 buffer (mailbox_out_capacity).
  virtual Status post_mailbox(ConstByteSpan message) noexcept = 0;

  // Length of the SM1 buffer the master configured: the longest message the device may post.
  virtual std::uint16_t mailbox_out_capacity() const noexcept = 0;

  // An application error (what a slave stack does on a local error): the ESC falls back to
  // `fall_back_to` if that is lower than the current state, sets the AL status error indication
  // and the status code. The master must acknowledge it.
  virtual void raise_al_error(AlState fall_back_to, std::uint16_t al_status_code) noexcept = 0;

  virtual DcSyncSettings dc_sync_settings() const noexcept = 0;
};

// How a PDO mapping can be left wrong (SlaveDevice::corrupt_pdo_mapping).
enum class PdoMappingFault : std::uint8_t {
  half_written,     // RxPDO entries written, its entry count (0x1600:00) left at 0: a tool stopped halfway
  foreign_default,  // another default mapping (fewer entries, as a factory-default drive has)
};

// The device application behind one ESC (joint drive, junction, test devices).
class SlaveDevice {
 public:
  SlaveDevice() = default;
  SlaveDevice(const SlaveDevice&) = delete;
  SlaveDevice& operator=(const SlaveDevice&) = delete;
  SlaveDevice(SlaveDevice&&) = delete;
  SlaveDevice& operator=(SlaveDevice&&) = delete;
  virtual ~SlaveDevice() = default;

  // The SII EEPROM image, byte for byte as stored (little-endian words). Must stay valid and
  // unchanged for the device's lifetime; the ESC copies it into its EEPROM at power-up.
  virtual ConstByteSpan sii_image() const noexcept = 0;

  virtual ProcessDataLayout process_data_layout() const noexcept = 0;

  // A state change the master requested and the ESC's own checks allowed (valid transition,
  // mailbox and process-data SyncManagers configured as the device needs). Upward transitions
  // (INIT->PRE-OP, PRE-OP->SAFE-OP, SAFE-OP->OP): return al_code::kNoError to accept or an AL
  // status code to refuse. Downward transitions cannot be refused; the return value is ignored.
  virtual std::uint16_t on_state_change(AlState from, AlState to, EscPdi& esc) noexcept = 0;

  // A complete message the master wrote into the SM0 mailbox: the whole SM0 buffer, starting with
  // the 6-byte mailbox header. Untrusted bytes: the device checks every length.
  virtual void on_mailbox(ConstByteSpan message, EscPdi& esc) noexcept = 0;

  // One application cycle (SAFE-OP and OP only). `outputs` is the latest SM2 buffer (empty if the
  // device has none), `inputs` the SM3 buffer to fill (empty if none); the ESC publishes it to the
  // master when the call returns.
  virtual void on_cycle(ConstByteSpan outputs, ByteSpan inputs, const CycleContext& ctx, EscPdi& esc) noexcept = 0;

  // Time passes. Called with non-decreasing `now` before every other call, and whenever the segment
  // advances, so the device can move its physics (motor, encoder) on.
  virtual void step(hal::Nanoseconds now, EscPdi& esc) noexcept = 0;

  // Fault injection: a device fault with a device-specific error code (a drive raises its CiA 402
  // fault with this error code). Devices without such faults ignore it.
  virtual void inject_fault(std::uint16_t error_code) noexcept = 0;

  // Fault injection: the device's PDO mapping left as another tool left it (kept through power
  // cycles, as a drive keeps its stored mapping). Devices without a configurable mapping refuse it.
  virtual Status corrupt_pdo_mapping(PdoMappingFault fault) noexcept {
    (void)fault;
    return make_error(Errc::unsupported, "device has no configurable PDO mapping");
  }
};

}  // namespace rescue::drivers
