#include "drivers/sim/devices/junction_device.hpp"

namespace rescue::drivers {

namespace {

SiiIdentity junction_identity(std::uint32_t serial, std::uint16_t alias) noexcept {
  SiiIdentity identity{};
  identity.vendor_id = kJunctionIdentity.vendor_id;
  identity.product_code = kJunctionIdentity.product_code;
  identity.revision = kJunctionIdentity.revision;
  identity.serial = serial;
  identity.station_alias = alias;
  // Like EtherCAT junction modules (ET1100 without a microcontroller): device emulation on (AL
  // status follows AL control), enhanced link detection, DC SYNC out unit (as an EK1100's 0x0D00).
  identity.pdi_control = 0x0D00;
  return identity;
}

}  // namespace

JunctionDevice::JunctionDevice(std::size_t position) noexcept {
  // Cannot fail: the buffer is sized for the name.
  sii_length_ = build_minimal_sii(ByteSpan(sii_), junction_identity(serial_number_of(position), station_alias_of(position)),
                                  kJunctionIdentity.name)
                    .value_or(0);
}

JunctionDevice::JunctionDevice(Spare spare) noexcept {
  sii_length_ = build_minimal_sii(ByteSpan(sii_), junction_identity(spare.serial, 0), kJunctionIdentity.name).value_or(0);
}

}  // namespace rescue::drivers
