#include "hal/net/udp_socket.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

namespace rescue::hal {
namespace {

constexpr std::size_t kMaxBatch = 64;

}  // namespace

UdpSocket::~UdpSocket() { close(); }

void UdpSocket::close() noexcept {
  if (fd_ >= 0) (void)::close(fd_);
  fd_ = -1;
}

Result<std::uint32_t> parse_ipv4(const char* text) noexcept {
  in_addr a{};
  if (text == nullptr || ::inet_pton(AF_INET, text, &a) != 1) return make_error(Errc::malformed, "not an IPv4 address");
  return static_cast<std::uint32_t>(a.s_addr);
}

Status UdpSocket::open(const char* address, std::uint16_t port) noexcept {
  close();
  const Result<std::uint32_t> ip = parse_ipv4(address);
  if (!ip.ok()) return ip.error();
  const int sock = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (sock < 0) return make_error(Errc::io_error, "cannot create a UDP socket", static_cast<std::uint32_t>(errno));
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_port = htons(port);
  sa.sin_addr.s_addr = ip.value();
  if (::bind(sock, reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0) {  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
    const int e = errno;
    (void)::close(sock);
    return make_error(e == EADDRINUSE ? Errc::busy : Errc::io_error, "cannot bind the UDP port", static_cast<std::uint32_t>(e), port);
  }
  fd_ = sock;
  return Status::success();
}

std::uint16_t UdpSocket::local_port() const noexcept {
  sockaddr_in sa{};
  socklen_t len = sizeof sa;
  if (fd_ < 0 || ::getsockname(fd_, reinterpret_cast<sockaddr*>(&sa), &len) != 0) return 0;  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  return ntohs(sa.sin_port);
}

// Not const: receiving consumes the socket's queue (the object stands for the socket).
// NOLINTNEXTLINE(readability-make-member-function-const)
std::size_t UdpSocket::receive_batch(Span<UdpDatagram> out) noexcept {
  if (fd_ < 0 || out.size() == 0) return 0;
  const std::size_t n = std::min(out.size(), kMaxBatch);
  std::array<mmsghdr, kMaxBatch> headers{};
  std::array<iovec, kMaxBatch> iov{};
  std::array<sockaddr_in, kMaxBatch> from{};
  for (std::size_t i = 0; i < n; ++i) {
    iov[i].iov_base = out[i].bytes.data();
    iov[i].iov_len = out[i].bytes.size();
    headers[i].msg_hdr.msg_iov = &iov[i];
    headers[i].msg_hdr.msg_iovlen = 1;
    headers[i].msg_hdr.msg_name = &from[i];
    headers[i].msg_hdr.msg_namelen = sizeof from[i];
  }
  const int got = ::recvmmsg(fd_, headers.data(), static_cast<unsigned>(n), MSG_DONTWAIT, nullptr);
  if (got <= 0) return 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(got); ++i) {
    out[i].truncated = (headers[i].msg_hdr.msg_flags & MSG_TRUNC) != 0;
    out[i].size = headers[i].msg_len < out[i].bytes.size() ? headers[i].msg_len : out[i].bytes.size();
    out[i].address = from[i].sin_addr.s_addr;
    out[i].port = ntohs(from[i].sin_port);
  }
  return static_cast<std::size_t>(got);
}

bool UdpSocket::wait_readable(int timeout_ms) const noexcept {
  pollfd p{fd_, POLLIN, 0};
  return fd_ >= 0 && ::poll(&p, 1, timeout_ms) > 0 && (p.revents & POLLIN) != 0;
}

// Not const: sending changes the socket's state (its queue, its errors).
// NOLINTNEXTLINE(readability-make-member-function-const)
Status UdpSocket::send_to(std::uint32_t address, std::uint16_t port, ConstByteSpan bytes) noexcept {
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_port = htons(port);
  sa.sin_addr.s_addr = address;
  const ssize_t n = ::sendto(fd_, bytes.data(), bytes.size(), MSG_DONTWAIT,
                             reinterpret_cast<const sockaddr*>(&sa), sizeof sa);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  if (n < 0) return make_error(Errc::io_error, "cannot send the UDP datagram", static_cast<std::uint32_t>(errno));
  return Status::success();
}

}  // namespace rescue::hal
