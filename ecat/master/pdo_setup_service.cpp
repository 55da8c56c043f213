// Recovering slaves' PDO mappings and start-up SDOs through the cyclic mailbox channel.
#include "ecat/master/pdo_setup_service.hpp"

namespace rescue::ecat {
namespace {

constexpr hal::Nanoseconds kSdoResponseTimeout = 100 * hal::kNsPerMs;  // MailboxClient's default

}  // namespace

void PdoSetupService::start(std::size_t p) noexcept {
  RecoveryProgress& r = ctx_.slaves[p].recovery;
  r.sdos_pending = 0;
  r.sdo_next = 0;
  r.sdo_refused = false;
  ctx_.slaves[p].pdo.start(static_cast<std::uint8_t>(p), ctx_.plan[p].mailbox ? ctx_.plan[p].pdo : nullptr,
                           ctx_.slaves[p].setup.complete_access);
  feed(p);
}

void PdoSetupService::feed(std::size_t p) noexcept {
  RecoveryProgress& r = ctx_.slaves[p].recovery;
  if (r.state() != RecoveryState::startup_sdos || r.sdo_refused || r.sdos_pending != 0 || mailbox_.free_slots() == 0) return;
  PdoSetup& mapping = ctx_.slaves[p].pdo;
  if (mapping.failed()) {
    r.sdo_refused = true;
    return;
  }
  SdoRequest request;
  bool have = false;
  if (!mapping.finished()) {
    if (mapping.pending()) return;
    have = mapping.next(request);
  } else {
    const Span<const SdoRequest> sdos = ctx_.options.startup_sdos;
    while (!have && r.sdo_next < sdos.size()) {
      request = sdos[r.sdo_next++];
      if (request.position != p) continue;
      request.tag = MailboxClient::kMasterTagBit | static_cast<std::uint32_t>(p);
      have = true;
    }
  }
  if (!have) return;
  const std::size_t ahead = MailboxClient::kQueueCapacity - mailbox_.free_slots();
  if (!mailbox_.submit(request)) {
    if (!mapping.finished()) mapping.unsubmit();
    if ((request.tag & kPdoSetupTagBit) == 0 && r.sdo_next > 0) --r.sdo_next;
    return;  // waits its turn
  }
  if ((request.tag & kPdoSetupTagBit) == 0) r.sdos_pending = 1;
  // Transfers of other slaves queued before this one each may take their response timeout
  // (one that vanished meanwhile): waiting for them is not this slave's failure.
  r.deadline = ctx_.now() + ctx_.options.recovery_step_timeout + static_cast<hal::Nanoseconds>(ahead) * kSdoResponseTimeout;
}

bool PdoSetupService::done(std::size_t p) const noexcept {
  const RecoveryProgress& r = ctx_.slaves[p].recovery;
  const PdoSetup& mapping = ctx_.slaves[p].pdo;
  if (r.sdo_refused || r.sdos_pending != 0 || !mapping.finished() || mapping.failed()) return false;
  const Span<const SdoRequest> sdos = ctx_.options.startup_sdos;
  for (std::size_t i = r.sdo_next; i < sdos.size(); ++i) {
    if (sdos[i].position == p) return false;
  }
  return true;
}

void PdoSetupService::settle(CycleResult& /*result*/) noexcept {
  if (ctx_.state != MasterState::op || !ctx_.options.online_recovery) return;
  // Completions of the recovery's start-up SDOs, then the next ones in (paced: a transfer that
  // does not fit the queue waits its turn).
  SdoCompletion completion;
  while (mailbox_.pop_master_completion(completion)) {
    const std::size_t p = completion.request.position;
    if (p >= kMaxSlaves || ctx_.slaves[p].recovery.state() != RecoveryState::startup_sdos) continue;
    RecoveryProgress& r = ctx_.slaves[p].recovery;
    if ((completion.request.tag & kPdoSetupTagBit) != 0) {
      ctx_.slaves[p].pdo.on_completion(completion);
      if (ctx_.slaves[p].pdo.failed()) r.sdo_refused = true;
    } else {
      r.sdos_pending = 0;
      if (completion.outcome != SdoOutcome::ok) r.sdo_refused = true;
    }
  }
  for (std::size_t i = 0; i < kMaxSlaves; ++i) feed((rotate_ + i) % kMaxSlaves);
  rotate_ = (rotate_ + 1) % kMaxSlaves;
}

}  // namespace rescue::ecat
