// Fault injection: a hung application (the ESC still forwards and answers, the application part
// stops), a dead slave (its links drop on both sides; powered again it starts over in INIT), a frame
// dropped or corrupted on its way back, a drive fault handed to the device, a malformed frame.
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

class Faults : public ::testing::Test {
 protected:
  void SetUp() override {
    rig = Rig::robot();
    rig->assign_station_addresses();
  }
  std::unique_ptr<Rig> rig;
};

TEST_F(Faults, FrozenApplicationStillForwardsAndAnswersRegisters) {
  const std::size_t position = slave_position_of_joint(joint_index_by_name("r_elbow"));
  const std::uint16_t station = kSlaves[position].station_address;
  ASSERT_TRUE(rig->segment.freeze(position, true).ok());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount);  // everyone behind it still answers
  EXPECT_EQ(rig->read(Command::FPRD, station, reg::kAlStatus, 2).wkc, 1);
  configure_mailbox(*rig, station);
  EXPECT_EQ(request_state(*rig, station, AlState::pre_op), 0x0001);  // nobody serves AL control
  EXPECT_TRUE(rig->segment.esc(position).application_frozen());
  ASSERT_TRUE(rig->segment.freeze(position, false).ok());
  EXPECT_EQ(rig->read16(station, reg::kAlStatus), 0x0002);
}

TEST_F(Faults, DeadSlaveDropsOffWithEverythingBehindItAndRestartsInInit) {
  const std::size_t position = slave_position_of_joint(joint_index_by_name("l_leg"));
  const std::uint16_t station = kSlaves[position].station_address;
  configure_mailbox(*rig, station);
  ASSERT_EQ(request_state(*rig, station, AlState::pre_op), 0x0002);
  ASSERT_TRUE(rig->segment.set_power(position, false, rig->now).ok());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount - 4);  // l_leg, r_leg, l_track, r_track
  const std::uint16_t dl = rig->read16(kSlaves[kSlaves[position].upstream].station_address, reg::kDlStatus);
  EXPECT_EQ(dl & reg::dl_status_link(kSlaves[position].upstream_port), 0);
  ASSERT_TRUE(rig->segment.set_power(position, true, rig->now).ok());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount);
  // A fresh ESC: no station address, INIT.
  EXPECT_EQ(rig->read(Command::FPRD, station, reg::kType, 1).wkc, 0);
  EXPECT_EQ(rig->read16(kSlaves[position + 1].station_address, reg::kAlStatus), 0x0001);  // r_leg never left INIT
  const auto first = rig->read(Command::APRD, ecat::position_adp(static_cast<std::uint16_t>(position)), reg::kAlStatus, 2);
  EXPECT_EQ(first.data, le16(0x0001));
  EXPECT_EQ(rig->read(Command::APRD, ecat::position_adp(static_cast<std::uint16_t>(position)), reg::kStationAddress, 2).data, le16(0));
}

TEST_F(Faults, DroppedFramesNeverComeBackButTheSlavesSawThem) {
  rig->segment.drop_frames(2);
  EXPECT_FALSE(rig->write(Command::FPWR, 0x1004, 0x0F80, {0x31}).returned);
  EXPECT_FALSE(rig->read(Command::BRD, 0, reg::kType, 1).returned);
  EXPECT_TRUE(rig->read(Command::BRD, 0, reg::kType, 1).returned);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1004, 0x0F80, 1).data[0], 0x31);  // the lost frame's write happened
  EXPECT_EQ(rig->segment.counters().dropped_by_fault, 2u);
}

TEST_F(Faults, CorruptedFrameDiffersInExactlyOneBit) {
  const auto clean = rig->read(Command::BRD, 0, reg::kAlStatus, 2);
  rig->segment.corrupt_frames(1);
  // The same request again, compared bit by bit through the raw frame.
  ecat::FrameBuilder builder;
  builder.reset(ecat::MacAddress{0, 0, 0, 0, 0, 1});
  ASSERT_TRUE(builder.add(Command::BRD, 0, ecat::make_address(0, reg::kAlStatus), 2).ok());
  const ConstByteSpan built = builder.finish();
  std::array<std::uint8_t, ecat::kMaxFrameSize> corrupted{};
  std::array<std::uint8_t, ecat::kMaxFrameSize> reference{};
  std::memcpy(corrupted.data(), built.data(), built.size());
  std::memcpy(reference.data(), built.data(), built.size());
  ASSERT_TRUE(rig->segment.process(ByteSpan(corrupted.data(), built.size()), rig->now).ok());
  ASSERT_TRUE(rig->segment.process(ByteSpan(reference.data(), built.size()), rig->now + hal::kNsPerMs).ok());
  int flipped = 0;
  for (std::size_t i = 0; i < built.size(); ++i) flipped += __builtin_popcount(corrupted[i] ^ reference[i]);
  EXPECT_EQ(flipped, 1);
  EXPECT_EQ(rig->segment.counters().corrupted_by_fault, 1u);
  EXPECT_TRUE(clean.returned);
}

TEST_F(Faults, DriveFaultIsHandedToTheDevice) {
  const std::size_t position = slave_position_of_joint(3);
  ASSERT_TRUE(rig->segment.inject_device_fault(position, 0x7305).ok());
  EXPECT_EQ(rig->device_at(position).fault, 0x7305);
  EXPECT_FALSE(rig->segment.inject_device_fault(kSlaveCount, 1).ok());
}

TEST_F(Faults, MalformedFrameIsLostAndCountedAsAnInvalidFrame) {
  ecat::FrameBuilder builder;
  builder.reset(ecat::MacAddress{0, 0, 0, 0, 0, 1});
  ASSERT_TRUE(builder.add(Command::BRD, 0, ecat::make_address(0, reg::kType), 2).ok());
  const ConstByteSpan built = builder.finish();
  std::array<std::uint8_t, ecat::kMaxFrameSize> frame{};
  std::memcpy(frame.data(), built.data(), built.size());
  frame[ecat::kEthernetHeaderSize + 2 + 6] = 0xFF;  // datagram length far beyond the frame
  frame[ecat::kEthernetHeaderSize + 2 + 7] = 0x07;
  const auto outcome = rig->segment.process(ByteSpan(frame.data(), built.size()), rig->now);
  ASSERT_TRUE(outcome.ok());
  EXPECT_FALSE(outcome.value().returned);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1000, reg::kRxErrorCounter, 1).data[0], 1);
}

TEST_F(Faults, NonEthercatFramesAreDestroyedByDefault) {
  std::array<std::uint8_t, 60> frame{};
  frame[12] = 0x08;  // IPv4
  const auto outcome = rig->segment.process(ByteSpan(frame.data(), frame.size()), rig->now);
  ASSERT_TRUE(outcome.ok());
  EXPECT_FALSE(outcome.value().returned);
  EXPECT_EQ(rig->segment.counters().lost_not_ethercat, 1u);
  // DL control bit 0 cleared on the first slave: forwarded untouched.
  EXPECT_EQ(rig->write(Command::FPWR, 0x1000, reg::kDlControl, le32(0x00070000)).wkc, 1);
  const auto forwarded = rig->segment.process(ByteSpan(frame.data(), frame.size()), rig->now + hal::kNsPerMs);
  ASSERT_TRUE(forwarded.ok());
  EXPECT_TRUE(forwarded.value().returned);
}

}  // namespace
}  // namespace rescue::drivers::testing
