// The joint drive as the ESC sees it (drivers/sim/devices/slave_device.hpp): SII image, process-data sizes,
// AL state checks (PDO mapping, SYNC0 cycle), mailbox requests answered through EscPdi with
// mailbox counters and retry detection, and cycles in OP that enable the drive and move the joint;
// leaving OP switches the power stage off and the worm gear holds.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "core/base/endian.hpp"
#include "drivers/joint/device_identity.hpp"
#include "drivers/sim/devices/joint_drive_device.hpp"
#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/mailbox.hpp"
#include "ecat/sii/sii.hpp"
#include "drivers/joint/joint_units.hpp"

namespace rescue::drivers {
namespace {

namespace coe = ecat::coe;
namespace al_code = ecat::reg::al_code;

class FakeEsc final : public EscPdi {
 public:
  AlState al_state() const noexcept override { return state; }
  Status post_mailbox(ConstByteSpan message) noexcept override {
    posted.emplace_back(message.begin(), message.end());
    return Status::success();
  }
  std::uint16_t mailbox_out_capacity() const noexcept override { return 128; }
  void raise_al_error(AlState, std::uint16_t code) noexcept override { al_error = code; }
  DcSyncSettings dc_sync_settings() const noexcept override { return dc; }

  AlState state{AlState::pre_op};
  std::vector<std::vector<std::uint8_t>> posted;
  std::uint16_t al_error{0};
  DcSyncSettings dc{};
};

std::vector<std::uint8_t> sdo_request(const coe::Sdo& sdo, std::uint8_t counter) {
  std::vector<std::uint8_t> sm0(kJointMailboxSize, 0);
  ecat::mbx::Header h;
  h.counter = counter;
  EXPECT_TRUE(coe::encode(ByteSpan(sm0.data(), sm0.size()), h, sdo).ok());
  return sm0;
}

TEST(JointDriveDevice, AnnouncesItsSiiAndProcessData) {
  const std::size_t position = slave_position_of_joint(joint_index_by_name("r_hand"));
  JointDriveDevice device(position);
  auto sii = ecat::sii::Sii::parse(device.sii_image());
  ASSERT_TRUE(sii.ok());
  EXPECT_EQ(sii.value().identity.serial_number, serial_number_of(position));
  const ProcessDataLayout layout = device.process_data_layout();
  EXPECT_EQ(layout.output_sm, 2);
  EXPECT_EQ(layout.output_bytes, kJointOutputBytes);
  EXPECT_EQ(layout.input_sm, 3);
  EXPECT_EQ(layout.input_bytes, kJointInputBytes);
  EXPECT_EQ(device.joint(), joint_index_by_name("r_hand"));
}

TEST(JointDriveDevice, AnswersSdoRequestsAndRepeatsTheAnswerToARetry) {
  JointDriveDevice device(slave_position_of_joint(0));
  FakeEsc esc;
  const auto request = sdo_request(coe::upload_request(0x6041, 0), 1);
  device.on_mailbox(ConstByteSpan(request.data(), request.size()), esc);
  ASSERT_EQ(esc.posted.size(), 1u);
  auto m = coe::decode(ConstByteSpan(esc.posted[0].data(), esc.posted[0].size()));
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m.value().mailbox.counter, 1);
  EXPECT_EQ(load_le16(m.value().sdo.data.data()), 0x0250);  // switch on disabled after power-up

  // Same counter again: a retry; the same response, nothing re-executed.
  device.on_mailbox(ConstByteSpan(request.data(), request.size()), esc);
  ASSERT_EQ(esc.posted.size(), 2u);
  EXPECT_EQ(esc.posted[1], esc.posted[0]);
  EXPECT_EQ(device.mailbox_repeats(), 1u);

  const auto next = sdo_request(coe::upload_request(0x1018, 2), 2);
  device.on_mailbox(ConstByteSpan(next.data(), next.size()), esc);
  ASSERT_EQ(esc.posted.size(), 3u);
  m = coe::decode(ConstByteSpan(esc.posted[2].data(), esc.posted[2].size()));
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m.value().mailbox.counter, 2);
  EXPECT_EQ(load_le32(m.value().sdo.data.data()), kJointDriveIdentity.product_code);
}

TEST(JointDriveDevice, RefusesSafeOpWithoutTheFixedMappingOrWithTooFastSync0) {
  JointDriveDevice device(slave_position_of_joint(5));
  FakeEsc esc;
  EXPECT_EQ(device.on_state_change(AlState::pre_op, AlState::safe_op, esc), al_code::kNoError);
  // A master leaves the RxPDO assignment empty.
  const auto clear = sdo_request(coe::download_request(0x1C12, 0, ConstByteSpan(std::array<std::uint8_t, 1>{0})), 1);
  device.on_mailbox(ConstByteSpan(clear.data(), clear.size()), esc);
  EXPECT_EQ(device.on_state_change(AlState::pre_op, AlState::safe_op, esc), al_code::kInvalidOutputMapping);
  const auto restore = sdo_request(coe::download_request(0x1C12, 0, ConstByteSpan(std::array<std::uint8_t, 1>{1})), 2);
  device.on_mailbox(ConstByteSpan(restore.data(), restore.size()), esc);
  EXPECT_EQ(device.on_state_change(AlState::pre_op, AlState::safe_op, esc), al_code::kNoError);
  esc.dc.cyclic_active = true;
  esc.dc.sync0_active = true;
  esc.dc.sync0_cycle_ns = 50'000;
  EXPECT_EQ(device.on_state_change(AlState::pre_op, AlState::safe_op, esc), al_code::kDcInvalidSyncCycleTime);
  esc.dc.sync0_cycle_ns = 1'000'000;
  EXPECT_EQ(device.on_state_change(AlState::pre_op, AlState::safe_op, esc), al_code::kNoError);
}

TEST(JointDriveDevice, CyclesInOpEnableAndMoveTheJointAndLeavingOpHoldsIt) {
  const std::size_t joint = joint_index_by_name("l_shoulder_yaw");
  JointDriveDevice device(slave_position_of_joint(joint));
  FakeEsc esc;
  esc.state = AlState::op;
  JointOutputImage outputs{};
  JointInputImage inputs{};
  hal::Nanoseconds now = 1'000'000'000;  // segment time need not start at 0
  device.step(now, esc);
  auto cycle = [&](const JointOutputs& out) {
    encode_outputs(out, ByteSpan(outputs));
    CycleContext ctx;
    ctx.now = now;
    ctx.state = esc.state;
    ctx.trigger = CycleTrigger::sync0;
    device.on_cycle(ConstByteSpan(outputs), ByteSpan(inputs), ctx, esc);
    now += hal::kNsPerMs;
    device.step(now, esc);
    return decode_inputs(ConstByteSpan(inputs));
  };
  JointOutputs out;
  out.mode_of_operation = static_cast<std::int8_t>(ControlMode::cyclic_position);
  for (std::uint16_t cw : {cia402::cw::kShutdown, cia402::cw::kSwitchOnCommand, cia402::cw::kEnableOperationCommand}) {
    out.controlword = cw;
    (void)cycle(out);
  }
  // Interpolated CSP ramp to 0.5 rad at 1 rad/s, as a master would send it.
  JointInputs in;
  for (int i = 1; i <= 1500; ++i) {
    out.target_position = drivers::rad_to_counts(std::min(0.5, 0.001 * i));
    in = cycle(out);
  }
  EXPECT_EQ(cia402::state_from_statusword(in.statusword), cia402::State::operation_enabled);
  EXPECT_NEAR(drivers::counts_to_rad(in.position_actual), 0.5, 1e-3);
  EXPECT_EQ(in.mode_display, 8);
  EXPECT_EQ(device.objects().od().get_i32(0x6064, 0), in.position_actual);  // SDO sees the same

  const std::int32_t held = in.position_actual;
  (void)device.on_state_change(AlState::op, AlState::safe_op, esc);
  esc.state = AlState::safe_op;
  out.target_position = drivers::rad_to_counts(1.5);  // ignored outside OP
  for (int i = 0; i < 500; ++i) in = cycle(out);
  EXPECT_EQ(cia402::state_from_statusword(in.statusword), cia402::State::switch_on_disabled);
  EXPECT_EQ(in.position_actual, held);
}

TEST(JointDriveDevice, InjectedFaultShowsInTheInputs) {
  JointDriveDevice device(slave_position_of_joint(1));
  FakeEsc esc;
  esc.state = AlState::op;
  device.step(0, esc);
  device.inject_fault(drive_error::kOverTemperature);
  device.step(hal::kNsPerMs, esc);
  JointOutputImage outputs{};
  JointInputImage inputs{};
  CycleContext ctx;
  ctx.state = AlState::op;
  ctx.now = hal::kNsPerMs;
  device.on_cycle(ConstByteSpan(outputs), ByteSpan(inputs), ctx, esc);
  const JointInputs in = decode_inputs(ConstByteSpan(inputs));
  EXPECT_EQ(cia402::state_from_statusword(in.statusword), cia402::State::fault);
  EXPECT_EQ(in.error_code, drive_error::kOverTemperature);
}

}  // namespace
}  // namespace rescue::drivers
