#include "ecat/master/bring_up_report.hpp"

#include <array>
#include <cinttypes>
#include <cstring>

#include "ecat/mailbox/coe.hpp"

namespace rescue::ecat {
namespace {

bool is_step(const char* step, const char* name) noexcept { return step != nullptr && std::strcmp(step, name) == 0; }

// The steps that request an AL state (al_control.hpp): their errors carry the slave's position and its
// AL status code (refused) or AL status (timeout).
bool is_al_step(const char* step) noexcept { return is_step(step, "INIT") || is_step(step, "PRE-OP") || is_step(step, "SAFE-OP"); }

// The numbers an error carries, said in words where the step tells what they are.
void print_numbers(std::FILE* out, const BringUpReport& r) noexcept {
  if (is_step(r.failed_step, "count") && r.error.code == Errc::timeout) {
    (void)std::fprintf(out, " (%" PRIu32 " BRDs sent, %" PRIu32 " ms waited)", r.error.detail0, r.error.detail1);
  } else if (is_step(r.failed_step, "compare") && r.error.code == Errc::mismatch) {
    (void)std::fprintf(out, " (%" PRIu32 " differences that stop the bring-up, %" PRIu32 " slaves found)", r.error.detail0,
                       r.error.detail1);
  } else if (is_step(r.failed_step, "PRE-OP SDO") && r.error.code == Errc::refused) {
    (void)std::fprintf(out, " (refused: slave at position %" PRIu32 ", object 0x%04" PRIX32 ":%02" PRIX32 ")", r.error.detail0,
                       r.error.detail1 >> 8U, r.error.detail1 & 0xFFU);
  } else if (is_al_step(r.failed_step) && r.error.code == Errc::refused) {
    (void)std::fprintf(out, " (refused: slave at position %" PRIu32 ", AL status code 0x%04" PRIx32 ")", r.error.detail0,
                       r.error.detail1);
  } else if (is_al_step(r.failed_step) && r.error.code == Errc::timeout) {
    (void)std::fprintf(out, " (timeout: slave at position %" PRIu32 ", AL status 0x%04" PRIx32 ")", r.error.detail0,
                       r.error.detail1);
  } else if (is_al_step(r.failed_step) && r.error.code == Errc::io_error) {
    (void)std::fprintf(out, " (I/O error: slave at position %" PRIu32 " does not answer)", r.error.detail0);
  } else if (is_step(r.failed_step, "OP") && r.error.code == Errc::timeout) {
    (void)std::fprintf(out, " (timeout: slave at position %" PRIu32 " not in OP)", r.error.detail0);
  } else if (is_step(r.failed_step, "ring")) {  // cable redundancy (master_bring_up.cpp, check_ring_closes)
    (void)std::fprintf(out, " (the main port reaches %" PRIu32 " slaves, the ring port %" PRIu32 ")", r.error.detail0,
                       r.error.detail1);
  } else if (r.error.detail0 != 0 || r.error.detail1 != 0) {
    (void)std::fprintf(out, " (%s; details %" PRIu32 ", %" PRIu32 ")", to_string(r.error.code), r.error.detail0, r.error.detail1);
  } else {
    (void)std::fprintf(out, " (%s)", to_string(r.error.code));
  }
}

}  // namespace

void print_bring_up_failure(std::FILE* out, const char* first_prefix, const char* prefix, Master& master) noexcept {
  const BringUpReport& r = master.report();
  if (r.failed_step == nullptr) return;
  (void)std::fprintf(out, "%sbring-up failed at %s: %s", first_prefix, r.failed_step, r.error.what);
  print_numbers(out, r);
  (void)std::fputc('\n', out);
  if (r.slaves_counted != 0) (void)std::fprintf(out, "%s%u slaves answer\n", prefix, static_cast<unsigned>(r.slaves_counted));
  std::array<char, kDifferenceLineCapacity> line{};
  for (const NetworkDifference& d : r.match.differences) {
    (void)describe(d, master.plan(), r.found.span(), line.data(), line.size());
    (void)std::fprintf(out, "%s%s\n", prefix, line.data());
  }
  if (r.al_failure.position != kNoPosition) {
    (void)describe(r.al_failure, master.plan(), line.data(), line.size());
    (void)std::fprintf(out, "%s%s\n", prefix, line.data());
  }
  if (is_step(r.failed_step, "PRE-OP SDO")) {
    const SdoCompletion& s = r.failed_sdo;
    const char* slave = s.request.position < kMaxSlaves ? master.plan()[s.request.position].name : "?";
    (void)std::fprintf(out, "%sstart-up SDO %s 0x%04X:%02X to %s: %s", prefix,
                       s.request.direction == SdoDirection::download ? "download" : "upload", s.request.index,
                       s.request.subindex, slave, to_string(s.outcome));
    if (s.outcome == SdoOutcome::aborted) {
      (void)std::fprintf(out, ", abort code 0x%08" PRIX32 " %s", s.abort_code, coe::explain_abort_code(s.abort_code));
    }
    (void)std::fputc('\n', out);
  }
  const LinkStats& link = master.link().stats();
  (void)std::fprintf(out,
                     "%slink: %" PRIu64 " exchanges, %" PRIu64 " timeouts, %" PRIu64 " late frames, %" PRIu64 " malformed\n",
                     prefix, link.exchanges, link.timeouts, link.stale_frames, link.malformed);
}

}  // namespace rescue::ecat
