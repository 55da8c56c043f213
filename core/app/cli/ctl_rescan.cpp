#include "core/app/cli/ctl_rescan.hpp"

#include <algorithm>
#include <array>
#include <cinttypes>
#include <cstdio>

#include "core/app/cli/ctl_network.hpp"
#include "core/app/cli/ctl_output.hpp"
#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/master/network_match.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;
using protocol::RescanStatus;

const char* status_reason(RescanStatus s) noexcept {
  switch (s) {
    case RescanStatus::ok: return "";
    case RescanStatus::incomplete: return "a device's SII could not be read: its identity is unknown, not compared with the plan";
    case RescanStatus::recovering: return "the master's online recovery is identifying a slave; try again";
    case RescanStatus::busy: return "another rescan is under way; try again";
    case RescanStatus::not_cycling: return "the master is not cycling in OP";
    case RescanStatus::no_answer: return "the EtherCAT handler did not answer within 1.8 s";
  }
  return "?";
}

// The devices as the master's matcher sees them (for ecat::describe's lines): a device of a
// planned type named by it.
std::array<ecat::FoundSlave, protocol::kRescanDevices> g_found{};  // 9 KiB: not on the stack

void fill_found(const protocol::RescanResultPayload& r) noexcept {
  for (std::size_t i = 0; i < r.devices && i < g_found.size(); ++i) {
    const protocol::RescanDeviceRecord& d = r.records[i];
    ecat::FoundSlave& f = g_found[i];
    f = ecat::FoundSlave{};
    f.vendor_id = d.vendor_id;
    f.product_code = d.product_code;
    f.revision = d.revision;
    f.serial_number = d.serial_number;
    f.station_alias = d.station_alias;
    const char* name = d.identified != 0 ? "unknown device" : "not identified";
    // A planned slave of the same type names it (SlavePlan::device_name is the device type's name).
    const auto* type = std::find_if(drivers::kRobotNetworkPlan.begin(), drivers::kRobotNetworkPlan.end(), [&d](const ecat::SlavePlan& s) {
      return s.vendor_id == d.vendor_id && s.product_code == d.product_code;
    });
    if (d.identified != 0 && type != drivers::kRobotNetworkPlan.end()) name = type->device_name;
    (void)std::snprintf(f.name.data(), f.name.size(), "%s", name);
  }
}

const char* slot_name(std::uint8_t slot) noexcept { return slot < kSlaveCount ? planned_slave_name(slot) : nullptr; }

}  // namespace

Result<Message> build_rescan(const ParsedArgs& /*args*/, CtlPeer& /*peer*/) noexcept {
  Message m;
  m.header.type = MessageType::rescan;
  return m;
}

int print_rescan_result(const Message& /*request*/, const Message& answer) noexcept {
  if (answer.header.type != MessageType::rescan_result) return ctl_unexpected_answer(answer);
  const protocol::RescanResultPayload& r = answer.rescan_result;
  const bool ok = r.status == RescanStatus::ok;
  fill_found(r);
  const Span<const ecat::FoundSlave> found(g_found.data(), r.devices);
  char line[ecat::kDifferenceLineCapacity];
  if (ctl_output().json) {
    begin_json(ok);
    (void)std::printf(R"(,"status":"%s")", protocol::to_string(r.status));
    if (!ok) {
      (void)std::printf(R"(,"reason":)");
      print_json_string(status_reason(r.status));
    }
    (void)std::printf(R"(,"counted":%u,"frames":%u,"devices":[)", static_cast<unsigned>(r.counted),
                      static_cast<unsigned>(r.frames));
    for (std::size_t i = 0; i < r.devices; ++i) {
      const protocol::RescanDeviceRecord& d = r.records[i];
      (void)std::printf(R"(%s{"position":%zu,"identified":%s,"device":)", i == 0 ? "" : ",", i,
                        d.identified != 0 ? "true" : "false");
      print_json_string(g_found[i].name.data());
      (void)std::printf(R"(,"vendor_id":"0x%08)" PRIx32 R"(","product_code":"0x%08)" PRIx32 R"(","revision":"0x%08)" PRIx32
                        R"(","serial_number":"0x%08)" PRIx32 R"(","alias":"0x%04x","slave":)",
                        d.vendor_id, d.product_code, d.revision, d.serial_number, static_cast<unsigned>(d.station_alias));
      const char* slave = slot_name(d.slot);
      if (slave != nullptr) {
        print_json_string(slave);
      } else {
        (void)std::printf("null");
      }
      (void)std::printf("}");
    }
    (void)std::printf(R"(],"differences":[)");
    for (std::size_t k = 0; k < r.differences; ++k) {
      const protocol::RescanDifferenceRecord& d = r.found_differences[k];
      const ecat::NetworkDifference nd{static_cast<ecat::DifferenceKind>(d.kind), d.planned, d.found};
      (void)ecat::describe(nd, drivers::kRobotNetworkPlan, found, line, sizeof line);
      (void)std::printf(R"(%s{"kind":"%s","slave":)", k == 0 ? "" : ",", ecat::to_string(nd.kind));
      const char* slave = slot_name(d.planned);
      if (slave != nullptr) {
        print_json_string(slave);
      } else {
        (void)std::printf("null");
      }
      if (d.found != protocol::kNoPlace) {
        (void)std::printf(R"(,"position":%u,"text":)", static_cast<unsigned>(d.found));
      } else {
        (void)std::printf(R"(,"position":null,"text":)");
      }
      print_json_string(line);
      (void)std::printf("}");
    }
    (void)std::printf("]");
    end_json();
    return ok ? 0 : static_cast<int>(CtlExit::refused);
  }
  if (r.devices > 0) {
    (void)std::printf("POS  DEVICE            VENDOR      PRODUCT     REVISION    SERIAL      ALIAS   AS\n");
    for (std::size_t i = 0; i < r.devices; ++i) {
      const protocol::RescanDeviceRecord& d = r.records[i];
      const char* slave = slot_name(d.slot);
      (void)std::printf("%-4zu %-17.17s 0x%08" PRIx32 "  0x%08" PRIx32 "  0x%08" PRIx32 "  0x%08" PRIx32 "  0x%04x  %s\n", i,
                        g_found[i].name.data(), d.vendor_id, d.product_code, d.revision, d.serial_number,
                        static_cast<unsigned>(d.station_alias), slave != nullptr ? slave : "-");
    }
  }
  if (!ok) {
    (void)std::printf("rescan: refused: %s\n", status_reason(r.status));
    return static_cast<int>(CtlExit::refused);
  }
  (void)std::printf("%u devices on the wire, %u identified; ", static_cast<unsigned>(r.counted),
                    static_cast<unsigned>(r.devices));
  if (r.differences == 0) {
    (void)std::printf("no difference from the plan\n");
    return 0;
  }
  (void)std::printf("%u differences from the plan:\n", static_cast<unsigned>(r.differences));
  for (std::size_t k = 0; k < r.differences; ++k) {
    const protocol::RescanDifferenceRecord& d = r.found_differences[k];
    const ecat::NetworkDifference nd{static_cast<ecat::DifferenceKind>(d.kind), d.planned, d.found};
    (void)ecat::describe(nd, drivers::kRobotNetworkPlan, found, line, sizeof line);
    (void)std::printf("  %s\n", line);
  }
  return 0;
}

}  // namespace rescue::app
