// The socket handler's side of an operator request it relays to the EtherCAT handler and answers
// when the result comes back (ctl states, ctl rescan): one in flight at a time, matched to its
// result by an id (a result of a request already answered no_answer is dropped), given up at its
// deadline. Fixed size, no heap, no locks.
#pragma once

#include <cstdint>

#include "core/concurrency/message_port.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

// LinkRequest has an `id`; LinkResult an `id` too.
template <typename LinkRequest, typename LinkResult>
class RelayedRequest {
 public:
  enum class Collected : std::uint8_t { nothing, result, expired };

  bool active() const noexcept { return active_; }
  // Sends `request` (its id set here) to the EtherCAT handler; false (nothing in flight) when the
  // queue is full. The answer goes to `address`:`port` for the datagram of `request_sequence`.
  [[nodiscard]] bool start(MessageSink<LinkRequest>& sink, LinkRequest request, std::uint64_t request_sequence,
                           std::uint32_t address, std::uint16_t port, hal::Nanoseconds deadline) noexcept {
    request.id = ++ids_;
    if (!sink.try_send(request)) return false;
    active_ = true;
    id_ = request.id;
    request_sequence_ = request_sequence;
    address_ = address;
    port_ = port;
    deadline_ = deadline;
    return true;
  }
  // The in-flight request's result into `out` (result), or its deadline passed (expired); either
  // ends it. Results of earlier requests are taken and dropped.
  Collected collect(MessageSource<LinkResult>& source, LinkResult& out, hal::Nanoseconds now) noexcept {
    while (source.try_receive(out)) {
      if (!active_ || out.id != id_) continue;
      active_ = false;
      return Collected::result;
    }
    if (active_ && now > deadline_) {
      active_ = false;
      return Collected::expired;
    }
    return Collected::nothing;
  }
  std::uint64_t request_sequence() const noexcept { return request_sequence_; }
  std::uint32_t address() const noexcept { return address_; }
  std::uint16_t port() const noexcept { return port_; }

 private:
  bool active_{false};
  std::uint32_t ids_{0};
  std::uint32_t id_{0};
  std::uint64_t request_sequence_{0};
  std::uint32_t address_{0};
  std::uint16_t port_{0};
  hal::Nanoseconds deadline_{0};
};

}  // namespace rescue::app
