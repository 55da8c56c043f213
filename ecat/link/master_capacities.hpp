// The master's capacities, fixed at compile time (no heap): the size of the segment this build of
// the master is made for. ecat/ speaks in slaves only; the robot that must fit in them says so with
// static_asserts where its plan is built (drivers/joint/robot_network_plan.hpp).
//
// A NetworkPlan holds exactly kMaxSlaves slaves (every entry is a real slave, in frame order) on
// exactly kMaxBranches process-data branches, so a different segment means different constants here.
#pragma once

#include <cstddef>
#include <cstdint>

namespace rescue::ecat {

constexpr std::size_t kMaxSlaves = 23;            // slaves in the plan (SlaveMask holds up to 32)
constexpr std::size_t kMaxBranches = 4;           // process-data regions, one LRW each
constexpr std::size_t kMaxSlavesPerBranch = 8;
// Slaves whose mailbox step rides in one cyclic frame (each adds up to one mailbox, about 140 bytes,
// to it); bring-up's own mailbox frames take every slave that fits.
constexpr std::size_t kCyclicMailboxSlaves = 2;
constexpr std::uint8_t kMasterUpstream = 0xFF;    // SlavePlan::upstream of the first slave

}  // namespace rescue::ecat
