// The bring-up report (ecat/master/bring_up_report.hpp) as `run`, `run --check` and `bench master`
// print it, from a bring-up on the simulated robot: a device's SII name is printed whole however
// long (a real EK1100 calls itself in 34 characters; the SII allows 255), and every number in the
// headline says what it is (a state refusal: the slave's position and its AL status code in hex).
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "ecat/master/bring_up_report.hpp"
#include "tests/support/sii_image_device.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::describe_master_failure;
using testing::SimulatedRobotRig;

// What print_bring_up_failure writes, read back from a temporary file.
std::string printed_report(Master& master) {
  std::FILE* file = std::tmpfile();
  if (file == nullptr) return "(no temporary file)";
  print_bring_up_failure(file, "", "", master);
  std::rewind(file);
  std::string text;
  for (int c = std::fgetc(file); c != EOF; c = std::fgetc(file)) text += static_cast<char>(c);
  (void)std::fclose(file);
  return text;
}

// Issue 35 item 15: the name was cut at 31 characters ("EK1100 EtherCAT-Koppler (2A E-B").
TEST(BringUpReport, NamesAnExtraDeviceWithItsWholeSiiName) {
  const char* const kEk1100 = "EK1100 EtherCAT-Koppler (2A E-Bus)";
  ASSERT_EQ(std::string(kEk1100).size(), 34u);
  drivers::SiiIdentity id;
  id.vendor_id = 0x00000002;
  id.product_code = 0x044C2C52;
  id.revision = 0x00110000;
  id.serial = 7;
  testing::SiiImageDevice coupler(testing::SiiImageDevice::minimal_image(id, kEk1100));
  ASSERT_GT(coupler.sii_image().size(), 0u) << "the name fits the minimal image";
  auto rig = std::make_unique<SimulatedRobotRig>(false);
  const drivers::SegmentSlave extra = testing::extra_slave_behind_the_last(coupler, "coupler");
  rig->build({}, &extra);
  ASSERT_TRUE(rig->built.ok()) << rig->built.error().what;
  ASSERT_FALSE(rig->bus.bring_up(testing::fast_options()).ok());
  Master& m = rig->bus.master();
  ASSERT_EQ(m.report().match.count(DifferenceKind::extra), 1u) << describe_master_failure(m);
  EXPECT_STREQ(m.report().found[kSlaveCount].name.data(), kEk1100);
  const std::string report = printed_report(m);
  EXPECT_NE(report.find("extra: device at position 23 (EK1100 EtherCAT-Koppler (2A E-Bus) 0x00000002:0x044c2c52"),
            std::string::npos)
      << report;
}

// Issue 35 item 15: the headline said "(refused; details 5, 29)": which slave, which code, in what base?
TEST(BringUpReport, LabelsThePositionAndTheAlStatusCodeOfAStateRefusal) {
  auto rig = std::make_unique<SimulatedRobotRig>();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("r_elbow"));
  ASSERT_TRUE(rig->segment.refuse_state(elbow, drivers::AlState::safe_op, 0x001D).ok());
  MasterOptions options = testing::fast_options();
  options.al.retries = 1;
  ASSERT_FALSE(rig->bus.bring_up(options).ok());
  Master& m = rig->bus.master();
  ASSERT_STREQ(m.report().failed_step, "SAFE-OP") << describe_master_failure(m);
  const std::string report = printed_report(m);
  EXPECT_EQ(report.substr(0, report.find('\n') + 1),
            "bring-up failed at SAFE-OP: slave refused state (refused: slave at position " + std::to_string(elbow) +
                ", AL status code 0x001d)\n")
      << report;
  EXPECT_NE(report.find("r_elbow refused SAFE-OP: AL status 0x0012 (PRE-OP, error), code 0x001d invalid output configuration\n"),
            std::string::npos)
      << report;
}

}  // namespace
}  // namespace rescue::ecat
