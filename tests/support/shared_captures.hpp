// The real captures in ../shared/vectors/captures that tests read (never copied into the project),
// and a GoogleTest-friendly name for each. Tests only.
#pragma once

#include <cctype>
#include <string>

#include <gtest/gtest.h>

namespace rescue::test {

inline const std::string kSharedCaptureDir = std::string(RESCUE_SHARED_DIR) + "/vectors/captures/";

inline const char* const kSharedCaptures[] = {"twincat-run-ek1100-el1004.pcapng", "soem-single-lan9252.pcapng",
                                              "soem-sdinfo-akd.pcapng", "replay-dc.pcapng"};

// "replay-dc.pcapng" -> "replay_dc_pcapng": a valid test name.
inline std::string capture_test_name(const std::string& file) {
  std::string name = file;
  for (char& ch : name) {
    if (std::isalnum(static_cast<unsigned char>(ch)) == 0) ch = '_';
  }
  return name;
}

inline std::string capture_param_name(const testing::TestParamInfo<const char*>& p) { return capture_test_name(p.param); }

}  // namespace rescue::test
