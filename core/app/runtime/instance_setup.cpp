// The instance's locks and its shared-memory segment (instance_setup.hpp).
#include "core/app/runtime/instance_setup.hpp"

#include <cstdio>
#include <new>
#include <utility>

#include "core/app/config/command_line.hpp"
#include "core/app/runtime/run_context.hpp"
#include "hal/files/instance_lock.hpp"
#include "hal/files/state_dir.hpp"

namespace rescue::app::runner {
namespace {

// A resource another instance holds: name it and the holder's pid; the run does not start.
int fail_locked(const char* what, const char* name, const Error& error) noexcept {
  if (error.code == Errc::busy) {
    if (error.detail0 != 0) {
      (void)std::fprintf(stderr, "rescue-motion run: %s %s is in use by another rescue-motion (pid %u); not starting\n",
                         what, name, error.detail0);
    } else {
      (void)std::fprintf(stderr, "rescue-motion run: %s %s is in use by another rescue-motion (pid unknown); not starting\n",
                         what, name);
    }
    return 1;
  }
  (void)std::fprintf(stderr, "rescue-motion run: cannot lock %s %s: %s (%s, errno %u); not starting\n", what, name,
                     error.what, to_string(error.code), error.detail0);
  return 1;
}

}  // namespace

int take_instance_locks(const FirmwareOptions& options, const char* dir) noexcept {
  // One instance per state directory and per raw NIC (a second one would erase the first's losses).
  const Status writable = hal::check_writable(dir);
  if (!writable.ok()) {
    (void)std::fprintf(stderr,
                       "rescue-motion run: WARNING: state directory %s is not writable (errno %u): a joint lost in this run "
                       "cannot be recorded, and no other instance is kept out; fix its permissions or use "
                       "--state-dir\n",
                       dir, writable.error().detail0);
  } else {
    const Status locked = hal::lock_state_directory(dir);
    if (!locked.ok()) return fail_locked("state directory", dir, locked.error());
  }
  if (options.nic.kind == NicKind::raw) {
    const Status locked = hal::lock_raw_interface(options.nic.interface_name.data());
    if (!locked.ok()) return fail_locked("interface", options.nic.interface_name.data(), locked.error());
  }
  return 0;
}

int create_segment(const FirmwareOptions& options, const char* state_dir) noexcept {
  if (g_run.segment.created()) {  // a second run in this process (tests): the run's words start afresh
    new (&shared_links().run) RunControl();
    return 0;
  }
  shm::SegmentName name = shm::default_segment_name(state_dir);
  if (options.segment_name != nullptr) {
    const Result<shm::SegmentName> given = shm::segment_name(options.segment_name);
    if (!given.ok()) return fail("run", given.error().what);
    name = given.value();
  }
  shm::CreateReport report;
  Result<shm::SegmentOwner> created = shm::SegmentOwner::create(name, &report);
  if (!created.ok()) {
    char line[512];
    (void)shm::describe_segment_error(name, created.error(), line, sizeof line);
    (void)std::fprintf(stderr, "rescue-motion run: %s; not starting\n", line);
    return 1;
  }
  g_run.segment = std::move(created.value());
  if (report.previous != shm::Previous::none) {
    (void)std::printf("rescue-motion run: replaced stale shared-memory segment %s (%s, creator pid %d); its contents "
                      "were not used\n",
                      name.c_str(), shm::to_string(report.previous), static_cast<int>(report.previous_creator.pid));
  }
  (void)std::printf("rescue-motion run: shared-memory segment %s, %zu bytes, layout version %u hash 0x%08x%s\n",
                    name.c_str(), shm::kSegmentSize, static_cast<unsigned>(TaskLinks::kLayoutVersion),
                    static_cast<unsigned>(shm::kLayoutHash), report.memory_lock.ok() ? ", locked in RAM" : "");
  return 0;
}

}  // namespace rescue::app::runner
