// ctl's exchange names the real refusal (docs/protocol.md "Senders"): when the robot answered
// get_epoch but its replay window dropped the request (this sender's sequence already passed in
// this epoch, e.g. pushed ahead by another holder of the key), ctl says so, and does not blame a
// robot that is not running, a wrong port or another key.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <ctime>
#include <string>
#include <thread>

#include "core/app/operator_protocol/ctl_client.hpp"
#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/replay_window.hpp"
#include "tests/support/loopback_socket_handler.hpp"

namespace rescue::app {
namespace {

std::int64_t unix_now_ns() {
  timespec ts{};
  (void)clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000LL + ts.tv_nsec;
}

TEST(CtlClientRefusal, ARequestDroppedByTheReplayWindowIsNotCalledASilentRobot) {
  protocol::Key key{};
  key.fill(0x77);
  test::LoopbackSocketHandler rig(SocketHandlerPorts{}, key);
  const std::int64_t now = unix_now_ns();
  rig.wall.set(now);
  // Another key holder pushes sender 1's sequence 5 minutes ahead (within the robot's bound).
  ASSERT_TRUE(rig.window.accept(protocol::kOperatorSender, static_cast<std::uint64_t>(now) + 300'000'000'000ULL,
                                static_cast<std::uint64_t>(now)).ok());
  std::atomic<bool> done{false};
  std::thread robot([&] {
    while (!done.load()) {
      rig.handler.step(0);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  CtlTarget target;
  target.address = rig.loopback;
  target.port = rig.handler.control_port();
  target.key = key;
  target.sender = protocol::kOperatorSender;
  target.timeout_ms = 3000;  // the get_epoch answer comes from a thread that a loaded machine may hold back
  protocol::Message request;
  request.header.type = protocol::MessageType::get_status;
  const Result<protocol::Message> answer = ctl_exchange(target, request);
  done.store(true);
  robot.join();
  ASSERT_FALSE(answer.ok());
  const std::string what = answer.error().what;
  EXPECT_NE(what.find("answered get_epoch"), std::string::npos) << what;
  EXPECT_NE(what.find("replay window"), std::string::npos) << what;
  EXPECT_EQ(what.find("not running"), std::string::npos) << what;
  EXPECT_EQ(rig.handler.counters().rejected[static_cast<std::size_t>(protocol::Rejection::replayed)], 1U);
}

}  // namespace
}  // namespace rescue::app
