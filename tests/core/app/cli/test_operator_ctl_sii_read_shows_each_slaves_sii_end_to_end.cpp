// Issue 36 item 3, `ctl sii_read SLAVE` against a running robot (docs/operator.md "SII"): the bytes of
// a joint drive's SII with --raw are the simulated drive's own EEPROM (drivers/sim/devices/
// joint_drive_sii.hpp) where the master read them (its first 128 bytes, identity included, byte for
// byte; a byte that differs is one of the Strings the master skipped, which read 0, and the answer
// says so); --json carries the same bytes as hex and their size; the text is a hex dump of 16 bytes
// a line; a junction (no mailbox) is read too, by its position; a position past the last slave and
// --raw with --json are usage errors (exit 2), nothing sent.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "drivers/sim/devices/joint_drive_sii.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::json_field;
using testing::OperatorRun;

std::string hex_of(const std::string& bytes) {
  std::string out;
  char two[3];
  for (const char c : bytes) {
    (void)std::snprintf(two, sizeof two, "%02x", static_cast<unsigned>(static_cast<unsigned char>(c)));
    out += two;
  }
  return out;
}

TEST(OperatorCtlSiiRead, RawTextAndJsonShowTheSiiTheMasterReadFromEachSlave) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  const Result<drivers::SiiImage> eeprom = drivers::build_joint_drive_sii(elbow);
  ASSERT_TRUE(eeprom.ok());

  const CommandResult raw = testing::run_program({"ctl", "--key", run.key, "--port", std::to_string(run.control_port),
                                                  "sii_read", "l_elbow", "--raw"},
                                                 false);
  ASSERT_EQ(raw.status, 0) << raw.out;
  ASSERT_GT(raw.out.size(), 128U);
  ASSERT_LE(raw.out.size(), eeprom.value().size());
  std::size_t differing = 0;
  bool differing_read_zero = true;
  for (std::size_t i = 0; i < raw.out.size(); ++i) {
    const auto byte = static_cast<std::uint8_t>(raw.out[i]);
    if (i < 128) {
      EXPECT_EQ(byte, eeprom.value()[i]) << "byte " << i;
    }
    if (byte != eeprom.value()[i]) {
      ++differing;
      differing_read_zero = differing_read_zero && byte == 0;
    }
  }
  EXPECT_TRUE(differing_read_zero) << "a byte the master read differs from the drive's EEPROM";

  const CommandResult json = run.ctl({"--json", "sii_read", std::to_string(elbow)});
  ASSERT_EQ(json.status, 0) << json.out;
  EXPECT_EQ(json_field(json.out, "slave"), "l_elbow") << json.out;
  EXPECT_EQ(json_field(json.out, "size"), std::to_string(raw.out.size())) << json.out;
  EXPECT_EQ(json_field(json.out, "bytes"), hex_of(raw.out));
  EXPECT_EQ(json_field(json.out, "strings_skipped"), differing > 0 ? "true" : "false") << json.out;

  const CommandResult text = run.ctl({"sii_read", "l_elbow"});
  ASSERT_EQ(text.status, 0) << text.out;
  EXPECT_EQ(text.out.rfind("l_elbow (position " + std::to_string(elbow) + "): " + std::to_string(raw.out.size()) +
                               " bytes of SII as the master read them at bring-up",
                           0),
            0U)
      << text.out;
  std::size_t lines = 0;
  for (const char c : text.out) lines += c == '\n' ? 1 : 0;
  EXPECT_EQ(lines, 1 + (raw.out.size() + 15) / 16) << text.out;
  EXPECT_NE(text.out.find("\n0000: " + hex_of(raw.out.substr(0, 1)) + " "), std::string::npos) << text.out;

  const CommandResult junction = run.ctl({"--json", "sii_read", "1"});
  ASSERT_EQ(junction.status, 0) << junction.out;
  EXPECT_EQ(json_field(junction.out, "slave"), "junction_b") << junction.out;
  // Its identity in the SII's words 8..11: vendor id, then product code "JCT4", little-endian.
  EXPECT_EQ(json_field(junction.out, "bytes").substr(32, 16), "5c0a00003454434a") << junction.out;

  EXPECT_EQ(run.ctl({"sii_read", "23"}).status, 2);
  EXPECT_EQ(run.ctl({"--json", "sii_read", "l_elbow", "--raw"}).status, 2);
  EXPECT_EQ(run.ctl({"status", "--raw"}).status, 2);
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
