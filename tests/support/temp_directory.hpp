// A fresh directory under GoogleTest's temporary directory for one test, removed with everything in
// it when the test ends; and the bytes of a string, for the file functions that take spans.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/base/span.hpp"

namespace rescue::testing {

class TempDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string templ = ::testing::TempDir() + "rescue-test-XXXXXX";
    ASSERT_NE(mkdtemp(templ.data()), nullptr);
    dir_ = templ;
  }
  void TearDown() override { (void)std::system(("rm -rf '" + dir_ + "'").c_str()); }
  std::string path(const char* name) const { return dir_ + "/" + name; }
  std::string dir_;
};

inline ConstByteSpan bytes_of(const std::string& s) {
  return ConstByteSpan(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
}

}  // namespace rescue::testing
