// A master given a ring NIC (Master::use_ring) never runs silently on one port: over a two-port fake
// segment, a ring NIC that receives nothing (the segment's far end not cabled to it) refuses the
// bring-up at its "ring" step with that reason, and so does a ring already open (naming how many
// slaves each port reaches); a closed ring passes the step (the bring-up goes on to identify).
// Virtual time.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "ecat/master/bring_up_report.hpp"
#include "ecat/master/master.hpp"
#include "tests/support/two_port_rig.hpp"

namespace rescue::ecat {
namespace {

using test::kRingRigSlaves;

unsigned g_stop_calls = 0;
// Stops the bring-up at its second check (before identify): the count and the ring check ran.
bool stop_after_count() noexcept { return ++g_stop_calls > 1; }

class RingBringUp : public ::testing::Test {
 protected:
  RingBringUp() {
    master.use_ring(rig.segment.ring());
    options.first_contact_timeout = 10 * hal::kNsPerMs;
    options.stop_requested = stop_after_count;
    g_stop_calls = 0;
  }

  test::TwoPortRig rig;
  std::array<std::uint8_t, 64> image{};
  Master master{rig.segment.main(), rig.plan, rig.layout, ByteSpan(image)};
  MasterOptions options{};
};

TEST_F(RingBringUp, ARingNicThatHearsNothingIsRefusedWithTheReason) {
  rig.segment.cut(kRingRigSlaves);  // the last slave's free port is not cabled to the ring NIC
  const Status st = master.bring_up(options);
  ASSERT_FALSE(st.ok());
  ASSERT_NE(master.report().failed_step, nullptr);
  EXPECT_STREQ(master.report().failed_step, "ring");
  EXPECT_EQ(st.error().code, Errc::not_found);
  EXPECT_NE(std::strstr(st.error().what, "ring NIC received nothing"), nullptr) << st.error().what;
  EXPECT_EQ(st.error().detail0, kRingRigSlaves) << "slaves reached from the main port";
  // The headline says what the numbers are.
  char* text = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&text, &size);
  ASSERT_NE(out, nullptr);
  print_bring_up_failure(out, "", "", master);
  std::fclose(out);
  const std::string line(text, size);
  std::free(text);
  EXPECT_NE(line.find("bring-up failed at ring: the ring does not close: the ring NIC received nothing"), std::string::npos)
      << line;
  EXPECT_NE(line.find("(the main port reaches 6 slaves, the ring port 0)"), std::string::npos) << line;
}

TEST_F(RingBringUp, ARingOpenAtBringUpIsRefusedNamingEachPortsReach) {
  rig.segment.cut(2);
  const Status st = master.bring_up(options);
  ASSERT_FALSE(st.ok());
  EXPECT_STREQ(master.report().failed_step, "ring");
  EXPECT_EQ(st.error().code, Errc::refused);
  EXPECT_EQ(st.error().detail0, 2U);
  EXPECT_EQ(st.error().detail1, kRingRigSlaves - 2);
}

TEST_F(RingBringUp, AClosedRingPassesTheRingCheck) {
  const Status st = master.bring_up(options);
  ASSERT_FALSE(st.ok());  // stopped on request before identify
  EXPECT_STREQ(master.report().failed_step, "identify");
  EXPECT_EQ(master.report().slaves_counted, kRingRigSlaves) << "the merged count: every slave once";
}

}  // namespace
}  // namespace rescue::ecat
