// What start-up says before the tasks run (startup_log.hpp).
#include "core/app/runtime/startup_log.hpp"

#include <cinttypes>
#include <cstdio>

#include "core/app/runtime/run_log.hpp"
#include "core/app/runtime/stop_signal.hpp"
#include "core/app/tasks/error_joints_storage.hpp"
#include "ecat/master/bring_up_report.hpp"

namespace rescue::app::runner {

int report_bring_up_failure(drivers::JointBus& bus) noexcept {
  ecat::print_bring_up_failure(stderr, "rescue-motion run: ", "rescue-motion run: ", bus.master());
  return 1;
}

void print_restored(JointMask restored) noexcept {
  if (restored == 0) return;
  char names[kJointNamesCapacity];
  format_joint_names(restored, names, sizeof names);
  (void)std::printf("rescue-motion run: restored lost joints %s from the error-joints file before bring-up; "
                    "they stay out of the exchange until an operator clears them\n",
                    names);
}

namespace {

// No readable record (the file and its copy): the joints held beyond what the file still lists.
void print_held_unreadable(const RestoreReport& r) noexcept {
  if (r.held_unreadable == 0) return;
  char names[kJointNamesCapacity];
  format_joint_names(r.held_unreadable, names, sizeof names);
  (void)std::printf("rescue-motion run:   no readable record of the lost joints (the error-joints file and its second "
                    "copy %s damaged or missing): which were lost cannot be known, so %s are held in Error as well, "
                    "until each is cleared by name (held position unknown)\n",
                    ErrorJointsFileStorage::kCopyName, names);
}

}  // namespace

void print_restore_problems(const RestoreReport& r, const char* dir) noexcept {
  char kept[64];
  set_aside_name(r.set_aside_suffix, kept, sizeof kept);
  char names[kJointNamesCapacity];
  if (r.newer_temporary) {
    format_joint_names(r.from_temporary, names, sizeof names);
    (void)std::printf("rescue-motion run: %s/%s is complete and newer (sequence %" PRIu64 ") than the error-joints "
                      "file: a write was interrupted before its rename; its joints are kept recorded lost%s%s\n",
                      dir, ErrorJointsFileStorage::kTemporaryName, r.temporary_sequence,
                      r.from_temporary != 0 ? "; it adds " : "", r.from_temporary != 0 ? names : "");
  }
  if (r.from_copy) {  // the file damaged, missing or older: every loss its second copy holds is kept
    if (r.damaged()) {
      (void)std::printf("rescue-motion run: error-joints file not used: %s (%s); its second copy %s/%s (sequence %" PRIu64
                        ") used instead, and the file rewritten from it\n",
                        r.file_status.error().what, to_string(r.file_status.error().code), dir,
                        ErrorJointsFileStorage::kCopyName, r.copy_sequence);
    } else {
      (void)std::printf("rescue-motion run: error-joints file missing or older than its second copy %s/%s (sequence %" PRIu64
                        "): the copy used, and the file rewritten from it\n",
                        dir, ErrorJointsFileStorage::kCopyName, r.copy_sequence);
    }
    if (r.set_aside) (void)std::printf("rescue-motion run:   the damaged original is kept as %s/%s\n", dir, kept);
    return;
  }
  if (!r.damaged()) return;
  const Error& why = r.file_status.error();
  if (r.salvaged == 0) {
    (void)std::printf("rescue-motion run: error-joints file not used: %s (%s); %u record(s) dropped; starting safely\n",
                      why.what, to_string(why.code), r.records_dropped);
    if (r.set_aside) (void)std::printf("rescue-motion run:   the original is kept as %s/%s\n", dir, kept);
    print_held_unreadable(r);
    format_joint_names(r.restored, names, sizeof names);
    (void)std::printf("rescue-motion run:   %s stay out of service; clear each one by name once checked: --clear-joint "
                      "NAMES\n", names);
    return;
  }
  format_joint_names(r.salvaged, names, sizeof names);
  (void)std::printf("rescue-motion run: error-joints file damaged: %s (%s); salvaged %s from the records that passed "
                    "their checks; dropped %u record(s) that did not\n",
                    why.what, to_string(why.code), names, r.records_dropped);
  if (r.added_behind != 0) {
    format_joint_names(r.added_behind, names, sizeof names);
    (void)std::printf("rescue-motion run:   also recorded lost: %s, behind a salvaged lost joint on its branch and "
                      "so unreachable too (held position unknown)\n",
                      names);
  }
  if (r.set_aside) (void)std::printf("rescue-motion run:   the damaged original is kept as %s/%s\n", dir, kept);
  print_held_unreadable(r);
  format_joint_names(r.restored, names, sizeof names);
  (void)std::printf("rescue-motion run:   %s stay out of service (brought up if they answer, never driven); once "
                    "they are repaired and checked, clear them with --clear-joint %s\n",
                    names, names);
}

int stopped_in_bring_up(drivers::JointBus& bus, const FirmwareOptions& options) noexcept {
  const ecat::BringUpReport& report = bus.master().report();
  (void)std::printf("rescue-motion run: stopped by signal %d during bring-up, before step %s; no drive was enabled "
                    "(no slave reached OP); error-joints file unchanged\n",
                    stop_signal(), report.failed_step != nullptr ? report.failed_step : "?");
  if (options.capture_path != nullptr) (void)finish_capture(options.capture_path);
  return 0;
}

bool announce_repaired_joints(const RepairedJointsPlan& plan) noexcept {
  char names[kJointNamesCapacity];
  if (plan.not_recorded != 0) {
    format_joint_names(plan.not_recorded, names, sizeof names);
    (void)std::printf("rescue-motion run: --clear-joint: %s not recorded lost; nothing to clear\n", names);
  }
  if (plan.refused()) {
    format_joint_names(plan.stranded, names, sizeof names);
    char blocking[kJointNamesCapacity];
    format_joint_names(plan.blocking, blocking, sizeof blocking);
    (void)std::fprintf(stderr,
                       "rescue-motion run: --clear-joint: %s cannot answer behind %s, which stay(s) recorded lost: "
                       "clear those too; the error-joints file is unchanged\n",
                       names, blocking);
    return false;
  }
  if (plan.to_clear != 0) {
    format_joint_names(plan.to_clear, names, sizeof names);
    (void)std::printf("rescue-motion run: operator declares %s repaired: expected on the network, cleared once they "
                      "answer in OP\n",
                      names);
  }
  return true;
}

}  // namespace rescue::app::runner
