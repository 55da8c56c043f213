// What each device of the robot's EtherCAT network says about itself in its SII EEPROM: the one
// table the simulator's SII builder writes and the master compares a scanned network against.
//
// Identity (SII words 0x08..0x0F): vendor id, product code, revision, serial number. The master
// requires vendor and product to match the device type expected at a position and reports a
// different revision; serial numbers are read and reported, never compared.
//
// Station alias (SII word 0x04, copied by the ESC to register 0x0012): written at commissioning to
// the station address the device is designed to have (0x1000 + its position in kSlaves). It tells
// the master which device is which among identical joint drives, so a swapped cable is reported as
// "wrong position" rather than accepted. Alias 0 means "not commissioned": position only.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/robot/robot.hpp"

namespace rescue::drivers {

struct DeviceIdentity {
  std::uint32_t vendor_id;
  std::uint32_t product_code;
  std::uint32_t revision;
  const char* name;  // SII General category name string (device type, e.g. "RM-JD402")
};

// The robot's own (private) vendor id; product codes spell the device type in ASCII.
constexpr std::uint32_t kRescueVendorId = 0x00000A5C;

constexpr DeviceIdentity kJunctionIdentity{kRescueVendorId, 0x4A435434 /* "JCT4" */, 0x00010000, "RM-JCT4"};
constexpr DeviceIdentity kJointDriveIdentity{kRescueVendorId, 0x4A443432 /* "JD42" */, 0x00010000, "RM-JD402"};

static_assert(kJunctionIdentity.product_code != kJointDriveIdentity.product_code, "device types must differ");

constexpr const DeviceIdentity& identity_of(SlaveKind kind) noexcept {
  return kind == SlaveKind::junction ? kJunctionIdentity : kJointDriveIdentity;
}

// Serial number of the device built into the slot at `position` (unique per device).
constexpr std::uint32_t serial_number_of(std::size_t position) noexcept {
  return 0x52460000U + static_cast<std::uint32_t>(position);
}

// Commissioned station alias of the device at `position` (its designed station address).
constexpr std::uint16_t station_alias_of(std::size_t position) noexcept {
  return kSlaves[position].station_address;
}

}  // namespace rescue::drivers
