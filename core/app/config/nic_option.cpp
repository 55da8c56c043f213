#include "core/app/config/nic_option.hpp"

#include <cstring>

namespace rescue::app {
namespace {

constexpr const char kRawPrefix[] = "raw:";
constexpr std::size_t kRawPrefixLength = sizeof kRawPrefix - 1;

// What the kernel refuses in a name (dev_valid_name): '/', ':' and white space, "." and "..".
bool valid_interface_name(const char* name) noexcept {
  if (std::strcmp(name, ".") == 0 || std::strcmp(name, "..") == 0) return false;
  for (const char* c = name; *c != '\0'; ++c) {
    if (*c == '/' || *c == ':' || *c == ' ' || *c == '\t' || *c == '\n' || *c == '\r' || *c == '\v' || *c == '\f') {
      return false;
    }
  }
  return true;
}

}  // namespace

Result<NicChoice> parse_nic_option(const char* text) noexcept {
  NicChoice choice;
  if (text == nullptr || std::strcmp(text, "sim") == 0) return choice;
  if (std::strncmp(text, kRawPrefix, kRawPrefixLength) != 0) {
    return make_error(Errc::invalid_argument, "--nic must be 'sim' or 'raw:IFACE' (e.g. raw:eth0)");
  }
  const char* name = text + kRawPrefixLength;
  const std::size_t length = std::strlen(name);
  if (length == 0) return make_error(Errc::invalid_argument, "--nic raw: needs an interface name (e.g. raw:eth0)");
  if (length > hal::kMaxInterfaceNameLength) {
    return make_error(Errc::invalid_argument, "--nic raw:IFACE: interface names have at most 15 characters",
                      static_cast<std::uint32_t>(length));
  }
  if (!valid_interface_name(name)) {
    return make_error(Errc::invalid_argument, "--nic raw:IFACE: an interface name has no '/', ':' or spaces");
  }
  choice.kind = NicKind::raw;
  std::memcpy(choice.interface_name.data(), name, length + 1);
  return choice;
}

Result<NicChoice> parse_ring_nic_option(const char* text, const NicChoice& main) noexcept {
  if (std::strcmp(text, "sim") == 0) {
    if (main.kind != NicKind::sim) {
      return make_error(Errc::invalid_argument, "--ring-nic sim is the simulated robot's second port: it needs --nic sim");
    }
    return NicChoice{};
  }
  if (std::strncmp(text, kRawPrefix, kRawPrefixLength) != 0) {
    return make_error(Errc::invalid_argument, "--ring-nic must be 'sim' or 'raw:IFACE' (e.g. raw:eth1)");
  }
  Result<NicChoice> ring = parse_nic_option(text);
  if (!ring.ok()) return make_error(Errc::invalid_argument, "--ring-nic raw:IFACE: not an interface name (at most 15 bytes, no '/', ':' or spaces)");
  if (main.kind != NicKind::raw) {
    return make_error(Errc::invalid_argument, "--ring-nic raw:IFACE needs --nic raw:IFACE (both master ports on the wire)");
  }
  if (std::strcmp(ring.value().interface_name.data(), main.interface_name.data()) == 0) {
    return make_error(Errc::invalid_argument,
                      "--ring-nic is the --nic interface itself: the ring's second port must be another interface");
  }
  return ring;
}

}  // namespace rescue::app
