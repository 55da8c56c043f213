#include "drivers/junction_device.hpp"

#include <cstring>

namespace rescue::drivers {

JunctionDevice::JunctionDevice(const char* name, std::uint32_t serial) noexcept {
  std::array<char, kMaxNameLength + 1> clipped{};
  if (name != nullptr) std::strncpy(clipped.data(), name, kMaxNameLength);
  const SiiIdentity identity{kJunctionVendorId, kJunctionProductCode, kJunctionRevision, serial, 0};
  // Cannot fail: the buffer is sized for the longest name.
  sii_length_ = build_minimal_sii(ByteSpan(sii_), identity, clipped.data()).value_or(0);
}

}  // namespace rescue::drivers
