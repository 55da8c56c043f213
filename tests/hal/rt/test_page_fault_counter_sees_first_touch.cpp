#include <gtest/gtest.h>

#include <sys/mman.h>
#include <unistd.h>

#include "hal/rt/rt_setup.hpp"

namespace rescue::hal {
namespace {

TEST(PageFaults, FirstTouchOfFreshPagesIsCountedOncePerPage) {
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  constexpr std::size_t kPages = 16;  // 64 KiB: too small for a transparent huge page
  void* memory = mmap(nullptr, kPages * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(memory, MAP_FAILED);
  auto* bytes = static_cast<volatile unsigned char*>(memory);

  const PageFaults before = page_faults_of_thread();
  for (std::size_t i = 0; i < kPages; ++i) bytes[i * page] = 1;
  const PageFaults touched = page_faults_of_thread();
  for (std::size_t i = 0; i < kPages; ++i) bytes[i * page] = 2;
  const PageFaults again = page_faults_of_thread();
  munmap(memory, kPages * page);

  EXPECT_GE(touched.minor - before.minor, kPages);
  EXPECT_LT(again.minor - touched.minor, kPages) << "pages already mapped do not fault again";
  EXPECT_EQ(touched.major, before.major) << "anonymous memory needs no I/O";
}

TEST(PageFaults, ProcessCountIncludesTheThreadCount) {
  const PageFaults thread = page_faults_of_thread();
  const PageFaults process = page_faults_of_process();
  EXPECT_GE(process.minor, thread.minor);
  EXPECT_GT(process.minor, 0u) << "loading the program itself faults";
}

}  // namespace
}  // namespace rescue::hal
