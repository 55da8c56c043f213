// What the OS lets this process do that the firmware needs (docs/deploy.md): the capabilities
// CAP_NET_RAW (raw EtherCAT socket), CAP_SYS_NICE (SCHED_FIFO above RLIMIT_RTPRIO) and CAP_IPC_LOCK
// (mlockall above RLIMIT_MEMLOCK), and those two limits. Read with capget(2) (fixed kernel structs,
// no text parsing) and getrlimit(2). describe_privileges() says, per missing item, what it costs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "core/base/result.hpp"

namespace rescue::hal {

struct Privileges {
  bool root{false};      // effective uid 0
  bool net_raw{false};   // effective capabilities
  bool sys_nice{false};
  bool ipc_lock{false};
  std::uint64_t rtprio_limit{0};   // RLIMIT_RTPRIO soft limit (kUnlimited: no limit)
  std::uint64_t memlock_limit{0};  // RLIMIT_MEMLOCK soft limit in bytes (kUnlimited: no limit)
  static constexpr std::uint64_t kUnlimited = ~std::uint64_t{0};
};

Result<Privileges> query_privileges() noexcept;

// What the run needs: the highest SCHED_FIFO priority it asks for, whether it opens a raw socket.
struct PrivilegeNeeds {
  int max_priority{0};
  bool raw_socket{false};
};

// One line per missing item ("CAP_NET_RAW missing: ..."), written to `out` each prefixed by
// `prefix`; returns how many were missing (0: one line saying everything is there).
std::size_t describe_privileges(const Privileges& have, const PrivilegeNeeds& needs, const char* prefix,
                                std::FILE* out) noexcept;

}  // namespace rescue::hal
