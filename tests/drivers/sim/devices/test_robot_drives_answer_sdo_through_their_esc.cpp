// The robot's own devices (drivers/sim/devices/robot_devices.hpp) in the simulated segment, reached the way a
// master reaches them: mailbox SyncManagers configured as the SII announces, PRE-OP, an SDO upload
// written into SM0 and its answer read from SM1 through the ESC; a PDO assignment the drive
// cannot run makes the ESC refuse SAFE-OP with the drive's AL status code.
#include <gtest/gtest.h>

#include <memory>

#include "core/base/endian.hpp"
#include "drivers/joint/device_identity.hpp"
#include "drivers/sim/devices/robot_devices.hpp"
#include "drivers/sim/segment/robot_segment.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"
#include "ecat/mailbox/coe.hpp"
#include "ecat/codec/frame.hpp"
#include "ecat/codec/registers.hpp"
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers {
namespace {

namespace coe = ecat::coe;
namespace reg = ecat::reg;
using ecat::Command;
using testing::Rig;

struct RobotRig {
  RobotRig() {
    std::array<SegmentSlave, kSlaveCount> slaves{};
    EXPECT_TRUE(describe_robot_segment(Span<SlaveDevice* const>(robot->devices()), RobotSegmentOptions{},
                                       Span<SegmentSlave>(slaves))
                    .ok());
    EXPECT_TRUE(rig.segment.build(Span<const SegmentSlave>(slaves), 0).ok());
    rig.assign_station_addresses();
  }
  std::vector<std::uint8_t> sm(std::uint16_t start, std::uint16_t length, std::uint8_t control) {
    return {static_cast<std::uint8_t>(start), static_cast<std::uint8_t>(start >> 8), static_cast<std::uint8_t>(length),
            static_cast<std::uint8_t>(length >> 8), control, 0, 1, 0};
  }
  void configure_mailbox(std::uint16_t station) {
    EXPECT_EQ(rig.write(Command::FPWR, station, reg::sync_manager(0), sm(kJointMailboxOutStart, kJointMailboxSize, 0x26)).wkc, 1);
    EXPECT_EQ(rig.write(Command::FPWR, station, reg::sync_manager(1), sm(kJointMailboxInStart, kJointMailboxSize, 0x22)).wkc, 1);
  }
  void request_state(std::uint16_t station, reg::AlState state) {
    EXPECT_EQ(rig.write16(station, reg::kAlControl, static_cast<std::uint16_t>(state)), 1);
    rig.wait(hal::kNsPerMs);
  }
  // One SDO exchange through SM0/SM1, as a master polls for the answer.
  coe::Message sdo(std::uint16_t station, const coe::Sdo& request, std::uint8_t counter) {
    std::vector<std::uint8_t> sm0(kJointMailboxSize, 0);
    ecat::mbx::Header h;
    h.counter = counter;
    EXPECT_TRUE(coe::encode(ByteSpan(sm0.data(), sm0.size()), h, request).ok());
    EXPECT_EQ(rig.write(Command::FPWR, station, kJointMailboxOutStart, sm0).wkc, 1);
    for (int poll = 0; poll < 100; ++poll) {
      rig.wait(100 * hal::kNsPerUs);
      const auto status = rig.read(Command::FPRD, station, static_cast<std::uint16_t>(reg::sync_manager(1) + reg::kSmStatus), 1);
      if (!status.data.empty() && (status.data[0] & reg::kSmStatusMailboxFull) != 0) break;
    }
    const auto answer = rig.read(Command::FPRD, station, kJointMailboxInStart, kJointMailboxSize);
    EXPECT_EQ(answer.wkc, 1);
    answer_bytes = answer.data;
    auto m = coe::decode(ConstByteSpan(answer_bytes.data(), answer_bytes.size()));
    EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().what);
    return m.ok() ? m.value() : coe::Message{};
  }

  std::unique_ptr<RobotDevices> robot = std::make_unique<RobotDevices>();
  Rig rig;
  std::vector<std::uint8_t> answer_bytes;
};

TEST(RobotDrivesThroughTheirEsc, SdoUploadOfIdentityAndStatusword) {
  RobotRig r;
  const std::size_t position = slave_position_of_joint(joint_index_by_name("l_wrist_pitch"));
  const auto station = static_cast<std::uint16_t>(kStationAddressBase + position);
  r.configure_mailbox(station);
  r.request_state(station, reg::AlState::pre_op);
  ASSERT_EQ(r.rig.read16(station, reg::kAlStatus) & reg::kAlStateMask, static_cast<std::uint16_t>(reg::AlState::pre_op));

  coe::Message m = r.sdo(station, coe::upload_request(0x1018, 4), 1);
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::upload_initiate_response);
  ASSERT_EQ(m.sdo.data.size(), 4u);
  EXPECT_EQ(load_le32(m.sdo.data.data()), serial_number_of(position));

  m = r.sdo(station, coe::upload_request(0x6041, 0), 2);
  ASSERT_EQ(m.sdo.data.size(), 2u);
  EXPECT_EQ(load_le16(m.sdo.data.data()), 0x0250);  // switch on disabled
  m = r.sdo(station, coe::upload_request(0x2000, 0), 3);
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::abort);
  EXPECT_EQ(m.sdo.abort_code, coe::abort_code::kObjectDoesNotExist);
}

TEST(RobotDrivesThroughTheirEsc, EmptyPdoAssignmentMakesSafeOpRefused) {
  RobotRig r;
  const std::size_t position = slave_position_of_joint(joint_index_by_name("neck_pan"));
  const auto station = static_cast<std::uint16_t>(kStationAddressBase + position);
  r.configure_mailbox(station);
  r.request_state(station, reg::AlState::pre_op);
  const std::array<std::uint8_t, 1> zero{0};
  const coe::Message m = r.sdo(station, coe::download_request(0x1C12, 0, ConstByteSpan(zero)), 1);
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::download_initiate_response);

  EXPECT_EQ(r.rig.write(Command::FPWR, station, reg::sync_manager(2), r.sm(kJointOutputsStart, kJointOutputBytes, 0x64)).wkc, 1);
  EXPECT_EQ(r.rig.write(Command::FPWR, station, reg::sync_manager(3), r.sm(kJointInputsStart, kJointInputBytes, 0x20)).wkc, 1);
  r.request_state(station, reg::AlState::safe_op);
  const std::uint16_t status = r.rig.read16(station, reg::kAlStatus);
  EXPECT_NE(status & reg::kAlErrorBit, 0);
  EXPECT_EQ(status & reg::kAlStateMask, static_cast<std::uint16_t>(reg::AlState::pre_op));
  EXPECT_EQ(r.rig.read16(station, reg::kAlStatusCode), reg::al_code::kInvalidOutputMapping);
}

}  // namespace
}  // namespace rescue::drivers
