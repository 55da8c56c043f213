// `rescue-motion bench codec` runs to the end and reports every figure as a `key: value unit` line
// after the header (CPU, kernel, privileges), with no heap allocation after init. No timing is
// asserted: the figures are for people and docs/ecat-codec.md.
#include <gtest/gtest.h>

#include <unistd.h>

#include <regex>
#include <string>

#include "tests/support/run_command.hpp"

namespace rescue {
namespace {

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

TEST(BenchCodec, PrintsHeaderAndEveryFigure) {
  ASSERT_EQ(::access(kProgram.c_str(), X_OK), 0) << kProgram << " is not built";
  const test::CommandOutput out = test::run_command("'" + kProgram + "' bench codec --frames 2000 2>&1");
  ASSERT_EQ(out.exit_status, 0) << out.out;
  for (const char* header : {"bench: codec\n", "\ncpu: ", "\nkernel: ", "\nprivileges: "}) {
    EXPECT_NE(out.out.find(header), std::string::npos) << header;
  }
  const std::regex figure("^[a-z0-9_]+: [0-9.]+ [a-z%/]+$");
  std::size_t figures = 0;
  for (const std::string& line : test::split_lines(out.out)) {
    if (std::regex_match(line, figure)) ++figures;
  }
  EXPECT_GE(figures, 15U) << out.out;
  for (const char* key : {"\nframe_bytes: 672 bytes\n", "\nframe_datagrams: 5 datagrams\n",
                          "\nwire_time_100mbit: 55680 ns\n", "\nbuild_median: ", "\nbuild_p99: ", "\ndecode_median: ",
                          "\ndecode_p99: ", "\nbuild_median_of_wire_time: ", "\ndecode_median_of_wire_time: ",
                          "\nheap_allocations_after_init: 0 allocations\n"}) {
    EXPECT_NE(out.out.find(key), std::string::npos) << key << "\n" << out.out;
  }
}

}  // namespace
}  // namespace rescue
