#include "core/app/tasks/lost_joint_tracker.hpp"

namespace rescue::app {

LostJointTracker::LostJointTracker(MessageSink<LostJointsReport>& reports, MessageSource<JointManagerNotice>& notices,
                                   JointMask restored_lost) noexcept
    : reports_(reports), notices_(notices), confirmed_(restored_lost & kAllJoints) {}

void LostJointTracker::on_cycle(std::uint64_t cycle, hal::Nanoseconds now, JointMask out) noexcept {
  // Detection is the master's (it confirmed the loss over kLossConfirmFrames returned frames).
  unreported_ |= out & kAllJoints & ~excluded();

  // Step 1: report, without waiting. A full queue means: try again next cycle.
  if (unreported_ != 0) {
    LostJointsReport report;
    report.lost = unreported_;
    report.cycle = cycle;
    report.detected_at = now;
    if (reports_.try_send(report)) {
      pending_ |= unreported_;
      unreported_ = 0;
      ++reports_sent_;
    } else {
      ++reports_deferred_;
    }
  }

  // Step 6 (and operator clears): read the joint manager's notices.
  JointManagerNotice notice;
  for (std::size_t n = 0; n < kMaxNoticesPerCycle && notices_.try_receive(notice); ++n) {
    // A record of the shared segment: an unknown kind or a joint beyond the robot is damage (a
    // stray write, a bit flip), refused and counted; read as a clear it would command lost joints.
    const bool known_kind = notice.kind == NoticeKind::lost_joints_recorded || notice.kind == NoticeKind::joints_cleared;
    if (!known_kind || (notice.joints & ~kAllJoints) != 0) {
      ++damaged_notices_;
      continue;
    }
    const JointMask joints = notice.joints;
    if (notice.kind == NoticeKind::lost_joints_recorded) {
      confirmed_ |= joints & pending_;
      pending_ &= ~joints;
      last_file_status_ = notice.file_status;
      last_answer_cycle_ = notice.cycle;
    } else {
      confirmed_ &= ~joints;
    }
  }
}

}  // namespace rescue::app
