// One running instance per state directory and per raw NIC (issue 11 item 3): two `run`s sharing a
// state directory would overwrite each other's error-joints file, two masters on one NIC would
// answer each other's frames.
//
//  - The state directory: flock(LOCK_EX | LOCK_NB) on DIR/rescue-motion.lock, which holds the
//    holder's pid. The kernel drops the lock when the process dies (even by SIGKILL), so a stale
//    file never blocks a start.
//  - A raw NIC: the abstract unix socket "@rescue-motion/nic/IFACE", bound and listening. Abstract
//    names live in the network namespace, like the interface, and vanish with the process. A second
//    instance that finds the name taken connects to it and reads the holder's pid (SO_PEERCRED).
//
// Both are held until the process exits (the descriptors stay open; nothing to release).
#pragma once

#include <cstdint>

#include "core/base/result.hpp"

namespace rescue::hal {

constexpr const char* kStateLockName = "rescue-motion.lock";

// Takes the lock of `dir`. Errors: busy when another process holds it (detail0 = its pid, 0 when
// unknown), or the OS error of creating/locking the file (detail0 = errno).
Status lock_state_directory(const char* dir) noexcept;

// Takes the lock of the raw interface `iface`. Errors: busy (detail0 = the holder's pid, 0 when
// unknown), out_of_range for a name too long, io_error (detail0 = errno).
Status lock_raw_interface(const char* iface) noexcept;

}  // namespace rescue::hal
