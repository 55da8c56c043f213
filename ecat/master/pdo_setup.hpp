// A slave's PDO assignment and mapping set up through start-up SDOs (ETG.1020 section "PDO
// configuration", CiA 402): the master depends on the mapping its process image was built from
// (SlavePlan::pdo), so it reads what the slave holds and writes only what differs, then reads it back.
//
//   read     per direction (outputs 0x1C12/0x16xx, then inputs 0x1C13/0x1Axx): the assignment count
//            and entry, the mapping count and each planned entry (expedited uploads; an aborted
//            upload counts as "differs"). A slave whose SII announces SDO complete access gives
//            each object in one upload from subindex 0 (count as 16 bits, then the entries); what
//            that does not give (an aborted complete access, fewer entries than planned) is read
//            one subindex at a time as above, so the same writes follow
//   write    per direction that differs, in the order ETG.1020 prescribes:
//              assignment count := 0            (the PDO may only be changed while unassigned)
//              mapping count := 0               (only if not 0 already, and only if the mapping differs)
//              mapping entries that differ
//              mapping count := n               (last: the slave checks the whole mapping here)
//              assignment entry (if it differs), assignment count := 1 (last)
//   verify   after any write: the same reads again, every value as planned
//
// One request of a slave is in flight at a time (next() gives nothing while one is pending), so
// the writes stay in order and many slaves set up at once never fill the mailbox queue: each
// holds at most one place in it. No heap: fixed capacities.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "ecat/link/network_plan.hpp"
#include "ecat/mailbox/mailbox_client.hpp"

namespace rescue::ecat {

constexpr std::size_t kMaxPdoEntries = 8;  // mapping entries per PDO this master sets up
// Tag bits of the PDO set-up's transfers (MailboxClient::kMasterTagBit: the master's own).
constexpr std::uint32_t kPdoSetupTagBit = 0x40000000U;

// What a slave holds for one direction (as read).
struct PdoMappingState {
  std::uint32_t assign_count{0};
  std::uint32_t assigned{0};
  std::uint32_t entry_count{0};
  std::array<std::uint32_t, kMaxPdoEntries> entries{};
  // Bit k set: read k (0 assignment count, 1 assignment entry, 2 mapping count, 3.. entries) was refused.
  std::uint32_t unknown{0};
};

constexpr std::size_t kPdoReadsPerDirection = 3 + kMaxPdoEntries;
constexpr std::size_t kPdoWritesPerDirection = 5 + kMaxPdoEntries;

// The downloads that turn `current` into `plan` for one direction, in ETG.1020's order, only what
// differs; none when the slave already holds the plan. Writes at most kPdoWritesPerDirection.
std::size_t pdo_mapping_writes(std::uint8_t position, const PdoMappingPlan& plan, const PdoMappingState& current,
                               SdoRequest* out, std::size_t capacity) noexcept;
// True when `current` is `plan` (assignment 1 x pdo_index, every entry, the count).
bool pdo_mapping_matches(const PdoMappingPlan& plan, const PdoMappingState& current) noexcept;

class PdoSetup {
 public:
  enum class Phase : std::uint8_t { idle, reading, writing, verifying, done, failed };

  // Starts the set-up of the slave at `position` (nullptr or an unusable plan: done at once / failed).
  // `complete_access`: the slave's SII announces SDO complete access (reads of whole objects).
  void start(std::uint8_t position, const SlavePdoPlan* plan, bool complete_access = false) noexcept;
  // The next transfer to submit (tag: kMasterTagBit | kPdoSetupTagBit | position); false while one
  // is in flight or nothing is left. Call only when the queue has room: it counts as submitted.
  [[nodiscard]] bool next(SdoRequest& out) noexcept;
  // The completion of the transfer next() gave.
  void on_completion(const SdoCompletion& done) noexcept;
  // next() gave one that could not be submitted after all: it is given again.
  void unsubmit() noexcept;

  Phase phase() const noexcept { return phase_; }
  bool finished() const noexcept { return phase_ == Phase::done || phase_ == Phase::failed || phase_ == Phase::idle; }
  bool failed() const noexcept { return phase_ == Phase::failed; }
  bool pending() const noexcept { return pending_; }
  // The transfer that failed: refused, or read back different (outcome bad_response, data = value read).
  const SdoCompletion& failure() const noexcept { return failure_; }
  std::uint16_t reads() const noexcept { return reads_; }
  std::uint16_t writes() const noexcept { return writes_; }
  // What was read before writing (outputs, inputs).
  const PdoMappingState& found(std::size_t direction) const noexcept { return found_[direction]; }

 private:
  void build_reads() noexcept;
  void after_reads() noexcept;
  void store(const SdoCompletion& done) noexcept;
  void store_complete(const SdoCompletion& done) noexcept;
  void read_single(std::uint16_t index, std::uint8_t from, std::uint8_t to) noexcept;  // appends uploads
  const PdoMappingPlan& direction_plan(std::size_t d) const noexcept { return d == 0 ? plan_->outputs : plan_->inputs; }

  // Writes of both directions, or reads: 4 complete accesses and every single read after them.
  static constexpr std::size_t kMaxList = 2 * kPdoWritesPerDirection + 4;
  const SlavePdoPlan* plan_{nullptr};
  std::uint8_t position_{0};
  bool complete_access_{false};
  Phase phase_{Phase::idle};
  std::array<SdoRequest, kMaxList> list_{};
  std::size_t count_{0};
  std::size_t next_{0};
  bool pending_{false};
  std::array<PdoMappingState, 2> state_{};
  std::array<PdoMappingState, 2> found_{};
  SdoCompletion failure_{};
  std::uint16_t reads_{0};
  std::uint16_t writes_{0};
};

}  // namespace rescue::ecat
