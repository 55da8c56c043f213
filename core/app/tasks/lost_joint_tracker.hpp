// The EtherCAT handler's side of reconfiguration (paper IV-C steps 1 and 6), called once per cycle.
// It never blocks and never touches the disk: it turns the master's verdict into a lost-joints
// report on a queue, keeps lost joints out of the commands at once, and reads the joint manager's
// answer when it comes. The healthy branches keep their cycle throughout.
//
// It decides nothing about the network: the master's link monitor alone confirms a loss
// (ecat/master/link_monitor.hpp, kLossConfirmFrames; docs/master.md), and the joints behind the
// slaves it took out of the exchange are what this tracker reports, in the cycle they leave it.
//
//   out of the exchange (the master says so)        -> `unreported` (excluded at once: held, not commanded)
//   report queued (try_send succeeded)              -> `pending`    (step 1 done; waiting for the answer)
//   answer read (lost_joints_recorded)              -> `confirmed`  (step 6: resume with the others)
//   operator cleared them (joints_cleared)          -> commanded again
// A full report queue costs nothing but a retry next cycle (counted).
#pragma once

#include <cstdint>

#include "core/app/links/joint_messages.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/robot/robot.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

class LostJointTracker {
 public:
  static constexpr std::size_t kMaxNoticesPerCycle = 4;

  // `restored_lost`: the joints the joint manager restored from the error-joints file at start-up;
  // they are excluded from the first cycle on.
  LostJointTracker(MessageSink<LostJointsReport>& reports, MessageSource<JointManagerNotice>& notices,
                   JointMask restored_lost) noexcept;

  // Once per cycle. `out`: the joints whose slaves the master holds out of the exchange this cycle
  // (lost, not operational, restored and not yet re-integrated, held out of service). Bounded work:
  // one try_send, at most kMaxNoticesPerCycle try_receive.
  void on_cycle(std::uint64_t cycle, hal::Nanoseconds now, JointMask out) noexcept;

  JointMask unreported() const noexcept { return unreported_; }
  JointMask pending() const noexcept { return pending_; }
  JointMask confirmed() const noexcept { return confirmed_; }
  // Joints the handler must not command (their drives hold; their outputs are not sent).
  JointMask excluded() const noexcept { return unreported_ | pending_ | confirmed_; }

  std::uint32_t reports_sent() const noexcept { return reports_sent_; }
  std::uint32_t reports_deferred() const noexcept { return reports_deferred_; }
  // Notices refused as damaged (unknown kind, a joint beyond the robot): nothing changed by them.
  std::uint32_t damaged_notices() const noexcept { return damaged_notices_; }
  // Whether the joint manager's last answer said the error-joints file holds the loss.
  Errc last_file_status() const noexcept { return last_file_status_; }
  std::uint64_t last_answer_cycle() const noexcept { return last_answer_cycle_; }

 private:
  MessageSink<LostJointsReport>& reports_;
  MessageSource<JointManagerNotice>& notices_;
  JointMask unreported_{0};
  JointMask pending_{0};
  JointMask confirmed_{0};
  std::uint32_t reports_sent_{0};
  std::uint32_t reports_deferred_{0};
  std::uint32_t damaged_notices_{0};
  Errc last_file_status_{Errc::ok};
  std::uint64_t last_answer_cycle_{0};
};

}  // namespace rescue::app
