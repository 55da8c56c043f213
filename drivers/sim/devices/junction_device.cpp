#include "drivers/sim/devices/junction_device.hpp"

namespace rescue::drivers {

JunctionDevice::JunctionDevice(std::size_t position) noexcept {
  SiiIdentity identity{};
  identity.vendor_id = kJunctionIdentity.vendor_id;
  identity.product_code = kJunctionIdentity.product_code;
  identity.revision = kJunctionIdentity.revision;
  identity.serial = serial_number_of(position);
  identity.station_alias = station_alias_of(position);
  // Like EtherCAT junction modules (ET1100 without a microcontroller): device emulation on (AL
  // status follows AL control), enhanced link detection, DC SYNC out unit (as an EK1100's 0x0D00).
  identity.pdi_control = 0x0D00;
  // Cannot fail: the buffer is sized for the name.
  sii_length_ = build_minimal_sii(ByteSpan(sii_), identity, kJunctionIdentity.name).value_or(0);
}

}  // namespace rescue::drivers
