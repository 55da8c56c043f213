// The joint drive's object dictionary: table shape, defaults taken from the robot tables, and the
// PDO mapping/assignment rules: a master may rewrite the mapping the way masters do (sub 0 to 0,
// entries, sub 0 back) but only with the fixed layout of drivers/joint/joint_drive_pdo.hpp.
#include <gtest/gtest.h>

#include "core/base/endian.hpp"
#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "ecat/mailbox/coe.hpp"
#include "drivers/joint/joint_units.hpp"

namespace rescue::drivers {
namespace {

using ecat::reg::AlState;
namespace abort_code = ecat::coe::abort_code;

std::uint32_t put(ObjectDictionary& od, std::uint16_t index, std::uint8_t sub, std::uint32_t value, std::size_t size,
                  AlState state = AlState::pre_op) {
  std::uint8_t b[4];
  store_le32(b, value);
  return od.write(index, sub, ConstByteSpan(b, size), state);
}

TEST(JointDriveObjects, TableIsSortedAndEveryEntryHasStorage) {
  const auto table = joint_drive_object_table();
  EXPECT_EQ(table.size(), kJointDriveObjectCount);
  std::size_t end = 0;
  for (const ObjectEntry& e : table) {
    EXPECT_GE(e.offset, end) << std::hex << e.index;
    end = e.offset + e.size;
  }
  EXPECT_LE(end, kJointDriveObjectBytes);
}

TEST(JointDriveObjects, DefaultsComeFromTheRobotTables) {
  const std::size_t joint = joint_index_by_name("neck_tilt");
  JointDriveObjects objects(joint, slave_position_of_joint(joint));
  const DriveSettings s = objects.settings();
  EXPECT_EQ(s.position_min_counts, drivers::rad_to_counts(-0.8));
  EXPECT_EQ(s.position_max_counts, drivers::rad_to_counts(1.0));
  EXPECT_EQ(s.max_velocity_counts_s, static_cast<std::uint32_t>(drivers::rad_to_counts(2.0)));
  EXPECT_EQ(s.max_torque_per_mille, 1000);
  EXPECT_EQ(objects.od().get_u32(0x6076, 0), 10000u);  // 10 N m rated, in mN m
  EXPECT_EQ(objects.od().get_i32(0x6060, 0), 8);
  EXPECT_EQ(objects.od().get_u32(0x6502, 0), kSupportedModesCsxBits);
  EXPECT_TRUE(objects.mapping_is_complete());

  const std::size_t track = joint_index_by_name("l_track");
  JointDriveObjects t(track, slave_position_of_joint(track));
  EXPECT_EQ(t.od().get_i32(0x6060, 0), 9);  // CSV
  EXPECT_EQ(t.settings().position_min_counts, INT32_MIN);  // continuous: no software limits
}

TEST(JointDriveObjects, MasterStyleRewriteOfTheMappingIsAccepted) {
  JointDriveObjects objects(0, slave_position_of_joint(0));
  ObjectDictionary& od = objects.od();
  EXPECT_EQ(put(od, 0x1C12, 0, 0, 1), 0u);
  EXPECT_EQ(put(od, 0x1600, 0, 0, 1), 0u);
  for (std::uint8_t i = 0; i < kJointRxMapping.size(); ++i) {
    EXPECT_EQ(put(od, 0x1600, static_cast<std::uint8_t>(i + 1), kJointRxMapping[i].mapping_word(), 4), 0u) << int(i);
  }
  EXPECT_FALSE(objects.mapping_is_complete());
  EXPECT_EQ(put(od, 0x1600, 0, kJointRxMapping.size(), 1), 0u);
  EXPECT_EQ(put(od, 0x1C12, 1, 0x1600, 2), 0u);
  EXPECT_EQ(put(od, 0x1C12, 0, 1, 1), 0u);
  EXPECT_TRUE(objects.mapping_is_complete());
}

TEST(JointDriveObjects, OtherMappingsAreRefusedWithTheirAbortCodes) {
  JointDriveObjects objects(0, slave_position_of_joint(0));
  ObjectDictionary& od = objects.od();
  EXPECT_EQ(put(od, 0x1600, 1, kJointRxMapping[0].mapping_word(), 4), abort_code::kSubindex0MustBeZero);
  EXPECT_EQ(put(od, 0x1600, 0, 0, 1), 0u);
  EXPECT_EQ(put(od, 0x1600, 1, 0x60FE0120, 4), abort_code::kCannotBeMapped);          // digital outputs
  EXPECT_EQ(put(od, 0x1600, 2, kJointRxMapping[0].mapping_word(), 4), abort_code::kCannotBeMapped);  // reordered
  EXPECT_EQ(put(od, 0x1600, 0, 9, 1), abort_code::kPdoLengthExceeded);
  EXPECT_EQ(put(od, 0x1600, 0, 3, 1), abort_code::kParameterIncompatible);  // a shorter image than the fixed one
  EXPECT_EQ(put(od, 0x1C13, 0, 2, 1), abort_code::kValueTooHigh);
  EXPECT_EQ(put(od, 0x1C13, 0, 0, 1), 0u);
  EXPECT_EQ(put(od, 0x1C13, 1, 0x1A01, 2), abort_code::kValueRange);
  EXPECT_EQ(put(od, 0x6600, 0, 0, 1), abort_code::kObjectDoesNotExist);
}

TEST(JointDriveObjects, SoftwareLimitsKeepMinBelowMax) {
  const std::size_t joint = joint_index_by_name("l_elbow");
  JointDriveObjects objects(joint, slave_position_of_joint(joint));
  ObjectDictionary& od = objects.od();
  const auto max = static_cast<std::uint32_t>(od.get_i32(0x607D, 2));
  EXPECT_EQ(put(od, 0x607D, 1, max + 1, 4, AlState::op), abort_code::kMaxBelowMin);
  EXPECT_EQ(put(od, 0x607D, 2, static_cast<std::uint32_t>(drivers::rad_to_counts(1.0)), 4, AlState::op), 0u);
  EXPECT_EQ(objects.settings().position_max_counts, drivers::rad_to_counts(1.0));
  EXPECT_EQ(put(od, 0x607F, 0, od.get_u32(0x6080, 0) + 1, 4), abort_code::kValueTooHigh);
}

TEST(JointDriveObjects, ProcessDataIsMirroredForSdoReads) {
  JointDriveObjects objects(3, slave_position_of_joint(3));
  JointInputs in;
  in.statusword = 0x0237;
  in.position_actual = -42;
  in.error_code = 0x8611;
  objects.store_inputs(in);
  EXPECT_EQ(objects.od().get_u32(0x6041, 0), 0x0237u);
  EXPECT_EQ(objects.od().get_i32(0x6064, 0), -42);
  EXPECT_EQ(objects.od().get_u32(0x603F, 0), 0x8611u);
  EXPECT_EQ(objects.od().get_u32(0x1001, 0), 1u);
  JointOutputs out;
  out.controlword = 0x000F;
  out.target_velocity = -7;
  out.mode_of_operation = 9;
  objects.store_outputs(out);
  EXPECT_EQ(objects.outputs(), out);
}

}  // namespace
}  // namespace rescue::drivers
