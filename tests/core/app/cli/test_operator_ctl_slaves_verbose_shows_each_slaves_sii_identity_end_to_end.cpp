// Issue 24, `ctl slaves -v` (docs/operator.md), like IgH's `ethercat slaves -v`: against a real
// `rescue-motion run` on the simulated robot, every slave's vendor id, product code, revision and
// serial number are those its SII holds (the simulator's devices: drivers/joint/device_identity.hpp),
// as the master read them at bring-up, and its AL state and AL status code are those it answered
// (OP, 0x0000 "no error" on a healthy network). Text and --json (parsed).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "core/robot/robot.hpp"
#include "drivers/joint/device_identity.hpp"
#include "tests/support/json_query.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::OperatorRun;

TEST(OperatorCtlSlavesVerbose, ShowsEachSlavesSiiIdentityAndAlStatusCode) {
  OperatorRun run;
  ASSERT_EQ(run.keygen.status, 0) << run.keygen.out;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  // The identity is published once cycling, the AL status once each slave confirmed OP.
  CommandResult json;
  for (int i = 0; i < 100; ++i) {
    json = run.ctl({"--json", "slaves", "-v"});
    if (json.status == 0 && json.out.find("\"al_state\":\"-\"") == std::string::npos &&
        json.out.find("\"al_state\":\"SAFEOP\"") == std::string::npos) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(json.status, 0) << json.out;
  const auto q = [&](const std::string& expr) { return testing::json_query(run.dir.path, json.out, expr); };
  ASSERT_EQ(q("len(d['slaves'])"), std::to_string(kSlaveCount)) << json.out;
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    const drivers::DeviceIdentity& id = drivers::identity_of(kSlaves[p].kind);
    const std::string s = "d['slaves'][" + std::to_string(p) + "]";
    char want[256];
    (void)std::snprintf(want, sizeof want, R"([%zu, %u, "%s", true, %u, %u, %u, %u, true, "OP", false, 0, "no error"])", p,
                        static_cast<unsigned>(kSlaves[p].station_address), kSlaves[p].name, id.vendor_id, id.product_code,
                        id.revision, drivers::serial_number_of(p));
    EXPECT_EQ(q("[" + s + "[k] for k in ('position', 'station', 'name', 'identity_read', 'vendor_id', 'product_code', "
                "'revision', 'serial_number', 'al_status_read', 'al_state', 'al_error', 'al_status_code', "
                "'al_status_code_name')]"),
              want)
        << kSlaves[p].name;
  }

  // Text: the same facts, one row per slave; -v and --verbose are the same option.
  const CommandResult text = run.ctl({"slaves", "--verbose"});
  ASSERT_EQ(text.status, 0) << text.out;
  EXPECT_NE(text.out.find("POS STATION NAME             VENDOR     PRODUCT    REVISION   SERIAL     AL      AL STATUS CODE"),
            std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("19  0x1013  l_elbow          0x00000a5c 0x4a443432 0x00010000 0x52460013 OP      0x0000 no error"),
            std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("0   0x1000  junction_a       0x00000a5c 0x4a435434 0x00010000 0x52460000 OP"), std::string::npos)
      << text.out;
  // Without -v, ctl slaves is the table it was; -v with another verb is refused.
  EXPECT_EQ(run.ctl({"slaves"}).out.find("VENDOR"), std::string::npos);
  EXPECT_EQ(run.ctl({"status", "-v"}).status, 2);
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
