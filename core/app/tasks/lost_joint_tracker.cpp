#include "core/app/tasks/lost_joint_tracker.hpp"

namespace rescue::app {

LostJointTracker::LostJointTracker(MessageSink<LostJointsReport>& reports, MessageSource<JointManagerNotice>& notices,
                                   JointMask restored_lost, std::uint8_t confirm_cycles) noexcept
    : reports_(reports),
      notices_(notices),
      confirm_cycles_(confirm_cycles == 0 ? 1 : confirm_cycles),
      confirmed_(restored_lost & kAllJoints) {}

void LostJointTracker::on_cycle(std::uint64_t cycle, hal::Nanoseconds now, JointMask unreachable) noexcept {
  // Detection: only a loss confirmed over several cycles is reported (one lost frame is not damage).
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((unreachable & joint_bit(j)) == 0) {
      missed_[j] = 0;
      continue;
    }
    if (missed_[j] < confirm_cycles_) ++missed_[j];
    if (missed_[j] >= confirm_cycles_ && (excluded() & joint_bit(j)) == 0) unreported_ |= joint_bit(j);
  }

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
    const JointMask joints = notice.joints & kAllJoints;
    if (notice.kind == NoticeKind::lost_joints_recorded) {
      confirmed_ |= joints & pending_;
      pending_ &= ~joints;
      last_file_status_ = notice.file_status;
      last_answer_cycle_ = notice.cycle;
    } else {
      confirmed_ &= ~joints;
      for (std::size_t j = 0; j < kJointCount; ++j) {
        if ((joints & joint_bit(j)) != 0) missed_[j] = 0;
      }
    }
  }
}

}  // namespace rescue::app
