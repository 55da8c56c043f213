// A non-blocking IPv4 UDP socket for the socket handler (docs/protocol.md) and the operator client:
// bind, receive a bounded batch per call (recvmmsg), send one datagram. Received datagrams land in
// the caller's fixed buffers; one longer than a buffer is flagged truncated (MSG_TRUNC), never
// read beyond it. No heap.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"

namespace rescue::hal {

constexpr std::size_t kUdpBufferSize = 2048;

struct UdpDatagram {
  std::array<std::uint8_t, kUdpBufferSize> bytes{};
  std::size_t size{0};       // bytes in `bytes`
  bool truncated{false};     // the datagram was longer than the buffer
  std::uint32_t address{0};  // source IPv4, network byte order
  std::uint16_t port{0};     // source port, host byte order
};

class UdpSocket {
 public:
  UdpSocket() = default;
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;
  UdpSocket(UdpSocket&&) = delete;
  UdpSocket& operator=(UdpSocket&&) = delete;
  ~UdpSocket();

  // Binds `address` (dotted IPv4) : `port` (0: any free port). Errors name the cause (errno in detail0).
  Status open(const char* address, std::uint16_t port) noexcept;
  void close() noexcept;
  bool is_open() const noexcept { return fd_ >= 0; }
  int fd() const noexcept { return fd_; }
  std::uint16_t local_port() const noexcept;

  // Up to out.size() datagrams already queued (never waits); returns how many.
  std::size_t receive_batch(Span<UdpDatagram> out) noexcept;
  // Waits at most `timeout_ms` for a datagram (poll); true when one is queued.
  bool wait_readable(int timeout_ms) const noexcept;
  Status send_to(std::uint32_t address, std::uint16_t port, ConstByteSpan bytes) noexcept;

 private:
  int fd_{-1};
};

// Dotted IPv4 text to network byte order; malformed on anything else.
Result<std::uint32_t> parse_ipv4(const char* text) noexcept;

}  // namespace rescue::hal
