#include "hal/net/raw_socket_nic.hpp"

#include <arpa/inet.h>
#include <linux/filter.h>
#include <linux/if_ether.h>
#include <linux/if_packet.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <ctime>

#include "core/base/endian.hpp"

namespace rescue::hal {
namespace {

// Same value as ecat::kEtherTypeEtherCAT; hal sits below ecat and cannot include it.
constexpr std::uint16_t kEtherTypeEtherCAT = 0x88A4;
constexpr std::uint16_t kEtherTypeVlan = 0x8100;
constexpr std::size_t kEthernetHeaderSize = 14;
constexpr std::size_t kMaxFrameSize = 1514;

#ifndef PACKET_IGNORE_OUTGOING
constexpr int PACKET_IGNORE_OUTGOING = 23;  // NOLINT(readability-identifier-naming): kernel name, older headers lack it
#endif

// Linux defines EWOULDBLOCK as EAGAIN; testing both trips -Wlogical-op.
static_assert(EAGAIN == EWOULDBLOCK, "EAGAIN is the only would-block errno checked");

std::uint32_t errno_value() noexcept { return static_cast<std::uint32_t>(errno); }

Error os_error(const char* what) noexcept {
  const int e = errno;
  if (e == EPERM || e == EACCES) {
    return make_error(Errc::permission_denied,
                      "raw sockets need CAP_NET_RAW: run as root, or give the binary the capability "
                      "with `setcap cap_net_raw+ep rescue-motion`",
                      errno_value());
  }
  return make_error(Errc::io_error, what, errno_value());
}

Status set_int_option(int fd, int level, int option, int value, const char* what) noexcept {
  if (::setsockopt(fd, level, option, &value, sizeof value) != 0) return os_error(what);
  return Status::success();
}

// The kernel moves a received frame's 802.1Q tag into metadata (PACKET_AUXDATA); this puts it back
// between the source address and the EtherType so the frame reads as it was on the wire. False when
// the tagged frame would not fit the buffer.
bool restore_vlan_tag(msghdr& message, ByteSpan buffer, std::size_t& length) noexcept {
  for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
    if (c->cmsg_level != SOL_PACKET || c->cmsg_type != PACKET_AUXDATA) continue;
    if (c->cmsg_len < CMSG_LEN(sizeof(tpacket_auxdata))) continue;
    tpacket_auxdata aux{};
    std::memcpy(&aux, CMSG_DATA(c), sizeof aux);
    if ((aux.tp_status & TP_STATUS_VLAN_VALID) == 0) return true;
    if (length < 12 || length + 4 > buffer.size()) return false;
    const auto tpid = static_cast<std::uint16_t>((aux.tp_status & TP_STATUS_VLAN_TPID_VALID) != 0 ? aux.tp_vlan_tpid
                                                                                                : kEtherTypeVlan);
    std::memmove(buffer.data() + 16, buffer.data() + 12, length - 12);
    store_be16(buffer.data() + 12, tpid);
    store_be16(buffer.data() + 14, aux.tp_vlan_tci);
    length += 4;
    return true;
  }
  return true;
}

// Classic BPF run by the kernel on every frame of the interface: keep those whose protocol is
// EtherCAT. SKF_AD_PROTOCOL is the protocol after the kernel took a VLAN tag out, so tagged
// EtherCAT frames pass too; our own outgoing frames carry the bound ETH_P_ALL and never do.
Status attach_ethercat_filter(int fd) noexcept {
  sock_filter program[] = {
      BPF_STMT(BPF_LD | BPF_H | BPF_ABS, static_cast<std::uint32_t>(SKF_AD_OFF + SKF_AD_PROTOCOL)),
      BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, kEtherTypeEtherCAT, 0, 1),
      BPF_STMT(BPF_RET | BPF_K, 0xFFFFU),  // accept: the whole frame
      BPF_STMT(BPF_RET | BPF_K, 0),        // drop
  };
  sock_fprog filter{};
  filter.len = static_cast<unsigned short>(sizeof program / sizeof program[0]);
  filter.filter = program;
  if (::setsockopt(fd, SOL_SOCKET, SO_ATTACH_FILTER, &filter, sizeof filter) != 0) {
    return os_error("setsockopt(SO_ATTACH_FILTER) for EtherType 0x88A4 failed");
  }
  return Status::success();
}

// The kernel's receive timestamp (SO_TIMESTAMPNS, CLOCK_REALTIME) in the control messages; false
// when the frame has none.
bool find_receive_timestamp(msghdr& message, Nanoseconds& realtime) noexcept {
  for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
    if (c->cmsg_level != SOL_SOCKET || c->cmsg_type != SCM_TIMESTAMPNS) continue;
    if (c->cmsg_len < CMSG_LEN(sizeof(timespec))) continue;
    timespec stamp{};
    std::memcpy(&stamp, CMSG_DATA(c), sizeof stamp);
    if (stamp.tv_sec == 0 && stamp.tv_nsec == 0) return false;  // stamping not on yet
    realtime = static_cast<Nanoseconds>(stamp.tv_sec) * kNsPerSec + stamp.tv_nsec;
    return true;
  }
  return false;
}

Nanoseconds realtime_now() noexcept {
  timespec ts{};
  (void)::clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<Nanoseconds>(ts.tv_sec) * kNsPerSec + ts.tv_nsec;
}

timespec to_timespec(Nanoseconds ns) noexcept {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / kNsPerSec);
  ts.tv_nsec = static_cast<long>(ns % kNsPerSec);
  return ts;
}

}  // namespace

bool is_ethercat_frame(ConstByteSpan frame) noexcept {
  if (frame.size() < kEthernetHeaderSize) return false;
  const std::uint16_t type = load_be16(frame.data() + 12);
  if (type == kEtherTypeEtherCAT) return true;
  return type == kEtherTypeVlan && frame.size() >= kEthernetHeaderSize + 4 &&
         load_be16(frame.data() + 16) == kEtherTypeEtherCAT;
}

RawSocketNic::~RawSocketNic() { close(); }

void RawSocketNic::close() noexcept {
  // Closing drops the promiscuous membership too: the kernel counts it per socket.
  if (fd_ >= 0) (void)::close(fd_);
  fd_ = -1;
}

Status RawSocketNic::open(const char* interface_name, const RawSocketSettings& settings) noexcept {
  if (fd_ >= 0) return make_error(Errc::invalid_argument, "raw socket NIC already open");
  if (interface_name == nullptr || interface_name[0] == '\0') {
    return make_error(Errc::invalid_argument, "empty interface name");
  }
  const std::size_t length = std::strlen(interface_name);
  if (length > kMaxInterfaceNameLength) {
    return make_error(Errc::invalid_argument, "interface name longer than 15 characters",
                      static_cast<std::uint32_t>(length));
  }
  const Status status = configure(interface_name, settings);
  if (!status.ok()) {
    close();
    return status;
  }
  set_receive_spin(settings.receive_spin);
  set_receive_wait(settings.receive_wait, settings.adaptive_lead);
  std::memcpy(name_.data(), "raw:", 4);
  std::memcpy(name_.data() + 4, interface_name, length + 1);
  return Status::success();
}

Status RawSocketNic::configure(const char* interface_name, const RawSocketSettings& settings) noexcept {
  features_ = RawSocketFeatures{};
  // Before socket(): a missing interface is the more useful message even without privileges.
  const unsigned index = ::if_nametoindex(interface_name);
  if (index == 0) {
    return make_error(Errc::not_found, "no such network interface in this namespace (see `ip link`)", errno_value());
  }
  features_.interface_index = static_cast<int>(index);

  // Protocol 0: the socket receives nothing until bind() names the interface, so no frame of
  // another interface can slip in between socket() and bind().
  fd_ = ::socket(AF_PACKET, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) return os_error("socket(AF_PACKET, SOCK_RAW) failed");

  ifreq request{};
  std::memcpy(request.ifr_name, interface_name, std::strlen(interface_name) + 1);
  if (::ioctl(fd_, SIOCGIFFLAGS, &request) != 0) return os_error("ioctl(SIOCGIFFLAGS) failed");
  if ((request.ifr_flags & IFF_UP) == 0) {
    return make_error(Errc::refused, "interface is down (bring it up: `ip link set IFACE up`)");
  }
  if (::ioctl(fd_, SIOCGIFHWADDR, &request) != 0) return os_error("ioctl(SIOCGIFHWADDR) failed");
  for (std::size_t i = 0; i < features_.hardware_address.size(); ++i) {
    features_.hardware_address[i] = static_cast<std::uint8_t>(request.ifr_hwaddr.sa_data[i]);
  }

  // Optional: without it, receive() drops PACKET_OUTGOING frames itself (only ETH_P_ALL sockets
  // see outgoing frames at all).
  features_.ignore_outgoing = set_int_option(fd_, SOL_PACKET, PACKET_IGNORE_OUTGOING, 1, "").ok();
  RESCUE_TRY(set_int_option(fd_, SOL_PACKET, PACKET_AUXDATA, 1, "setsockopt(PACKET_AUXDATA) failed"));
  if (settings.qdisc_bypass) {
    RESCUE_TRY(set_int_option(fd_, SOL_PACKET, PACKET_QDISC_BYPASS, 1, "setsockopt(PACKET_QDISC_BYPASS) failed"));
    features_.qdisc_bypass = true;
  }
  // SO_RCVBUFFORCE passes rmem_max when we have CAP_NET_ADMIN; plain SO_RCVBUF otherwise.
  if (!set_int_option(fd_, SOL_SOCKET, SO_RCVBUFFORCE, settings.receive_buffer_bytes, "").ok()) {
    RESCUE_TRY(set_int_option(fd_, SOL_SOCKET, SO_RCVBUF, settings.receive_buffer_bytes,
                              "setsockopt(SO_RCVBUF) failed"));
  }
  int granted = 0;
  socklen_t granted_size = sizeof granted;
  if (::getsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &granted, &granted_size) == 0) features_.receive_buffer_bytes = granted;
  if (settings.receive_timestamps) {
    RESCUE_TRY(set_int_option(fd_, SOL_SOCKET, SO_TIMESTAMPNS, 1, "setsockopt(SO_TIMESTAMPNS) failed"));
    features_.receive_timestamps = true;
  }

  // Every EtherType is bound (ETH_P_ALL) because only such taps get a received frame's VLAN tag:
  // the kernel clears it before protocol-specific sockets see the frame. EtherCAT-only is then the
  // kernel filter below, attached before bind() so no other frame is ever queued.
  if (settings.capture == RawSocketSettings::Capture::ethercat_only) {
    RESCUE_TRY(attach_ethercat_filter(fd_));
  }
  sockaddr_ll address{};
  address.sll_family = AF_PACKET;
  address.sll_protocol = htons(static_cast<std::uint16_t>(ETH_P_ALL));
  address.sll_ifindex = static_cast<int>(index);
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API takes sockaddr*
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    return os_error("bind(AF_PACKET) to the interface failed");
  }

  if (settings.promiscuous) {
    packet_mreq membership{};
    membership.mr_ifindex = static_cast<int>(index);
    membership.mr_type = PACKET_MR_PROMISC;
    if (::setsockopt(fd_, SOL_PACKET, PACKET_ADD_MEMBERSHIP, &membership, sizeof membership) != 0) {
      return os_error("setsockopt(PACKET_ADD_MEMBERSHIP, PACKET_MR_PROMISC) failed");
    }
    features_.promiscuous = true;
  }
  return Status::success();
}

Status RawSocketNic::send(ConstByteSpan frame) noexcept {
  if (fd_ < 0) return make_error(Errc::invalid_argument, "raw socket NIC not open");
  if (frame.size() < kEthernetHeaderSize || frame.size() > kMaxFrameSize) {
    ++stats_.send_errors;
    return make_error(Errc::invalid_argument, "frame length outside 14..1514", static_cast<std::uint32_t>(frame.size()));
  }
  for (;;) {
    const ssize_t sent = ::send(fd_, frame.data(), frame.size(), MSG_DONTWAIT);
    if (sent == static_cast<ssize_t>(frame.size())) {
      ++stats_.frames_sent;
      // The adaptive wait measures the round trip from here (one clock read, only in that mode).
      if (receive_wait_ == RawSocketSettings::ReceiveWait::adaptive) sent_at_ = clock_.now();
      return Status::success();
    }
    if (sent < 0 && errno == EINTR) continue;
    ++stats_.send_errors;
    if (sent >= 0) return make_error(Errc::io_error, "short send", static_cast<std::uint32_t>(sent));
    if (errno == EAGAIN || errno == ENOBUFS) {
      return make_error(Errc::busy, "send queue of the interface full", errno_value());
    }
    return os_error("send() on the raw socket failed");
  }
}

Result<std::size_t> RawSocketNic::read_one(ByteSpan buffer) noexcept {
  sockaddr_ll from{};
  iovec data{buffer.data(), buffer.size()};
  // Room for the control messages asked for: PACKET_AUXDATA (the VLAN tag the kernel took out) and
  // SCM_TIMESTAMPNS (the receive timestamp, with receive_timestamps).
  alignas(cmsghdr) std::array<std::uint8_t, CMSG_SPACE(sizeof(tpacket_auxdata)) + CMSG_SPACE(sizeof(timespec))> control{};
  msghdr message{};
  message.msg_name = &from;
  message.msg_namelen = sizeof from;
  message.msg_iov = &data;
  message.msg_iovlen = 1;
  message.msg_control = control.data();
  message.msg_controllen = control.size();
  // MSG_TRUNC: the return value is the frame's real length even when it did not fit.
  const ssize_t got = ::recvmsg(fd_, &message, MSG_TRUNC);
  if (got < 0) {
    if (errno == EAGAIN || errno == EINTR) return make_error(Errc::busy, "nothing queued");
    return os_error("recvmsg() on the raw socket failed");
  }
  auto length = static_cast<std::size_t>(got);
  if (from.sll_pkttype == PACKET_OUTGOING) return std::size_t{0};  // our own frame (without PACKET_IGNORE_OUTGOING)
  if (length > buffer.size() || !restore_vlan_tag(message, buffer, length)) {
    ++stats_.frames_dropped;
    return std::size_t{0};
  }
  if (!is_ethercat_frame(ConstByteSpan(buffer.data(), length))) {
    ++stats_.frames_dropped;
    return std::size_t{0};
  }
  ++stats_.frames_received;
  last_receive_time_ = -1;
  Nanoseconds stamp = 0;
  if (features_.receive_timestamps && find_receive_timestamp(message, stamp)) {
    // The realtime-monotonic difference read now, between two monotonic reads (a step of the
    // realtime clock, e.g. by NTP, is then taken into account frame by frame).
    const Nanoseconds before = clock_.now();
    const Nanoseconds realtime = realtime_now();
    const Nanoseconds after = clock_.now();
    const Nanoseconds monotonic = stamp - (realtime - before / 2 - after / 2);
    last_receive_time_ = monotonic < after ? monotonic : after;
  } else if (features_.receive_timestamps) {
    ++frames_without_timestamp_;
  }
  return length;
}

Result<Nanoseconds> RawSocketNic::last_receive_time() const noexcept {
  if (!features_.receive_timestamps) return make_error(Errc::unsupported, "receive timestamps not asked for");
  if (last_receive_time_ < 0) return make_error(Errc::not_found, "the last frame came without a receive timestamp");
  return last_receive_time_;
}

const char* to_string(RawSocketSettings::ReceiveWait wait) noexcept {
  switch (wait) {
    case RawSocketSettings::ReceiveWait::spin: return "spin";
    case RawSocketSettings::ReceiveWait::adaptive: return "adaptive";
    case RawSocketSettings::ReceiveWait::sleep: return "sleep";
  }
  return "?";
}

void RawSocketNic::learn_round_trip(Nanoseconds now) noexcept {
  if (sent_at_ < 0) return;
  const Nanoseconds sample = now - sent_at_;
  sent_at_ = -1;
  if (sample <= 0) return;
  if (learnt_frames_ == 0) {
    round_trip_ns_ = sample;
  } else {
    // An outlier (a late frame, a preempted thread) moves the mean by at most 1/16 of its excess.
    round_trip_ns_ += (sample - round_trip_ns_) / (Nanoseconds{1} << kAdaptiveWeightShift);
  }
  if (learnt_frames_ < kAdaptiveLearnFrames) ++learnt_frames_;
}

Status RawSocketNic::sleep_for_frame(Nanoseconds now, Nanoseconds until) noexcept {
  pollfd waiting{fd_, POLLIN, 0};
  const timespec timeout = to_timespec(until > now ? until - now : 0);
  if (::ppoll(&waiting, 1, &timeout, nullptr) < 0 && errno != EINTR) return os_error("ppoll() on the raw socket failed");
  if ((waiting.revents & (POLLERR | POLLNVAL)) != 0) {
    // E.g. ENETDOWN when the interface went down or away; reading SO_ERROR also clears it.
    int pending = 0;
    socklen_t pending_size = sizeof pending;
    (void)::getsockopt(fd_, SOL_SOCKET, SO_ERROR, &pending, &pending_size);
    return make_error(Errc::io_error, "raw socket error (interface down or removed?)",
                      static_cast<std::uint32_t>(pending));
  }
  return Status::success();
}

Result<std::size_t> RawSocketNic::receive(ByteSpan buffer, Nanoseconds deadline) noexcept {
  if (fd_ < 0) return make_error(Errc::invalid_argument, "raw socket NIC not open");
  using Wait = RawSocketSettings::ReceiveWait;
  // Where the wait stands: before its first read, asleep until the expected return (adaptive),
  // spinning, or asleep until the deadline.
  enum class Phase : std::uint8_t { first, asleep, spinning, late };
  Phase phase = Phase::first;
  Nanoseconds spin_until = -1;
  const Nanoseconds expected = expected_round_trip();
  for (;;) {
    // The time first, then the read: a timeout is declared only when the queue was still empty at or
    // after the deadline. A process preempted between the two (a slow host, not a lost frame) finds
    // the frame that arrived meanwhile, and a frame already queued is returned past the deadline.
    const Nanoseconds now = clock_.now();
    const Result<std::size_t> got = read_one(buffer);
    if (got.ok()) {
      if (got.value() == 0) continue;  // filtered out: look at the next one
      if (receive_wait_ == Wait::adaptive) learn_round_trip(now);
      switch (phase) {
        case Phase::first: ++wait_stats_.at_once; break;
        case Phase::asleep: ++wait_stats_.while_asleep; break;
        case Phase::spinning: ++wait_stats_.while_spinning; break;
        case Phase::late: ++wait_stats_.after_spin; break;
      }
      return got.value();
    }
    if (got.error().code != Errc::busy) return got.error();

    if (now >= deadline) {
      ++stats_.receive_timeouts;
      sent_at_ = -1;  // a lost frame teaches nothing about the round trip
      return make_error(Errc::timeout, "no EtherCAT frame before the deadline");
    }
    if (phase == Phase::first) {
      phase = Phase::spinning;
      spin_until = now + receive_spin_;
      if (receive_wait_ == Wait::sleep) {
        spin_until = now;
      } else if (receive_wait_ == Wait::adaptive && expected > 0 && sent_at_ >= 0) {
        const Nanoseconds wake_at = sent_at_ + expected - adaptive_lead_;
        if (wake_at > now) {
          // Asleep through most of the round trip: an early frame wakes the ppoll() at once.
          phase = Phase::asleep;
          RESCUE_TRY(sleep_for_frame(now, wake_at < deadline ? wake_at : deadline));
          spin_until = wake_at + receive_spin_;
          continue;
        }
      }
    }
    if (phase == Phase::asleep) phase = Phase::spinning;
    if (phase == Phase::spinning && now < spin_until) continue;  // spinning: read again without sleeping
    phase = Phase::late;
    RESCUE_TRY(sleep_for_frame(now, deadline));
  }
}

}  // namespace rescue::hal
