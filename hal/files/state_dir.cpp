#include "hal/files/state_dir.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace rescue::hal {
namespace {

bool is_absolute(const char* p) noexcept { return p != nullptr && p[0] == '/'; }

// `base` followed by `suffix`.
Result<StateDir> make(const char* source, const char* base, const char* suffix) noexcept {
  StateDir dir;
  dir.source = source;
  const int n = std::snprintf(dir.path.text.data(), dir.path.text.size(), "%s%s", base, suffix);
  if (n < 0 || static_cast<std::size_t>(n) >= dir.path.text.size()) return make_error(Errc::out_of_range, "state directory path too long");
  return dir;
}

}  // namespace

Result<StateDir> choose_state_dir(const char* option, bool privileged, const char* xdg_state_home,
                                  const char* home) noexcept {
  if (option != nullptr) {
    if (option[0] == '\0') return make_error(Errc::invalid_argument, "empty --state-dir");
    return make("--state-dir", option, "");
  }
  if (privileged) return make("system default", kSystemStateDir, "");
  // XDG: a relative XDG_STATE_HOME is invalid and must be ignored.
  if (is_absolute(xdg_state_home)) return make("$XDG_STATE_HOME", xdg_state_home, "/rescue-motion");
  if (is_absolute(home)) return make("$HOME", home, "/.local/state/rescue-motion");
  return make_error(Errc::not_found, "no state directory: not root, and neither XDG_STATE_HOME nor HOME is set");
}

bool is_installed_program_path(const char* exe) noexcept {
  return exe != nullptr && std::strncmp(exe, "/usr/", 5) == 0;
}

bool system_state_dir_is_default() noexcept {
  if (::geteuid() != 0) return false;
  char exe[4096];
  const ssize_t n = ::readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) return false;
  exe[n] = '\0';
  return is_installed_program_path(exe);
}

Result<StateDir> resolve_state_dir(const char* option) noexcept {
  const bool privileged = system_state_dir_is_default();
  // Start-up only, before any thread exists.
  const char* xdg = std::getenv("XDG_STATE_HOME");  // NOLINT(concurrency-mt-unsafe)
  const char* home = std::getenv("HOME");           // NOLINT(concurrency-mt-unsafe)
  auto dir = choose_state_dir(option, privileged, xdg, home);
  if (!dir.ok()) return dir;
  if (option == nullptr && !privileged && ::geteuid() == 0) {
    // Said at start ("state directory D (SOURCE)"), so root knows why not the system directory.
    dir.value().source = std::strcmp(dir.value().source, "$XDG_STATE_HOME") == 0
                             ? "$XDG_STATE_HOME: root, but not the installed /usr/bin/rescue-motion; --state-dir "
                               "/var/lib/rescue-motion to use the system directory"
                             : "$HOME: root, but not the installed /usr/bin/rescue-motion; --state-dir "
                               "/var/lib/rescue-motion to use the system directory";
  }
  const bool per_user = dir.value().source[0] == '$';  // "$XDG_STATE_HOME...", "$HOME..."
  const Status made = make_directories(dir.value().path.c_str(), per_user ? 0700U : 0755U);
  if (!made.ok()) return made.error();
  return dir;
}

Status check_writable(const char* dir) noexcept {
  if (::faccessat(AT_FDCWD, dir, W_OK | X_OK, AT_EACCESS) == 0) return Status::success();
  return make_error(Errc::permission_denied, "state directory not writable", static_cast<std::uint32_t>(errno));
}

}  // namespace rescue::hal
