#include "ecat/master/pdo_setup.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint32_t kTag = MailboxClient::kMasterTagBit | kPdoSetupTagBit;

bool known(const PdoMappingState& s, std::size_t k) noexcept { return (s.unknown & (1U << k)) == 0; }

bool assignment_matches(const PdoMappingPlan& plan, const PdoMappingState& s) noexcept {
  return known(s, 0) && s.assign_count == 1 && known(s, 1) && s.assigned == plan.pdo_index;
}

bool entries_match(const PdoMappingPlan& plan, const PdoMappingState& s) noexcept {
  if (!known(s, 2) || s.entry_count != plan.entry_count) return false;
  for (std::size_t i = 0; i < plan.entry_count && i < kMaxPdoEntries; ++i) {
    if (!known(s, 3 + i) || s.entries[i] != plan.entries[i]) return false;
  }
  return true;
}

}  // namespace

bool pdo_mapping_matches(const PdoMappingPlan& plan, const PdoMappingState& current) noexcept {
  return assignment_matches(plan, current) && entries_match(plan, current);
}

std::size_t pdo_mapping_writes(std::uint8_t position, const PdoMappingPlan& plan, const PdoMappingState& current,
                               SdoRequest* out, std::size_t capacity) noexcept {
  if (plan.entry_count > kMaxPdoEntries || capacity < kPdoWritesPerDirection) return 0;
  const bool map_ok = entries_match(plan, current);
  if (map_ok && assignment_matches(plan, current)) return 0;
  std::size_t n = 0;
  // The PDO may be changed only while it is not assigned: the assignment count goes to 0 first.
  if (!known(current, 0) || current.assign_count != 0) out[n++] = sdo_download(position, plan.assign_index, 0, 0, 1, kTag);
  if (!map_ok) {
    if (!known(current, 2) || current.entry_count != 0) out[n++] = sdo_download(position, plan.pdo_index, 0, 0, 1, kTag);
    for (std::size_t i = 0; i < plan.entry_count; ++i) {
      if (known(current, 3 + i) && current.entries[i] == plan.entries[i]) continue;
      out[n++] = sdo_download(position, plan.pdo_index, static_cast<std::uint8_t>(i + 1), plan.entries[i], 4, kTag);
    }
    // The entry count last: the slave checks the whole mapping when it is written.
    out[n++] = sdo_download(position, plan.pdo_index, 0, plan.entry_count, 1, kTag);
  }
  if (!known(current, 1) || current.assigned != plan.pdo_index) {
    out[n++] = sdo_download(position, plan.assign_index, 1, plan.pdo_index, 2, kTag);
  }
  out[n++] = sdo_download(position, plan.assign_index, 0, 1, 1, kTag);  // the assignment count last
  return n;
}

void PdoSetup::start(std::uint8_t position, const SlavePdoPlan* plan, bool complete_access) noexcept {
  plan_ = plan;
  position_ = position;
  complete_access_ = complete_access;
  count_ = 0;
  next_ = 0;
  pending_ = false;
  reads_ = 0;
  writes_ = 0;
  failure_ = SdoCompletion{};
  state_ = {};
  found_ = {};
  if (plan == nullptr) {
    phase_ = Phase::done;
    return;
  }
  if (plan->outputs.entry_count > kMaxPdoEntries || plan->inputs.entry_count > kMaxPdoEntries) {
    failure_.request = sdo_download(position, plan->outputs.pdo_index, 0, 0, 1, kTag);
    failure_.outcome = SdoOutcome::bad_response;
    phase_ = Phase::failed;
    return;
  }
  phase_ = Phase::reading;
  build_reads();
}

void PdoSetup::build_reads() noexcept {
  count_ = 0;
  next_ = 0;
  for (std::size_t d = 0; d < 2; ++d) {
    const PdoMappingPlan& m = direction_plan(d);
    state_[d] = PdoMappingState{};
    if (complete_access_) {
      for (const std::uint16_t index : {m.assign_index, m.pdo_index}) {
        list_[count_] = sdo_upload(position_, index, 0, kTag);
        list_[count_++].complete_access = true;
      }
      continue;
    }
    read_single(m.assign_index, 0, 1);
    read_single(m.pdo_index, 0, static_cast<std::uint8_t>(m.entry_count));
  }
}

void PdoSetup::read_single(std::uint16_t index, std::uint8_t from, std::uint8_t to) noexcept {
  for (unsigned sub = from; sub <= to && count_ < list_.size(); ++sub) {
    list_[count_++] = sdo_upload(position_, index, static_cast<std::uint8_t>(sub), kTag);
  }
}

void PdoSetup::store_complete(const SdoCompletion& done) noexcept {
  // SI0 as 16 bits (its 8-bit value, then 0), then subindexes 1..SI0 back to back: 16-bit PDO
  // indexes in an assignment, 32-bit entries in a mapping. What it does not hold is read singly.
  const std::uint16_t index = done.request.index;
  const bool ok = done.outcome == SdoOutcome::ok && done.size >= 2;
  const std::size_t count = ok ? done.data[0] : 0;
  for (std::size_t d = 0; d < 2; ++d) {
    const PdoMappingPlan& m = direction_plan(d);
    PdoMappingState& s = state_[d];
    if (index == m.assign_index) {
      if (!ok) {
        read_single(index, 0, 1);
        return;
      }
      s.assign_count = static_cast<std::uint32_t>(count);
      if (count >= 1 && done.size >= 4) {
        s.assigned = load_le16(done.data.data() + 2);
      } else {
        read_single(index, 1, 1);
      }
      return;
    }
    if (index == m.pdo_index) {
      if (!ok) {
        read_single(index, 0, static_cast<std::uint8_t>(m.entry_count));
        return;
      }
      s.entry_count = static_cast<std::uint32_t>(count);
      std::size_t given = 0;
      while (given < m.entry_count && given < count && 2 + 4 * (given + 1) <= done.size) {
        s.entries[given] = load_le32(done.data.data() + 2 + 4 * given);
        ++given;
      }
      if (given < m.entry_count) read_single(index, static_cast<std::uint8_t>(given + 1), static_cast<std::uint8_t>(m.entry_count));
      return;
    }
  }
}

bool PdoSetup::next(SdoRequest& out) noexcept {
  if (pending_ || finished() || next_ >= count_) return false;
  out = list_[next_++];
  pending_ = true;
  return true;
}

void PdoSetup::unsubmit() noexcept {
  if (!pending_ || next_ == 0) return;
  --next_;
  pending_ = false;
}

void PdoSetup::store(const SdoCompletion& done) noexcept {
  for (std::size_t d = 0; d < 2; ++d) {
    const PdoMappingPlan& m = direction_plan(d);
    PdoMappingState& s = state_[d];
    std::size_t k = kPdoReadsPerDirection;
    std::uint32_t* value = nullptr;
    if (done.request.index == m.assign_index && done.request.subindex <= 1) {
      k = done.request.subindex;
      value = done.request.subindex == 0 ? &s.assign_count : &s.assigned;
    } else if (done.request.index == m.pdo_index && done.request.subindex == 0) {
      k = 2;
      value = &s.entry_count;
    } else if (done.request.index == m.pdo_index && done.request.subindex <= kMaxPdoEntries) {
      k = 2U + done.request.subindex;
      value = &s.entries[done.request.subindex - 1U];
    }
    if (value == nullptr) continue;
    if (done.outcome == SdoOutcome::ok) {
      *value = sdo_value(done);
    } else {
      s.unknown |= 1U << k;
    }
  }
}

void PdoSetup::on_completion(const SdoCompletion& done) noexcept {
  if (!pending_ || finished()) return;
  pending_ = false;
  const bool upload = done.request.direction == SdoDirection::upload;
  if (upload) {
    ++reads_;
  } else {
    ++writes_;
  }
  // A refused write, or a read that did not come back (an aborted read only says "differs" while
  // reading; an aborted complete access is read again one subindex at a time).
  const bool aborted_whole = done.request.complete_access && done.outcome == SdoOutcome::aborted;
  const bool refused = done.outcome != SdoOutcome::ok && !aborted_whole &&
                       (!upload || phase_ == Phase::verifying || done.outcome != SdoOutcome::aborted);
  if (refused) {
    failure_ = done;
    phase_ = Phase::failed;
    return;
  }
  if (upload && done.request.complete_access) {
    store_complete(done);
  } else if (upload) {
    store(done);
  }
  if (next_ < count_) return;
  switch (phase_) {
    case Phase::reading: after_reads(); break;
    case Phase::writing:
      phase_ = Phase::verifying;
      build_reads();
      break;
    case Phase::verifying: {
      for (std::size_t d = 0; d < 2; ++d) {
        const PdoMappingPlan& m = direction_plan(d);
        if (pdo_mapping_matches(m, state_[d])) continue;
        // Read back different from what was written: named by the object that differs.
        failure_ = SdoCompletion{};
        failure_.outcome = SdoOutcome::bad_response;
        const bool assignment = !assignment_matches(m, state_[d]);
        failure_.request = sdo_upload(position_, assignment ? m.assign_index : m.pdo_index, 0, kTag);
        phase_ = Phase::failed;
        return;
      }
      phase_ = Phase::done;
      break;
    }
    default: break;
  }
}

void PdoSetup::after_reads() noexcept {
  found_ = state_;
  count_ = 0;
  next_ = 0;
  for (std::size_t d = 0; d < 2; ++d) {
    count_ += pdo_mapping_writes(position_, direction_plan(d), state_[d], list_.data() + count_, list_.size() - count_);
  }
  phase_ = count_ == 0 ? Phase::done : Phase::writing;
}

}  // namespace rescue::ecat
