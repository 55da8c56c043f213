// The message parser task (design brief section 3, paper III-B): takes authentic, decoded operator
// requests from two bounded queues (the socket handler's, and the runtime's for start-up and exit),
// and
//   - joint control messages (enable, disable, mode, clear) -> the joint handle queue;
//   - predefined messages -> their joint setting steps, in order, on the joint handle queue:
//       initialize  select_mode (each joint's default mode), set_reference, enable, for every selected
//                   joint that is reachable and not recorded lost
//       hold        disable, set_reference, enable for the selected joints that are Enabled: each
//                   stops where it stands (worm gears hold during the step) and holds that position
//       clear       clear_lost (the repaired joints leave the error-joints file), reset
//   - RC-task inputs (move, hand, owner) -> that RC task's input queue, or refused "no RC task
//     running" while its heartbeat is silent; move and hand are refused "not owner (owner: rcN)"
//     unless that task owns the motion (or an `owner` for it was just queued).
// It is the joint handle queue's only producer. One request is in flight at a time: its steps carry
// a request id, and the reply (accepted, or refused with the first refused joint and why) is sent
// once the joint manager has reported every step's outcome, or refused "busy" after kReplyTimeout.
// An operator's request (from the network) is all or nothing: its steps go to the joint manager as one
// request that is checked against every named joint first; refused, nothing changes and the reply
// names every blocking joint with its own reason. The runtime's own requests (start-up initialize,
// clears, the disable at exit) are applied joint by joint.
// It talks to the rest only through the ports below (queues and seqlocks of TaskLinks), so the same
// code runs as a thread or as its own process. No heap, never waits.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "core/app/links/control_messages.hpp"
#include "core/app/links/joint_messages.hpp"
#include "core/app/links/motion_owner.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/robot/joint_limits.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

struct MessageParserPorts {
  MessageSource<ControlRequest>* network{nullptr};    // from the socket handler
  MessageSource<ControlRequest>* local{nullptr};      // from the runtime
  MessageSink<ControlReply>* network_replies{nullptr};
  MessageSink<ControlReply>* local_replies{nullptr};
  MessageSink<JointCommand>* joint_commands{nullptr};  // the joint handle queue
  MessageSource<JointCommandOutcome>* outcomes{nullptr};
  const Seqlock<RobotSample>* samples{nullptr};        // reachability
  const Seqlock<RobotJointStatus>* joint_status{nullptr};
  std::array<MessageSink<RcTaskInput>*, protocol::kMaxRcTasks> rc_inputs{};
  const std::array<std::atomic<std::int64_t>, protocol::kMaxRcTasks>* rc_heartbeat_ns{nullptr};
  const MotionOwner* owner{nullptr};  // move and hand for a task that does not own the motion: "not owner"
};

class MessageParser {
 public:
  static constexpr hal::Nanoseconds kReplyTimeout = 500 * hal::kNsPerMs;
  // A clear is answered once the error-joints file is durable (the storage worker's time, a slow disk
  // included), so its request waits longer before it is called busy.
  static constexpr hal::Nanoseconds kClearReplyTimeout = 5 * hal::kNsPerSec;
  static constexpr hal::Nanoseconds kRcTaskSilence = 100 * hal::kNsPerMs;  // heartbeat older: not running
  static constexpr std::size_t kMaxRequestsPerStep = 8;

  explicit MessageParser(const MessageParserPorts& ports) noexcept : ports_(ports) {}

  // One period: collect outcomes, answer a finished request, start the next ones.
  void step(hal::Nanoseconds now) noexcept;

  bool idle() const noexcept { return !pending_.active; }
  std::uint64_t requests() const noexcept { return requests_; }
  std::uint64_t replies_dropped() const noexcept { return replies_dropped_; }
  // RC task heartbeats read damaged (links/heartbeat.hpp): the input was refused "no RC task running".
  std::uint64_t damaged_beats() const noexcept { return damaged_beats_; }

 private:
  struct Pending {
    bool active{false};
    ControlRequest request{};
    std::uint32_t id{0};
    std::uint32_t steps{0};
    std::uint32_t outcomes{0};
    JointMask applied{0};
    JointMask refused{0};
    JointCommandOutcome first_refusal{};
    std::array<JointRefusalNote, kJointCount> notes{};  // every refused joint's own reason
    hal::Nanoseconds deadline{0};
    JointMask skipped{0};    // selected but not taken (initialize: unreachable or lost)
    JointMask unchanged{0};  // selected but already where the request takes them (already_there)
  };

  void start(const ControlRequest& request, hal::Nanoseconds now) noexcept;
  void start_rc_input(const ControlRequest& request) noexcept;
  void finish() noexcept;
  void reply(const ControlRequest& request, protocol::Outcome outcome, protocol::RefusalReason reason,
             JointMask refused, const char* text,
             const std::array<JointRefusalNote, kJointCount>* notes = nullptr) noexcept;

  MessageParserPorts ports_;
  Pending pending_{};
  std::uint32_t next_id_{1};
  std::uint64_t requests_{0};
  std::uint64_t replies_dropped_{0};
  std::uint64_t damaged_beats_{0};
  hal::Nanoseconds now_{0};
  // The last `owner TASK` queued: the RC task takes the word in its next period, so a move or hand
  // right behind it (within kRcTaskSilence) is its owner's.
  std::uint8_t taking_task_{kNoOwnerTask};
  hal::Nanoseconds taking_since_{0};
};

}  // namespace rescue::app
