#include "hal/rt/privileges.hpp"

#include <linux/capability.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cinttypes>

namespace rescue::hal {
namespace {

bool has_bit(const __user_cap_data_struct (&data)[_LINUX_CAPABILITY_U32S_3], int cap) noexcept {
  const auto index = static_cast<std::size_t>(cap) / 32U;
  const auto bit = static_cast<unsigned>(cap) % 32U;
  return (data[index].effective & (1U << bit)) != 0;
}

Result<std::uint64_t> soft_limit(int resource) noexcept {
  rlimit limit{};
  if (::getrlimit(resource, &limit) != 0) {
    return make_error(Errc::io_error, "getrlimit refused", static_cast<std::uint32_t>(errno));
  }
  return limit.rlim_cur == RLIM_INFINITY ? Privileges::kUnlimited : static_cast<std::uint64_t>(limit.rlim_cur);
}

void print_limit(std::FILE* out, std::uint64_t value, const char* unit) noexcept {
  if (value == Privileges::kUnlimited) {
    (void)std::fprintf(out, "unlimited");
  } else {
    (void)std::fprintf(out, "%" PRIu64 "%s", value, unit);
  }
}

}  // namespace

Result<Privileges> query_privileges() noexcept {
  __user_cap_header_struct header{};
  header.version = _LINUX_CAPABILITY_VERSION_3;
  header.pid = 0;  // this thread
  __user_cap_data_struct data[_LINUX_CAPABILITY_U32S_3] = {};
  if (::syscall(SYS_capget, &header, &data[0]) != 0) {
    return make_error(Errc::io_error, "capget refused", static_cast<std::uint32_t>(errno));
  }
  Privileges p;
  p.root = ::geteuid() == 0;
  p.net_raw = has_bit(data, CAP_NET_RAW);
  p.sys_nice = has_bit(data, CAP_SYS_NICE);
  p.ipc_lock = has_bit(data, CAP_IPC_LOCK);
  const Result<std::uint64_t> rtprio = soft_limit(RLIMIT_RTPRIO);
  if (!rtprio.ok()) return rtprio.error();
  const Result<std::uint64_t> memlock = soft_limit(RLIMIT_MEMLOCK);
  if (!memlock.ok()) return memlock.error();
  p.rtprio_limit = rtprio.value();
  p.memlock_limit = memlock.value();
  return p;
}

std::size_t describe_privileges(const Privileges& have, const PrivilegeNeeds& needs, const char* prefix,
                                std::FILE* out) noexcept {
  std::size_t missing = 0;
  if (!have.net_raw) {
    ++missing;
    (void)std::fprintf(out, "%sCAP_NET_RAW missing: %s (grant it: AmbientCapabilities=CAP_NET_RAW)\n", prefix,
                       needs.raw_socket ? "the raw EtherCAT socket cannot be opened, the run will fail"
                                        : "no raw:IFACE NIC (the simulated robot needs none)");
  }
  const bool rtprio_enough = have.rtprio_limit != Privileges::kUnlimited &&
                             have.rtprio_limit >= static_cast<std::uint64_t>(needs.max_priority > 0 ? needs.max_priority : 0);
  const bool rtprio_ok = have.rtprio_limit == Privileges::kUnlimited || rtprio_enough;
  if (needs.max_priority > 0 && !have.sys_nice && !rtprio_ok) {
    ++missing;
    (void)std::fprintf(out, "%sCAP_SYS_NICE missing and RLIMIT_RTPRIO %" PRIu64 " below priority %d: the real-time "
                            "tasks run at normal priority, periods will be late under load (grant CAP_SYS_NICE or "
                            "LimitRTPRIO=%d)\n",
                       prefix, have.rtprio_limit, needs.max_priority, needs.max_priority);
  }
  // mlockall(MCL_CURRENT | MCL_FUTURE) needs CAP_IPC_LOCK unless the whole process fits the limit;
  // the firmware's locked size is not known before it runs, so only "unlimited" is sure.
  if (!have.ipc_lock && have.memlock_limit != Privileges::kUnlimited) {
    ++missing;
    (void)std::fprintf(out, "%sCAP_IPC_LOCK missing and RLIMIT_MEMLOCK ", prefix);
    print_limit(out, have.memlock_limit, " bytes");
    (void)std::fprintf(out, ": memory may not be locked, a page fault can stall a real-time period (grant "
                            "CAP_IPC_LOCK or LimitMEMLOCK=infinity)\n");
  }
  if (missing == 0) {
    (void)std::fprintf(out, "%s%s; CAP_NET_RAW %s, CAP_SYS_NICE %s, CAP_IPC_LOCK %s; RLIMIT_RTPRIO ", prefix,
                       have.root ? "root" : "not root", have.net_raw ? "held" : "not held",
                       have.sys_nice ? "held" : "not held", have.ipc_lock ? "held" : "not held");
    print_limit(out, have.rtprio_limit, "");
    (void)std::fprintf(out, ", RLIMIT_MEMLOCK ");
    print_limit(out, have.memlock_limit, " bytes");
    (void)std::fprintf(out, ": every real-time setting can be applied\n");
  }
  return missing;
}

}  // namespace rescue::hal
