#include "core/app/tasks/rescan_relay.hpp"

namespace rescue::app {
namespace {

using protocol::RescanStatus;

static_assert(protocol::kRescanDevices == ecat::kMaxFoundSlaves, "a rescan result holds every device found");
static_assert(protocol::kRescanDifferences == 2 * ecat::kMaxFoundSlaves, "and every difference");
static_assert(static_cast<std::uint8_t>(ecat::DifferenceKind::known_lost_present) == protocol::kRescanDifferenceLast,
              "the wire's difference kinds are the master's");

RescanStatus status_of(ecat::RescanService::Refusal r) noexcept {
  switch (r) {
    case ecat::RescanService::Refusal::none: return RescanStatus::ok;
    case ecat::RescanService::Refusal::busy: return RescanStatus::busy;
    case ecat::RescanService::Refusal::recovering: return RescanStatus::recovering;
    case ecat::RescanService::Refusal::not_cycling: return RescanStatus::not_cycling;
  }
  return RescanStatus::not_cycling;
}

RescanStatus status_of(ecat::RescanStatus s) noexcept {
  switch (s) {
    case ecat::RescanStatus::ok: return RescanStatus::ok;
    case ecat::RescanStatus::incomplete: return RescanStatus::incomplete;
    case ecat::RescanStatus::recovering: return RescanStatus::recovering;
  }
  return RescanStatus::incomplete;
}

}  // namespace

void RescanRelay::answer() noexcept { waiting_ = !results_->try_send(answer_); }

void RescanRelay::describe_rescan() noexcept {
  const ecat::RescanService& scan = master_.rescan();
  protocol::RescanResultPayload& r = answer_.result;
  r.status = status_of(scan.status());
  r.counted = scan.counted();
  r.frames = scan.frames();
  const Span<const ecat::FoundSlave> found = scan.found();
  const bool compared = scan.status() == ecat::RescanStatus::ok;
  r.devices = static_cast<std::uint8_t>(found.size() < r.records.size() ? found.size() : r.records.size());
  for (std::size_t i = 0; i < r.devices; ++i) {
    protocol::RescanDeviceRecord& d = r.records[i];
    if ((scan.identified() & (std::uint32_t{1} << i)) != 0) {
      d.vendor_id = found[i].vendor_id;
      d.product_code = found[i].product_code;
      d.revision = found[i].revision;
      d.serial_number = found[i].serial_number;
      d.station_alias = found[i].station_alias;
      d.identified = 1;
    }
    const std::uint8_t slot = compared ? scan.match().slot_of_found[i] : ecat::kNoPosition;
    d.slot = slot < ecat::kMaxSlaves ? slot : protocol::kNoPlace;
  }
  r.differences = 0;
  if (!compared) return;
  for (const ecat::NetworkDifference& nd : scan.match().differences) {
    if (r.differences >= r.found_differences.size()) break;
    protocol::RescanDifferenceRecord& d = r.found_differences[r.differences++];
    d.kind = static_cast<protocol::RescanDifference>(nd.kind);
    d.planned = nd.planned < ecat::kMaxSlaves ? nd.planned : protocol::kNoPlace;
    d.found = nd.found < r.devices ? nd.found : protocol::kNoPlace;
  }
}

void RescanRelay::step() noexcept {
  if (requests_ == nullptr || results_ == nullptr) return;
  if (waiting_) {
    answer();
    if (waiting_) return;
  }
  if (in_flight_) {
    if (!master_.take_rescan()) return;
    in_flight_ = false;
    describe_rescan();
    return answer();
  }
  RescanLinkRequest request;
  if (!requests_->try_receive(request)) return;
  answer_ = RescanLinkResult{};
  answer_.id = request.id;
  const auto refusal = master_.request_rescan();
  if (refusal != ecat::RescanService::Refusal::none) {
    answer_.result.status = status_of(refusal);
    return answer();
  }
  in_flight_ = true;
}

}  // namespace rescue::app
