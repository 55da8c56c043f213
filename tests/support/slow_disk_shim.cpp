// A slow disk for end-to-end tests (issue 21): an LD_PRELOAD library whose fsync() and fdatasync()
// wait RESCUE_SLOW_DISK_MS milliseconds before the real call, as a disk under heavy write-back does.
// With RESCUE_SLOW_DISK_LOG set, each delayed call appends one line ("fsync <fd>") to that file, so a
// test can check the delay really happened. Built as a test helper (rescue_slow_disk_shim), never
// linked into the program.
#include <dlfcn.h>
#include <fcntl.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

using SyncFn = int (*)(int);

void wait_like_a_slow_disk(const char* call, int fd) {
  const char* ms = std::getenv("RESCUE_SLOW_DISK_MS");
  const long delay = ms != nullptr ? std::strtol(ms, nullptr, 10) : 0;
  if (delay > 0) {
    timespec t{delay / 1000, (delay % 1000) * 1'000'000L};
    while (nanosleep(&t, &t) != 0) {
    }
  }
  const char* log = std::getenv("RESCUE_SLOW_DISK_LOG");
  if (log == nullptr) return;
  const int out = ::open(log, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
  if (out < 0) return;
  char line[64];
  const int n = std::snprintf(line, sizeof line, "%s %d\n", call, fd);
  if (n > 0) (void)!::write(out, line, static_cast<std::size_t>(n));
  (void)::close(out);
}

SyncFn next(const char* name) { return reinterpret_cast<SyncFn>(dlsym(RTLD_NEXT, name)); }

}  // namespace

extern "C" int fsync(int fd) {
  static const SyncFn real = next("fsync");
  wait_like_a_slow_disk("fsync", fd);
  return real(fd);
}

extern "C" int fdatasync(int fd) {
  static const SyncFn real = next("fdatasync");
  wait_like_a_slow_disk("fdatasync", fd);
  return real(fd);
}
