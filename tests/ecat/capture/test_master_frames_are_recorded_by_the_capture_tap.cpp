// The master's frame tap feeding the capture writer: a bring-up and some cycles on the simulated
// robot end up in a pcapng file, every frame sent and its returned copy, in order, readable back.
#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "ecat/capture/capture_reader.hpp"
#include "ecat/capture/capture_tap.hpp"
#include "ecat/capture/capture_writer.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

TEST(MasterCapture, EveryFrameSentAndReceivedIsRecorded) {
  const std::string path = std::string(RESCUE_BINARY_DIR) + "/master-capture-" + std::to_string(::getpid()) + ".pcapng";
  auto rig = std::make_unique<testing::SimulatedRobotRig>();
  CaptureWriter writer;
  ASSERT_TRUE(writer.open(path.c_str()).ok());
  rig->bus.master().set_tap(capture_tap, &writer);
  MasterOptions options = testing::fast_options();
  options.drift_compensation_frames = 100;
  ASSERT_TRUE(rig->bus.bring_up(options).ok());
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  for (int i = 0; i < 50; ++i) (void)rig->cycle(refs, fb);
  const std::uint64_t exchanged = rig->bus.master().link().stats().exchanges;
  ASSERT_TRUE(writer.close().ok());

  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Result<CaptureReader> reader = CaptureReader::open(ConstByteSpan(file.data(), file.size()));
  ASSERT_TRUE(reader.ok());
  CapturedFrame frame;
  std::uint64_t frames = 0;
  std::uint64_t lrw = 0;
  for (;;) {
    const Result<bool> got = reader.value().next(frame);
    ASSERT_TRUE(got.ok());
    if (!got.value()) break;
    ++frames;
    const Result<FrameView> view = FrameView::parse(frame.bytes);
    ASSERT_TRUE(view.ok());
    for (const DatagramView d : view.value()) lrw += d.command() == Command::LRW ? 1 : 0;
  }
  EXPECT_EQ(frames, 2 * exchanged) << "each exchange: the frame sent and the frame back";
  EXPECT_EQ(lrw, 2u * 4u * 50u) << "4 LRW per cycle, both directions";
  ::unlink(path.c_str());
}

}  // namespace
}  // namespace rescue::ecat
