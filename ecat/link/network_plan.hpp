// What the master expects on the wire, fixed at compile time: one SlavePlan per slave in frame
// order (the robot's is built in drivers/joint/robot_network_plan.hpp), and the logical process image
// derived from it.
//
// Process image: one logical address space, one region per branch, in branch order. A region holds
// the outputs of the branch's slaves (wiring order), then their inputs:
//
//   logical 0                                                                           total
//   | torso: out j0 j1 j2 | in j0 j1 j2 | left arm: out ... | in ... | right arm ... | lower ... |
//
// Each region is exchanged by one LRW per cycle, so its working counter concerns one branch only:
// every slave in OP that the frame reaches adds 3 (1 for its read FMMU, 2 for its write FMMU). The
// image buffer's byte offsets equal the logical addresses (logical base 0).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "ecat/link/master_capacities.hpp"

namespace rescue::ecat {

constexpr std::uint8_t kNoBranch = 0xFF;
constexpr std::uint8_t kMasterEnd = 0xFE;  // link diagnostics: the cable's other end is the master
constexpr std::uint16_t kLrwWkcPerSlave = 3;  // read (1) + write (2) by one slave

// A set of slaves by frame position (bit p = slave at position p of the plan).
using SlaveMask = std::uint32_t;
static_assert(kMaxSlaves <= 32, "SlaveMask holds 32 slaves");
constexpr SlaveMask slave_bit(std::size_t position) noexcept { return SlaveMask{1} << position; }
constexpr SlaveMask kAllSlaves = (SlaveMask{1} << kMaxSlaves) - 1;

// The PDO assignment and mapping a slave must hold for its process data to match the plan
// (ETG.1020, CiA 402): one PDO assigned to the SyncManager, `entry_count` mapping entries, each
// index << 16 | subindex << 8 | bits. The master reads it at bring-up and at online recovery and
// writes what differs (docs/master.md, "PDO mapping").
struct PdoMappingPlan {
  std::uint16_t assign_index;    // 0x1C12 (outputs, SM2) or 0x1C13 (inputs, SM3)
  std::uint16_t pdo_index;       // the PDO assigned there, e.g. 0x1600 / 0x1A00
  const std::uint32_t* entries;  // the mapping words, in order
  std::uint8_t entry_count;
};
struct SlavePdoPlan {
  PdoMappingPlan outputs;  // RxPDO (master -> slave)
  PdoMappingPlan inputs;   // TxPDO (slave -> master)
};

// The bytes a mapping fills (entries whose bit lengths are not whole bytes count their bits).
constexpr std::uint32_t mapping_bytes(const PdoMappingPlan& m) noexcept {
  std::uint32_t bits = 0;
  for (std::size_t i = 0; i < m.entry_count; ++i) bits += m.entries[i] & 0xFFU;
  return (bits + 7U) / 8U;
}

struct SlavePlan {
  const char* name;
  std::uint32_t vendor_id;
  std::uint32_t product_code;
  std::uint32_t revision;
  const char* device_name;        // SII General name of the device type
  std::uint16_t station_address;  // configured station address the master assigns
  std::uint16_t station_alias;    // commissioned alias (SII word 4); 0 = not checked
  std::uint8_t upstream;          // position of the slave it hangs off, kMasterUpstream for the first
  std::uint8_t upstream_port;     // port of that slave
  std::uint8_t branch;            // kNoBranch: no process data
  std::uint16_t output_bytes;     // master -> slave process data (SM2)
  std::uint16_t input_bytes;      // slave -> master process data (SM3)
  bool mailbox;                   // CoE over SM0/SM1
  bool dc_sync0;                  // outputs latched on SYNC0
  const SlavePdoPlan* pdo;        // the mapping the master sets up (nullptr: left as the slave has it)
};

using NetworkPlan = std::array<SlavePlan, kMaxSlaves>;

struct BranchLayout {
  std::uint32_t logical_start{0};  // == image offset
  std::uint16_t length{0};         // outputs + inputs of the branch
  std::uint16_t output_length{0};  // the outputs come first
  std::uint8_t slave_count{0};
  std::array<std::uint8_t, kMaxSlavesPerBranch> slaves{};  // positions, in wiring order
};

struct SlaveImage {
  std::uint32_t output_offset{0};  // image offset == logical address of its outputs
  std::uint32_t input_offset{0};
};

struct ProcessImageLayout {
  std::array<BranchLayout, kMaxBranches> branches{};
  std::array<SlaveImage, kMaxSlaves> slaves{};
  std::uint32_t total_bytes{0};
  bool valid{false};  // false when a branch has too many slaves (checked by static_assert at the robot)
};

constexpr ProcessImageLayout make_process_image_layout(const NetworkPlan& plan) noexcept {
  ProcessImageLayout layout{};
  std::uint32_t offset = 0;
  for (std::size_t b = 0; b < kMaxBranches; ++b) {
    BranchLayout& branch = layout.branches[b];
    branch.logical_start = offset;
    std::uint32_t outputs = 0;
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      if (plan[p].branch != b) continue;
      if (branch.slave_count == kMaxSlavesPerBranch) return ProcessImageLayout{};
      branch.slaves[branch.slave_count++] = static_cast<std::uint8_t>(p);
      layout.slaves[p].output_offset = offset + outputs;
      outputs += plan[p].output_bytes;
    }
    std::uint32_t inputs = 0;
    for (std::size_t i = 0; i < branch.slave_count; ++i) {
      const std::size_t p = branch.slaves[i];
      layout.slaves[p].input_offset = offset + outputs + inputs;
      inputs += plan[p].input_bytes;
    }
    branch.output_length = static_cast<std::uint16_t>(outputs);
    branch.length = static_cast<std::uint16_t>(outputs + inputs);
    offset += outputs + inputs;
  }
  layout.total_bytes = offset;
  layout.valid = true;
  return layout;
}

// Slaves of `branch` in wiring order, as a mask.
constexpr SlaveMask branch_slaves(const ProcessImageLayout& layout, std::size_t branch) noexcept {
  SlaveMask mask = 0;
  for (std::size_t i = 0; i < layout.branches[branch].slave_count; ++i) mask |= slave_bit(layout.branches[branch].slaves[i]);
  return mask;
}

// Every slave behind `position` (its subtree, itself included): what a cut link into it loses.
constexpr SlaveMask subtree_of(const NetworkPlan& plan, std::size_t position) noexcept {
  SlaveMask mask = slave_bit(position);
  for (std::size_t p = position + 1; p < kMaxSlaves; ++p) {
    const std::uint8_t up = plan[p].upstream;
    if (up != kMasterUpstream && (mask & slave_bit(up)) != 0) mask |= slave_bit(p);
  }
  return mask;
}

// `slaves` and every slave behind one of them (the closure of subtree_of over the set).
constexpr SlaveMask subtrees_of(const NetworkPlan& plan, SlaveMask slaves) noexcept {
  SlaveMask mask = slaves;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    const std::uint8_t up = plan[p].upstream;
    if (up != kMasterUpstream && (mask & slave_bit(up)) != 0) mask |= slave_bit(p);
  }
  return mask;
}

constexpr int popcount(std::uint32_t v) noexcept {
  int n = 0;
  for (; v != 0; v &= v - 1) ++n;
  return n;
}

// The position of the lowest set bit of a mask that is not empty.
constexpr std::size_t lowest_slave(SlaveMask mask) noexcept { return static_cast<std::size_t>(__builtin_ctz(mask)); }

// Calls visit(p) for each set bit p of `mask` in the order start, start + 1, ..., then from 0: one
// turn, as p = (start + i) % kMaxSlaves walks the positions; stops when visit returns false.
template <typename Visit>
constexpr void for_each_slave_from(SlaveMask mask, std::size_t start, Visit&& visit) noexcept {
  const SlaveMask from_start = start >= 32 ? 0 : mask & ~((SlaveMask{1} << start) - 1);
  for (SlaveMask m = from_start; m != 0; m &= m - 1) {
    if (!visit(lowest_slave(m))) return;
  }
  for (SlaveMask m = mask & ~from_start; m != 0; m &= m - 1) {
    if (!visit(lowest_slave(m))) return;
  }
}

}  // namespace rescue::ecat
