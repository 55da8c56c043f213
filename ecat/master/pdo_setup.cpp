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

void PdoSetup::start(std::uint8_t position, const SlavePdoPlan* plan) noexcept {
  plan_ = plan;
  position_ = position;
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
    list_[count_++] = sdo_upload(position_, m.assign_index, 0, kTag);
    list_[count_++] = sdo_upload(position_, m.assign_index, 1, kTag);
    list_[count_++] = sdo_upload(position_, m.pdo_index, 0, kTag);
    for (std::size_t i = 0; i < m.entry_count; ++i) {
      list_[count_++] = sdo_upload(position_, m.pdo_index, static_cast<std::uint8_t>(i + 1), kTag);
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
  // A refused write, or a read that did not come back (an aborted read only says "differs" while reading).
  const bool refused = done.outcome != SdoOutcome::ok &&
                       (!upload || phase_ == Phase::verifying || done.outcome != SdoOutcome::aborted);
  if (refused) {
    failure_ = done;
    phase_ = Phase::failed;
    return;
  }
  if (upload) store(done);
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
