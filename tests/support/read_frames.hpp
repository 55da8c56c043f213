// Reads every frame of a capture held in memory, failing the test on any reader error. Tests only.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "ecat/capture/capture_reader.hpp"

namespace rescue::test {

inline std::vector<ecat::CapturedFrame> read_all_frames(const std::vector<std::uint8_t>& file) {
  std::vector<ecat::CapturedFrame> frames;
  auto reader = ecat::CaptureReader::open(ConstByteSpan(file.data(), file.size()));
  EXPECT_TRUE(reader.ok()) << (reader.ok() ? "" : reader.error().what);
  if (!reader.ok()) return frames;
  ecat::CapturedFrame f;
  for (;;) {
    const Result<bool> more = reader.value().next(f);
    EXPECT_TRUE(more.ok()) << (more.ok() ? "" : more.error().what);
    if (!more.ok() || !more.value()) break;
    frames.push_back(f);
  }
  EXPECT_EQ(reader.value().frames_read(), frames.size());
  EXPECT_EQ(reader.value().offset(), file.size());
  return frames;
}

}  // namespace rescue::test
