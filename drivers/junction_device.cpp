#include "drivers/junction_device.hpp"

namespace rescue::drivers {

JunctionDevice::JunctionDevice(std::size_t position) noexcept {
  const SiiIdentity identity{kJunctionIdentity.vendor_id, kJunctionIdentity.product_code, kJunctionIdentity.revision,
                             serial_number_of(position), station_alias_of(position)};
  // Cannot fail: the buffer is sized for the name.
  sii_length_ = build_minimal_sii(ByteSpan(sii_), identity, kJunctionIdentity.name).value_or(0);
}

}  // namespace rescue::drivers
