// The message parser passes an operator's move or hand to an RC task only while the task's heartbeat
// (TaskLinks::rc_heartbeat_ns, a record of the shared segment) says it runs. A damaged beat
// (core/app/links/heartbeat.hpp: a time far in the future, a negative one) tells nothing of the
// task: the input is refused "no RC task running" and the damage counted. Before, a beat from the
// future read as a task that beat just now, and `now - beat` overflowed on a negative one.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <memory>

#include "core/app/links/task_links.hpp"
#include "core/app/runtime/task_ports.hpp"
#include "core/app/tasks/message_parser.hpp"

namespace rescue::app {
namespace {

constexpr hal::Nanoseconds kNow = 1000 * hal::kNsPerSec;

// The reason the parser gives a local `move` to RC task 0 whose heartbeat is `beat`.
struct Answer {
  protocol::RefusalReason reason{protocol::RefusalReason::none};
  std::uint64_t damaged_beats{0};
};

Answer move_with_beat(std::int64_t beat) {
  const std::unique_ptr<TaskLinks> links = std::make_unique<TaskLinks>();
  const std::unique_ptr<TaskPorts> ports = std::make_unique<TaskPorts>(*links);
  MessageParser parser(ports->message_parser());
  links->rc_heartbeat_ns[0].store(beat);
  ControlRequest request;
  request.type = protocol::MessageType::move_effector;
  request.task = 0;
  EXPECT_TRUE(links->local_requests.try_push(request));
  parser.step(kNow);
  ControlReply reply;
  EXPECT_TRUE(links->local_replies.try_pop(reply));
  return Answer{reply.reason, parser.damaged_beats()};
}

TEST(DamagedRcHeartbeat, ABeatFromTheFutureIsNotARunningTask) {
  const Answer a = move_with_beat(kNow + 3600 * hal::kNsPerSec);
  EXPECT_EQ(a.reason, protocol::RefusalReason::no_rc_task);
  EXPECT_EQ(a.damaged_beats, 1U);
}

TEST(DamagedRcHeartbeat, ANegativeBeatIsNotARunningTask) {
  const Answer a = move_with_beat(std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(a.reason, protocol::RefusalReason::no_rc_task);
  EXPECT_EQ(a.damaged_beats, 1U);
}

TEST(DamagedRcHeartbeat, AWholeRecentBeatIsARunningTask) {
  // Running, but nobody owns the motion: refused for that, not for the task.
  const Answer a = move_with_beat(kNow - hal::kNsPerMs);
  EXPECT_EQ(a.reason, protocol::RefusalReason::not_owner);
  EXPECT_EQ(a.damaged_beats, 0U);
  // A beat just after the parser read its clock (the task ran meanwhile) is whole too.
  EXPECT_EQ(move_with_beat(kNow + hal::kNsPerMs).reason, protocol::RefusalReason::not_owner);
}

}  // namespace
}  // namespace rescue::app
