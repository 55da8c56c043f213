// `run` keeps the SII cache in its state directory (docs/master.md "SII cache", docs/firmware.md):
// the first start reads every slave's SII whole and writes `sii-cache`; the next start takes all 23
// images from it (only each slave's first 32 EEPROM bytes read) and reaches OP; a damaged file is
// ignored (the run still reaches OP, every image read whole) and written again whole. Each run's
// summary says when it reached OP (`bring_up_to_op_ms:`) and how many images came from the cache.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/base/span.hpp"
#include "ecat/sii/sii_cache.hpp"
#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

std::string value_of(const std::string& out, const std::string& key) {
  const std::size_t at = out.find("\n" + key + ": ");
  if (at == std::string::npos) return std::string();
  const std::size_t begin = at + key.size() + 3;
  return out.substr(begin, out.find('\n', begin) - begin);
}

std::vector<std::uint8_t> read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<std::uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The file as the program would read it: decodes, and holds `images` images.
void expect_valid_cache(const std::string& path, std::size_t images) {
  const std::vector<std::uint8_t> bytes = read_all(path);
  ecat::SiiCache cache;
  EXPECT_TRUE(cache.decode(ConstByteSpan(bytes.data(), bytes.size())).ok()) << path;
  EXPECT_EQ(cache.size(), images);
}

TEST(RunSiiCache, LaterStartsTakeEveryImageFromTheStateDirectoryAndADamagedFileIsRewritten) {
  char dir[] = "/tmp/run-sii-cache.XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  const std::string file = std::string(dir) + "/sii-cache";
  const std::string command = kBinary + " run --duration 0.2 --state-dir " + dir + " 2>&1";

  const test::CommandOutput first = test::run_command(command);
  ASSERT_EQ(first.exit_status, 0) << first.out;
  EXPECT_EQ(value_of(first.out, "bring_up_sii_cache_hits"), "0 of 23 slaves") << first.out;
  EXPECT_FALSE(value_of(first.out, "bring_up_to_op_ms").empty()) << first.out;
  expect_valid_cache(file, 23);

  const test::CommandOutput second = test::run_command(command);
  ASSERT_EQ(second.exit_status, 0) << second.out;
  EXPECT_EQ(value_of(second.out, "bring_up_sii_cache_hits"), "23 of 23 slaves") << second.out;
  EXPECT_FALSE(value_of(second.out, "bring_up_to_op_ms").empty()) << second.out;

  // One byte of the file damaged: refused whole, every image read whole, the file written again.
  std::vector<std::uint8_t> bytes = read_all(file);
  ASSERT_GT(bytes.size(), 100U);
  bytes[100] ^= 0x01U;
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
  const test::CommandOutput third = test::run_command(command);
  ASSERT_EQ(third.exit_status, 0) << third.out;
  EXPECT_EQ(value_of(third.out, "bring_up_sii_cache_hits"), "0 of 23 slaves") << third.out;
  EXPECT_FALSE(value_of(third.out, "bring_up_to_op_ms").empty()) << third.out;
  expect_valid_cache(file, 23);

  const std::string cleanup = std::string("rm -rf ") + dir;
  (void)std::system(cleanup.c_str());
}

}  // namespace
}  // namespace rescue::app
