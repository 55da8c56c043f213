// The whole simulated robot (junctions and the 21 joint drives of drivers/sim/devices/joint_drive_device.hpp)
// brought up the way an independent master does it, only through frames: count, address, identity
// from the SII, mailbox SyncManagers from the SII, PDO assignment over CoE left as the drive has it,
// process-data SyncManagers and FMMUs, distributed clocks with SYNC0, SAFE-OP, OP; then a joint
// enabled through CiA 402 follows a target, and a cut link sends the joints behind it to SAFE-OP
// by their watchdog while the others keep running.
#include "drivers/joint/joint_drive_pdo.hpp"
#include "drivers/sim/devices/joint_drive_sii.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"
#include "tests/support/dc_master_steps.hpp"
#include "drivers/joint/joint_units.hpp"

namespace rescue::drivers::testing {
namespace {

constexpr hal::Nanoseconds kCycle = hal::kNsPerMs;
constexpr std::uint32_t kLogical = 0x00010000;
constexpr std::size_t kSlotBytes = kJointOutputBytes + kJointInputBytes;

std::uint32_t slot_of(std::size_t joint) { return kLogical + static_cast<std::uint32_t>(joint * kSlotBytes); }

std::uint32_t sii_read32(Rig& rig, std::uint16_t station, std::uint16_t word) {
  std::vector<std::uint8_t> command = le16(reg::kSiiCommandRead);
  const auto address = le32(word);
  command.insert(command.end(), address.begin(), address.end());
  EXPECT_EQ(rig.write(Command::FPWR, station, reg::kSiiControl, command).wkc, 1);
  while ((rig.read16(station, reg::kSiiControl) & reg::kSiiBusy) != 0) rig.wait(100 * hal::kNsPerUs);
  return static_cast<std::uint32_t>(from_le(rig.read(Command::FPRD, station, reg::kSiiData, 4).data));
}

class Robot : public ::testing::Test {
 protected:
  void SetUp() override {
    robot = std::make_unique<SimulatedRobot>();
    ASSERT_TRUE(robot->status().ok());
    rig = std::make_unique<Rig>(robot->segment());
  }

  // One cycle: every joint's process data in one LRW, then the reference time.
  std::vector<std::uint8_t> cycle(const std::vector<std::uint8_t>& outputs_image) {
    const auto lrw = rig->exchange(Command::LRW, kLogical, outputs_image, 20 * hal::kNsPerUs);
    last_lrw_wkc = lrw.wkc;
    (void)rig->exchange(Command::FRMW, ecat::make_address(kStationAddressBase, reg::kDcSystemTime), std::vector<std::uint8_t>(8, 0),
                        kCycle - 20 * hal::kNsPerUs);
    return lrw.data;
  }

  void bring_up() {
    // Scan and address.
    ASSERT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount);
    prepare_distributed_clocks(*rig, 1'000'000'000'000ULL, false);
    // Identity from the SII (4- and 8-byte ESCs alike, reading 32 bits at a time).
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      const DeviceIdentity& expected = identity_of(kSlaves[p].kind);
      EXPECT_EQ(sii_read32(*rig, kSlaves[p].station_address, ecat::sii::kVendorId), expected.vendor_id) << p;
      EXPECT_EQ(sii_read32(*rig, kSlaves[p].station_address, ecat::sii::kProductCode), expected.product_code) << p;
    }
    // Distributed clocks (offsets and measured delays written above) converge.
    for (int i = 0; i < 3000; ++i) distribute_reference_time(*rig, kCycle);
    // Mailbox SyncManagers from the SII's standard mailbox words, then PRE-OP.
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      const std::uint16_t station = kSlaves[p].station_address;
      const std::uint32_t out = sii_read32(*rig, station, ecat::sii::kStdRxMailboxOffset);
      const std::uint32_t in = sii_read32(*rig, station, ecat::sii::kStdTxMailboxOffset);
      if ((out >> 16) != 0) {
        EXPECT_EQ(rig->write(Command::FPWR, station, reg::sync_manager(0),
                             sm_config(static_cast<std::uint16_t>(out), static_cast<std::uint16_t>(out >> 16), kSmControlMailboxOut, 1)).wkc, 1);
        EXPECT_EQ(rig->write(Command::FPWR, station, reg::sync_manager(1),
                             sm_config(static_cast<std::uint16_t>(in), static_cast<std::uint16_t>(in >> 16), kSmControlMailboxIn, 1)).wkc, 1);
      }
      EXPECT_EQ(request_state(*rig, station, AlState::pre_op) & 0x1F, 0x02) << kSlaves[p].name;
    }
    // Process data and SYNC0 for the joints, SAFE-OP.
    const std::uint64_t now = from_le(rig->read(Command::FPRD, kStationAddressBase, reg::kDcSystemTime, 8).data);
    const std::uint64_t start = (now / kCycle + 100) * kCycle;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const std::uint16_t station = kSlaves[slave_position_of_joint(j)].station_address;
      EXPECT_EQ(rig->write(Command::FPWR, station, reg::sync_manager(2), sm_config(kJointOutputsStart, kJointOutputBytes, kSmControlOutputs, 1)).wkc, 1);
      EXPECT_EQ(rig->write(Command::FPWR, station, reg::sync_manager(3), sm_config(kJointInputsStart, kJointInputBytes, kSmControlInputs, 1)).wkc, 1);
      EXPECT_EQ(rig->write(Command::FPWR, station, reg::fmmu(0), fmmu_config(slot_of(j), kJointOutputBytes, kJointOutputsStart, 2)).wkc, 1);
      EXPECT_EQ(rig->write(Command::FPWR, station, reg::fmmu(1), fmmu_config(slot_of(j) + kJointOutputBytes, kJointInputBytes, kJointInputsStart, 1)).wkc, 1);
      EXPECT_EQ(rig->write(Command::FPWR, station, reg::kDcSync0CycleTime, le32(static_cast<std::uint32_t>(kCycle))).wkc, 1);
      EXPECT_EQ(rig->write(Command::FPWR, station, reg::kDcStartTime, le64(start)).wkc, 1);
      EXPECT_EQ(rig->write(Command::FPWR, station, reg::kDcActivation, {0x03}).wkc, 1);
      EXPECT_EQ(request_state(*rig, station, AlState::safe_op), 0x0004) << kJoints[j].name << " code "
                                                                        << rig->read16(station, reg::kAlStatusCode);
    }
    // Cyclic exchange running, then OP for everyone.
    for (int i = 0; i < 200; ++i) (void)cycle(image);
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const std::uint16_t station = kSlaves[slave_position_of_joint(j)].station_address;
      EXPECT_EQ(request_state(*rig, station, AlState::op), 0x0008) << kJoints[j].name;
    }
    for (int i = 0; i < 10; ++i) (void)cycle(image);
  }

  JointInputs inputs_of(const std::vector<std::uint8_t>& data, std::size_t joint) {
    return decode_inputs(ConstByteSpan(data.data() + joint * kSlotBytes + kJointOutputBytes, kJointInputBytes));
  }
  void set_outputs(std::size_t joint, const JointOutputs& out) {
    encode_outputs(out, ByteSpan(image.data() + joint * kSlotBytes, kJointOutputBytes));
  }

  std::unique_ptr<SimulatedRobot> robot;
  std::unique_ptr<Rig> rig;
  std::vector<std::uint8_t> image = std::vector<std::uint8_t>(kJointCount * kSlotBytes, 0);
  std::uint16_t last_lrw_wkc{0};
};

TEST_F(Robot, AllJointsReachOpWithDistributedClocks) {
  bring_up();
  EXPECT_EQ(last_lrw_wkc, 3 * kJointCount);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const Esc& esc = rig->segment.esc(slave_position_of_joint(j));
    EXPECT_EQ(esc.al_state(), AlState::op) << kJoints[j].name;
    EXPECT_EQ(esc.last_output_latch().trigger, CycleTrigger::sync0) << kJoints[j].name;
  }
}

TEST_F(Robot, AnEnabledJointFollowsItsTarget) {
  bring_up();
  const std::size_t joint = joint_index_by_name("l_elbow");
  auto in = inputs_of(cycle(image), joint);
  const std::int32_t start = in.position_actual;
  // CiA 402: shutdown, switch on, enable operation, in cyclic synchronous position mode.
  for (const std::uint16_t controlword : {0x0006, 0x0007, 0x000F}) {
    set_outputs(joint, JointOutputs{controlword, 8, start, 0, 0});
    for (int i = 0; i < 5; ++i) in = inputs_of(cycle(image), joint);
  }
  EXPECT_EQ(in.statusword & 0x006F, 0x0027) << std::hex << in.statusword;  // operation enabled
  const std::int32_t target = start + drivers::rad_to_counts(0.05);
  for (int i = 0; i < 500; ++i) {
    set_outputs(joint, JointOutputs{0x000F, 8, target, 0, 0});
    in = inputs_of(cycle(image), joint);
  }
  EXPECT_NEAR(in.position_actual, target, drivers::rad_to_counts(0.002));
}

TEST_F(Robot, CutLinkStopsTheJointsBehindItAndTheRestKeepCycling) {
  bring_up();
  const std::size_t cut_at = slave_position_of_joint(joint_index_by_name("r_elbow"));
  ASSERT_TRUE(rig->segment.cut_link(cut_at).ok());
  for (int i = 0; i < 150; ++i) (void)cycle(image);
  const JointMask lost = joints_lost_by_link_failure_at(joint_index_by_name("r_elbow"));
  EXPECT_EQ(last_lrw_wkc, 3 * (kJointCount - static_cast<std::size_t>(__builtin_popcount(lost))));
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const Esc& esc = rig->segment.esc(slave_position_of_joint(j));
    if ((lost & joint_bit(j)) != 0) {
      // Their process-data watchdog ran out: SAFE-OP with 0x001B, drive disabled (the worm gear holds).
      EXPECT_EQ(esc.register_u16(reg::kAlStatus), 0x0014) << kJoints[j].name;
      EXPECT_EQ(esc.register_u16(reg::kAlStatusCode), 0x001B) << kJoints[j].name;
    } else {
      EXPECT_EQ(esc.al_state(), AlState::op) << kJoints[j].name;
    }
  }
}

}  // namespace
}  // namespace rescue::drivers::testing
