// ctl states (docs/master.md "AL states on request"): the operator asks for an AL state of slaves
// that are out of service (the owner judges that; the master only carries it out), in the cyclic
// frame (never a frame of its own, never a wait), one request (a set of slaves) at a time:
//   write  FPWR 0x0120 = the state (with the error acknowledge once the slave showed an error)
//   read   FPRD 0x0130 each frame until the state is reached (done), the slave shows an error
//          after an acknowledging write and a plain one (refused, its AL status code kept), or the
//          deadline (timeout; not_answered when no read ever came back)
// A slave taken below OP this way is *parked* (SlaveRecord::parked): the online recovery leaves it
// alone (it is not searched for, not configured again, never taken back to OP behind the operator's
// back) until the operator asks for OP. OP for an operated slave, with online recovery, is no AL
// write of this service: its park is lifted and the online recovery configures it again as after
// any loss (SMs, PDO mapping, DC, SYNC0) and puts it back in the exchange; the request is done when
// it is in the exchange. (Without online recovery, or for a slave held out at bring-up, OP is
// written like the other states.) A slave the recovery is configuring (a step under way) is refused
// (recovering): nothing is written.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "ecat/codec/registers.hpp"
#include "ecat/master/cyclic_service.hpp"

namespace rescue::ecat {

enum class SlaveStateOutcome : std::uint8_t {
  reached = 0,       // AL status shows the state, no error
  refused = 1,       // AL status shows an error after the acknowledging write (al_code says why)
  timeout = 2,       // it answered but did not reach the state before the deadline
  not_answered = 3,  // no AL status read came back before the deadline (lost, cable cut)
  pending = 4,       // not finished (only while the request runs)
};

struct SlaveStateResult {
  SlaveMask slaves{0};
  reg::AlState target{reg::AlState::init};
  std::array<SlaveStateOutcome, kMaxSlaves> outcome{};
  std::array<std::uint16_t, kMaxSlaves> al_status{};  // as last read (0: none read)
  std::array<std::uint16_t, kMaxSlaves> al_code{};
  std::uint16_t frames{0};  // cyclic frames the request ran through
};

class SlaveStateService final : public CyclicService {
 public:
  // How long one request may take (an OP through the online recovery included); below ctl's
  // default 2 s wait so its answer comes first.
  static constexpr hal::Nanoseconds kDeadline = 1500 * hal::kNsPerMs;

  explicit SlaveStateService(ServiceContext& context) noexcept : ctx_(context) {}

  enum class Refusal : std::uint8_t { none, busy, bad_request, recovering, not_cycling };
  // Starts a request; Refusal::none when taken. busy: one under way or its result not taken;
  // bad_request: no slave, a slave not planned, a state other than INIT/PRE-OP/SAFE-OP/OP;
  // recovering: the online recovery is configuring one of them; not_cycling: the master is not in OP.
  [[nodiscard]] Refusal request(SlaveMask slaves, reg::AlState target) noexcept;
  // The finished request's result (once; false while none is finished).
  [[nodiscard]] bool take(SlaveStateResult& out) noexcept;
  bool busy() const noexcept { return state_ != State::idle; }
  // Slaves the operator parked below OP (the online recovery leaves them alone).
  SlaveMask parked() const noexcept;

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t tag, const DatagramView& datagram) noexcept override;
  void settle(CycleResult& result) noexcept override;

 private:
  enum class State : std::uint8_t { idle, running, done };
  enum class Step : std::uint8_t { write, read, acknowledge, by_recovery };
  static constexpr std::uint8_t kWriteTag = 0x80;  // tag bit: the AL control write (else the status read)

  ServiceContext& ctx_;
  State state_{State::idle};
  SlaveStateResult result_{};
  std::array<Step, kMaxSlaves> step_{};
  std::array<std::uint8_t, kMaxSlaves> errors_{};  // AL status reads with the error bit (acknowledge, ask, refused)
  hal::Nanoseconds deadline_{0};
};

}  // namespace rescue::ecat
