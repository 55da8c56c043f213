// Where the firmware keeps state that must outlive it (the error-joints file): --state-dir when given;
// otherwise /var/lib/rescue-motion for root running the installed program (/usr/bin/rescue-motion of
// the package: the motion PC); otherwise (a user, or root running a build from the source tree, so a
// source-tree run never leaves root's files in the package's directory) a per-user directory, following
// the XDG base-directory convention: $XDG_STATE_HOME/rescue-motion (absolute paths only), else
// $HOME/.local/state/rescue-motion. The directory is created when missing.
#pragma once

#include "core/base/result.hpp"
#include "hal/files/durable_file.hpp"

namespace rescue::hal {

constexpr const char* kSystemStateDir = "/var/lib/rescue-motion";

struct StateDir {
  PathBuffer path;
  const char* source{""};  // why this one: "--state-dir", "system default", "$XDG_STATE_HOME", "$HOME"
};

// The choice alone, from its inputs (testable without touching the environment or the disk).
// not_found when unprivileged with neither an absolute $XDG_STATE_HOME nor an absolute $HOME.
Result<StateDir> choose_state_dir(const char* option, bool privileged, const char* xdg_state_home,
                                  const char* home) noexcept;

// choose_state_dir with this process's privileges and environment, then creates the directory (0755
// for the system default, 0700 for per-user ones).
Result<StateDir> resolve_state_dir(const char* option) noexcept;

// Whether the system directory is the default for this process: root, running the installed program
// (its executable under /usr/, as the package installs it). The `privileged` of choose_state_dir.
bool system_state_dir_is_default() noexcept;
// Whether an executable path is an installed program's (under /usr/): testable without installing.
bool is_installed_program_path(const char* exe) noexcept;

// Whether this process may create files in `dir` (access W_OK with the effective ids; a read-only
// mount says so too). permission_denied (detail0 = errno) when it may not: a loss could not be recorded.
Status check_writable(const char* dir) noexcept;

}  // namespace rescue::hal
