// bench wcet's socket handler (docs/timing.md "Worst-path scenarios"): the real SocketHandler on
// 127.0.0.1 (ephemeral ports), fed authenticated operator datagrams by a client socket in the same
// thread. Under `flood` each period queues the most one wake-up handles (SocketHandler::kBudget,
// config::kSocketDatagramsPerWakeup) of the heaviest verbs before the wake-up: status, slaves,
// slaves -v, graph, tasks, diag, sii_read chunks, and one segmented SDO transfer at a time (a
// 160-byte label downloaded then uploaded, on the next joint each time: the `services` scenario's SDO path). Quiet,
// one status request per period (an operator polling ctl status). The client's side (sealing,
// sending, draining the answers) runs outside the measured period.
#pragma once

#include <cstdint>

#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/replay_window.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "hal/net/udp_socket.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app {

class WcetOperatorLoad {
 public:
  explicit WcetOperatorLoad(const SocketHandlerPorts& ports) noexcept;
  // Binds the handler's ports and the client's on 127.0.0.1; its error names the cause.
  Status open() noexcept;

  // Before the period: the datagrams of this period queued on the control port.
  void before(bool flood) noexcept;
  // After the period: the answers taken from the client's socket.
  void after() noexcept;

  SocketHandler& handler() noexcept { return handler_; }
  const SocketHandler& handler() const noexcept { return handler_; }
  std::uint64_t datagrams_sent() const noexcept { return sent_; }
  std::uint64_t answers() const noexcept { return answers_; }
  // SDO transfers ended (answered other than `busy`), and of those the ones answered ok.
  std::uint64_t sdo_transfers() const noexcept { return sdo_ended_; }
  std::uint64_t sdo_transfers_ok() const noexcept { return sdo_done_; }
  std::uint64_t send_failures() const noexcept { return send_failures_; }

 private:
  void send(protocol::Message m) noexcept;
  protocol::Message next_heavy() noexcept;

  protocol::ReplayWindow window_;
  hal::ManualWallClock wall_;
  protocol::Key key_{};
  SocketHandler handler_;
  hal::UdpSocket client_;
  std::uint32_t loopback_{0};
  std::uint64_t in_period_{0};  // datagrams sent this period (the sequence's offset)
  std::uint64_t verb_{0};
  std::uint64_t sdo_{0};
  std::uint64_t sent_{0};
  std::uint64_t answers_{0};
  std::uint64_t sdo_done_{0};
  std::uint64_t sdo_ended_{0};
  bool sdo_in_flight_{false};
  std::uint64_t send_failures_{0};
};

// The measured period: out of line, with a stable name, for callgrind's --toggle-collect; marks its end
// for toolchain/wcet/instructions.sh (core/app/tasks/period_mark.hpp).
void wcet_socket_handler_period(SocketHandler& handler, hal::Nanoseconds now) noexcept;

}  // namespace rescue::app
