// A joint drive as a slave device behind a simulated ESC (drivers/sim/devices/slave_device.hpp): its SII
// image, its CoE mailbox (SDO server over its object dictionary), its process data (13 output and
// 15 input bytes, drivers/joint/joint_drive_pdo.hpp) and the CiA 402 drive with its motor and worm gear.
//
//   PRE-OP -> SAFE-OP  refused with AL status 0x0025 / 0x0024 when the RxPDO / TxPDO assignment
//                      or mapping is not the fixed layout (e.g. left at 0 entries by a master), and
//                      with 0x0035 when SYNC0 is active with a cycle shorter than 100 us
//   SAFE-OP            inputs are produced, outputs ignored (the drive sees "disable voltage")
//   OP                 outputs drive the CiA 402 state machine and the motor
//   leaving OP         the power stage switches off: the worm gear holds the joint
//   mailbox            requests answered in order; a request repeating the previous mailbox
//                      counter is a retry: the previous response is sent again, nothing re-runs
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "drivers/sim/coe/coe_sdo_server.hpp"
#include "drivers/sim/devices/cia402_drive.hpp"
#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "drivers/sim/devices/joint_drive_sii.hpp"
#include "drivers/sim/devices/slave_device.hpp"

namespace rescue::drivers {

constexpr std::uint32_t kMinSync0CycleNs = 100'000;

class JointDriveDevice final : public SlaveDevice {
 public:
  // The drive built into slot `position` of kSlaves (a joint drive slot).
  explicit JointDriveDevice(std::size_t position) noexcept;

  ConstByteSpan sii_image() const noexcept override { return {sii_.data(), sii_.size()}; }
  ProcessDataLayout process_data_layout() const noexcept override;
  std::uint16_t on_state_change(AlState from, AlState to, EscPdi& esc) noexcept override;
  void on_mailbox(ConstByteSpan message, EscPdi& esc) noexcept override;
  void on_cycle(ConstByteSpan outputs, ByteSpan inputs, const CycleContext& ctx, EscPdi& esc) noexcept override;
  void step(hal::Nanoseconds now, EscPdi& esc) noexcept override;
  void inject_fault(std::uint16_t error_code) noexcept override;
  Status corrupt_pdo_mapping(PdoMappingFault fault) noexcept override;

  // For tests and fault injection from a running simulator. The dictionary mirrors the drive's
  // inputs as of the last time the device ran (see mirror_inputs()); use drive() for one call at
  // a time, so a change made through it shows in the dictionary only when the device next runs.
  Cia402Drive& drive() noexcept {
    mirror_inputs();
    return drive_;
  }
  const Cia402Drive& drive() const noexcept { return drive_; }
  JointDriveObjects& objects() noexcept {
    mirror_inputs();
    settings_stale_ = true;  // the caller may change them through the dictionary
    return objects_;
  }
  std::size_t joint() const noexcept { return joint_; }
  std::uint32_t mailbox_repeats() const noexcept { return mailbox_repeats_; }

 private:
  void lose_outputs(hal::Nanoseconds now) noexcept;
  // The drive's inputs into the dictionary (0x6041, 0x6064, ...), if time passed since they were
  // last put there. step() runs several times a cycle and only marks them stale: computing the
  // inputs (encoder rounding) each time cost more than anything else in the drive. Whoever reads
  // the dictionary or changes the drive from outside mirrors them first, so what it sees is what
  // an eager copy after every step would have left there.
  void mirror_inputs() noexcept;
  // The dictionary's drive settings (0x607D, 0x607F, 0x6072, 0x6065, 0x6066), read again only
  // after something may have written them (an SDO download, a caller of objects()): every
  // step needs them, and reading the dictionary each time costs cache misses.
  const DriveSettings& settings() noexcept;

  std::size_t joint_;
  JointDriveObjects objects_;
  Cia402Drive drive_;
  DriveSettings settings_{};
  bool settings_stale_{true};
  hal::Nanoseconds now_{0};
  bool started_{false};
  bool od_inputs_stale_{false};
  std::size_t last_response_length_{0};
  std::uint8_t last_request_counter_{0};
  std::uint8_t response_counter_{0};
  std::uint32_t mailbox_repeats_{0};
  // Last: read at start-up and on mailbox traffic only.
  SiiImage sii_{};
  std::array<std::uint8_t, kJointMailboxSize> last_response_{};
  SdoSegmentState segments_{};  // a segmented SDO transfer in progress
};

}  // namespace rescue::drivers
