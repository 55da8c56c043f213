// Issue 35, item 15: AL status codes from the vendor range (0x8000 and up, ETG.1000.6) were called
// "unknown"; they are the device's own codes, named as such, and a code below that range missing from
// the program's list is said to be missing from the list, not unknown to the standard.
#include <gtest/gtest.h>

#include <string>

#include "ecat/codec/registers.hpp"

namespace rescue::ecat::reg {
namespace {

TEST(AlStatusCodes, AreExplainedByTheirRangeAndNoneIsCalledUnknown) {
  EXPECT_STREQ(explain_al_status_code(al_code::kSynchronizationError), "synchronization error");
  for (const std::uint16_t vendor : {std::uint16_t{0x8000}, std::uint16_t{0x8001}, std::uint16_t{0xFFFF}}) {
    EXPECT_STREQ(explain_al_status_code(vendor), "vendor-specific AL status code (see the device's manual)") << vendor;
  }
  EXPECT_STREQ(explain_al_status_code(0x7FFF), "AL status code not in this program's list (see ETG.1000.6)");
  for (std::uint32_t code = 0; code <= 0xFFFF; ++code) {
    EXPECT_EQ(std::string(explain_al_status_code(static_cast<std::uint16_t>(code))).find("unknown AL status"), std::string::npos)
        << code;
  }
}

}  // namespace
}  // namespace rescue::ecat::reg
