// Issue 36 item 3, `ctl xml SLAVE` against a running robot (docs/operator.md "ESI from the SII"): the
// description ctl builds from the SII the master read is well-formed XML (Python's parser reads it)
// and names the joint drive's vendor, product and revision, its sync managers and its PDO entries;
// a junction is described too, by name or by its position alike; --json carries the same XML as one
// string; a position past the last slave and a missing SLAVE are usage errors (exit 2).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "drivers/joint/device_identity.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::json_field;
using testing::OperatorRun;

// True when python3's XML parser reads `xml` whole.
bool well_formed(const std::string& dir, const std::string& xml) {
  const std::string path = dir + "/slave.xml";
  std::ofstream(path) << xml;
  const std::string line = "python3 -c 'import sys, xml.dom.minidom; xml.dom.minidom.parse(sys.argv[1])' '" + path + "' 2>&1";
  return std::system(line.c_str()) == 0;
}

TEST(OperatorCtlXml, EachSlavesSiiBecomesAWellFormedDescription) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const CommandResult elbow = run.ctl({"xml", "l_elbow"});
  ASSERT_EQ(elbow.status, 0) << elbow.out;
  EXPECT_TRUE(well_formed(run.dir.path, elbow.out)) << elbow.out;
  char vendor[32];
  (void)std::snprintf(vendor, sizeof vendor, "<Id>#x%08x</Id>", drivers::kJointDriveIdentity.vendor_id);
  EXPECT_NE(elbow.out.find(vendor), std::string::npos) << elbow.out;
  char type[96];
  (void)std::snprintf(type, sizeof type, "<Type ProductCode=\"#x%08x\" RevisionNo=\"#x%08x\">%s</Type>",
                      drivers::kJointDriveIdentity.product_code, drivers::kJointDriveIdentity.revision,
                      drivers::kJointDriveIdentity.name);
  EXPECT_NE(elbow.out.find(type), std::string::npos) << elbow.out;
  EXPECT_NE(elbow.out.find(">Outputs</Sm>"), std::string::npos) << elbow.out;
  EXPECT_NE(elbow.out.find("<RxPdo Sm=\"2\">"), std::string::npos) << elbow.out;
  EXPECT_NE(elbow.out.find("<TxPdo Sm=\"3\">"), std::string::npos) << elbow.out;
  EXPECT_NE(elbow.out.find("<Index>#x6040</Index>"), std::string::npos) << elbow.out;
  EXPECT_NE(elbow.out.find("<Index>#x6064</Index>"), std::string::npos) << "the position actual value\n" << elbow.out;
  // The PDO names the master skipped reading are left empty, and the description says so.
  const CommandResult sii = run.ctl({"--json", "sii_read", "l_elbow"});
  ASSERT_EQ(sii.status, 0) << sii.out;
  EXPECT_EQ(json_field(sii.out, "strings_skipped") == "true", elbow.out.find("did not read the PDO") != std::string::npos)
      << elbow.out;

  const CommandResult junction = run.ctl({"xml", "junction_a"});
  ASSERT_EQ(junction.status, 0) << junction.out;
  EXPECT_TRUE(well_formed(run.dir.path, junction.out)) << junction.out;
  EXPECT_NE(junction.out.find(drivers::kJunctionIdentity.name), std::string::npos) << junction.out;
  EXPECT_EQ(junction.out.find("<RxPdo"), std::string::npos) << "a junction has no process data\n" << junction.out;
  const CommandResult by_position = run.ctl({"xml", "0"});
  EXPECT_EQ(by_position.status, 0);
  EXPECT_EQ(by_position.out, junction.out) << "position 0 is junction_a";

  const CommandResult json = testing::run_program(
      {"ctl", "--key", run.key, "--port", std::to_string(run.control_port), "--json", "xml", "l_elbow"}, false);
  ASSERT_EQ(json.status, 0) << json.out;
  EXPECT_EQ(json_field(json.out, "slave"), "l_elbow");
  EXPECT_NE(json.out.find(R"("xml":"<?xml version=\"1.0\" encoding=\"UTF-8\"?>)"), std::string::npos) << json.out;

  EXPECT_EQ(run.ctl({"xml", "23"}).status, 2);
  EXPECT_EQ(run.ctl({"xml"}).status, 2);
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
