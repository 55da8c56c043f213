#include "core/app/tasks/joint_events.hpp"

#include "core/app/tasks/error_joints_storage.hpp"

#include <cstdio>

namespace rescue::app {
namespace {

const char* joint_name(std::uint8_t joint) noexcept { return joint < kJointCount ? kJoints[joint].name : "robot"; }


const char* kStepWhat[] = {
    "",
    "1 handler reported the joints unreachable",
    "2 read their last state from shared memory",
    "3 wrote the error-joints file",
    "4 answered the handler",
    "5 marked them comm_lost (Error)",
};

}  // namespace

const char* to_string(JointEventKind kind) noexcept {
  switch (kind) {
    case JointEventKind::file_absent: return "file_absent";
    case JointEventKind::file_restored: return "file_restored";
    case JointEventKind::file_unusable: return "file_unusable";
    case JointEventKind::file_set_aside: return "file_set_aside";
    case JointEventKind::file_wiring_added: return "file_wiring_added";
    case JointEventKind::file_newer_temporary: return "file_newer_temporary";
    case JointEventKind::file_copy_used: return "file_copy_used";
    case JointEventKind::file_unreadable_held: return "file_unreadable_held";
    case JointEventKind::reconfiguration_step: return "reconfiguration_step";
    case JointEventKind::file_written: return "file_written";
    case JointEventKind::file_write_failed: return "file_write_failed";
    case JointEventKind::transition: return "transition";
    case JointEventKind::refused: return "refused";
    case JointEventKind::fault: return "fault";
    case JointEventKind::operator_cleared: return "operator_cleared";
    case JointEventKind::operator_clear_refused: return "operator_clear_refused";
    case JointEventKind::notice_deferred: return "notice_deferred";
    case JointEventKind::auto_cleared: return "auto_cleared";
    case JointEventKind::lost_joint_returned: return "lost_joint_returned";
    case JointEventKind::lost_joint_moved: return "lost_joint_moved";
  }
  return "unknown";
}

std::size_t format_event(const JointEvent& e, char* out, std::size_t capacity) noexcept {
  if (capacity == 0) return 0;
  char names[kJointNamesCapacity];
  format_joint_names(e.joints, names, sizeof names);
  int n = 0;
  switch (e.kind) {
    case JointEventKind::file_absent:
      n = std::snprintf(out, capacity, "error-joints file: none, no joint recorded lost");
      break;
    case JointEventKind::file_restored:
      n = e.joints == 0 ? std::snprintf(out, capacity, "error-joints file: read, no joint recorded lost")
                        : std::snprintf(out, capacity, "error-joints file: restored %s in Error with their held positions", names);
      break;
    case JointEventKind::file_unusable:
      n = e.joints != 0
              ? std::snprintf(out, capacity, "error-joints file damaged: %s (%s); salvaged %s; %llu record(s) dropped",
                              e.error.what, to_string(e.error.code), names, static_cast<unsigned long long>(e.count))
              : std::snprintf(out, capacity, "error-joints file not used: %s (%s; %llu record(s) dropped)", e.error.what,
                              to_string(e.error.code), static_cast<unsigned long long>(e.count));
      break;
    case JointEventKind::file_set_aside: {
      char name[64];
      set_aside_name(static_cast<std::uint32_t>(e.count), name, sizeof name);
      n = std::snprintf(out, capacity, "error-joints file kept aside as %s", name);
      break;
    }
    case JointEventKind::file_wiring_added:
      n = std::snprintf(out, capacity, "error-joints file: %s recorded lost too: behind a salvaged lost joint on its "
                        "branch, unreachable too (held position unknown)", names);
      break;
    case JointEventKind::file_newer_temporary:
      n = std::snprintf(out, capacity, "error-joints file: complete newer error-joints.bin.tmp (sequence %llu) left by "
                        "an interrupted write; its joints kept recorded lost%s%s",
                        static_cast<unsigned long long>(e.count), e.joints != 0 ? ", adding " : "", e.joints != 0 ? names : "");
      break;
    case JointEventKind::file_copy_used:
      n = e.error.code == Errc::ok
              ? std::snprintf(out, capacity, "error-joints file older than its second copy %s (sequence %llu, an "
                              "interrupted save): the copy used", ErrorJointsFileStorage::kCopyName,
                              static_cast<unsigned long long>(e.count))
              : std::snprintf(out, capacity, "error-joints file not used: %s (%s); its second copy %s (sequence %llu) "
                              "used instead", e.error.what, to_string(e.error.code), ErrorJointsFileStorage::kCopyName,
                              static_cast<unsigned long long>(e.count));
      break;
    case JointEventKind::file_unreadable_held:
      n = std::snprintf(out, capacity, "error-joints file: no readable record of the lost joints (the file and its "
                        "second copy damaged or missing): %s held in Error until the operator clears each by name "
                        "(ctl clear NAME, confirming the position: held position unknown)", names);
      break;
    case JointEventKind::reconfiguration_step:
      n = e.error.code == Errc::ok
              ? std::snprintf(out, capacity, "reconfiguration step %s: %s",
                              e.step < sizeof kStepWhat / sizeof kStepWhat[0] ? kStepWhat[e.step] : "?", names)
              : std::snprintf(out, capacity, "reconfiguration step %s: %s (the error-joints file does NOT hold them "
                                             "yet: %s; retrying)",
                              e.step < sizeof kStepWhat / sizeof kStepWhat[0] ? kStepWhat[e.step] : "?", names, e.error.what);
      break;
    case JointEventKind::file_written:
      n = std::snprintf(out, capacity, "error-joints file written (sequence %llu): %s",
                        static_cast<unsigned long long>(e.count), names);
      break;
    case JointEventKind::file_write_failed:
      n = std::snprintf(out, capacity, "error-joints file NOT written: %s (%s, errno %u); will retry", e.error.what,
                        to_string(e.error.code), e.error.detail0);
      break;
    case JointEventKind::transition:
      n = std::snprintf(out, capacity, "%s: %s --%s--> %s", joint_name(e.joint), fsm::to_string(e.from),
                        fsm::to_string(e.input), fsm::to_string(e.to));
      break;
    case JointEventKind::refused:
      n = std::snprintf(out, capacity, "%s: %s refused in %s (%s)", joint_name(e.joint), fsm::to_string(e.input),
                        fsm::to_string(e.from), e.error.what);
      break;
    case JointEventKind::fault:
      n = std::snprintf(out, capacity, "%s: %s (value %.4g, limit %.4g)", joint_name(e.joint), to_string(e.fault.reason),
                        e.fault.value, e.fault.limit);
      break;
    case JointEventKind::operator_cleared:
      n = std::snprintf(out, capacity, "%s: cleared by operator after repair (reset it to use it again)",
                        joint_name(e.joint));
      break;
    case JointEventKind::operator_clear_refused:
      n = std::snprintf(out, capacity, "%s: operator clear refused: %s", joint_name(e.joint), e.error.what);
      break;
    case JointEventKind::auto_cleared:
      n = std::snprintf(out, capacity, "%s: cleared automatically: its drive was power-cycled and is back", joint_name(e.joint));
      break;
    case JointEventKind::lost_joint_returned:
      n = std::snprintf(out, capacity, "%s: answers again at its held position; stays in Error until cleared", joint_name(e.joint));
      break;
    case JointEventKind::lost_joint_moved:
      n = std::snprintf(out, capacity,
                        "%s: answers again %.4f rad away from its held position; out of service until the operator "
                        "confirms the clear",
                        joint_name(e.joint), e.fault.value);
      break;
    case JointEventKind::notice_deferred:
      n = std::snprintf(out, capacity, "notice to the EtherCAT handler deferred (queue full): %s", names);
      break;
  }
  if (n < 0) {
    out[0] = '\0';
    return 0;
  }
  return static_cast<std::size_t>(n) < capacity ? static_cast<std::size_t>(n) : capacity - 1;
}

}  // namespace rescue::app
