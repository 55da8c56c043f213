// Online recovery while cycling: a slave out of the exchange (lost, restored, or not operational) is
// looked for at its auto-increment position and, when it answers, addressed, reset, identified from
// its SII, configured as at bring-up (SMs, start-up SDOs, FMMUs, DC offset/delay, SYNC0) and taken
// through PRE-OP and SAFE-OP to OP, then put back in the exchange ("recovered"). The states and
// transitions are the table of ecat/master/slave_recovery.hpp; this file does what each state says.
//
// Bounded cost: each cycle carries at most MasterOptions::recovery_datagrams_per_cycle datagrams of the
// recovery in all (one per slave being recovered, plus one search), only while something is out of
// the exchange; the healthy path carries none. Other slaves are only ever addressed by their own
// station address; the one APWR (by position) writes the device found at the expected position.
#include "ecat/master/recovery_service.hpp"

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/master/slave_config.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint8_t kGonePeriods = 3;
constexpr std::uint8_t kMaxBounces = 3;  // attempts in a row that lost the device again
constexpr std::uint16_t kSiiBlockLength = 14;  // 0x0502..0x050F: control, address, data
constexpr std::uint16_t kDcBlockLength = 0x20;  // 0x0910..0x092F: time, receive time, offset, delay, difference
constexpr std::uint8_t kReadStandIn = 3;  // clock step of the reference itself: a stand-in's time read (then sub 1)
constexpr std::uint16_t kDcLoopRestart = 0x1000;
constexpr std::uint64_t kSync0MarginPeriods = 10;
constexpr std::size_t kIdentityWords = 8;
constexpr std::uint8_t kSearchTag = 0x80;  // tag bit: a search datagram (else a step of the slave's state)

constexpr std::uint16_t al_control_value(reg::AlState state, bool acknowledge) noexcept {
  return static_cast<std::uint16_t>(static_cast<std::uint16_t>(state) | (acknowledge ? reg::kAlErrorBit : 0U));
}

// The AL state a state's control write asks for.
reg::AlState target_al_state(RecoveryState state) noexcept {
  switch (state) {
    case RecoveryState::pre_op: return reg::AlState::pre_op;
    case RecoveryState::safe_op: return reg::AlState::safe_op;
    case RecoveryState::op: return reg::AlState::op;
    default: return reg::AlState::init;
  }
}

bool is_al_step(RecoveryState state) noexcept {
  return state == RecoveryState::resetting || state == RecoveryState::pre_op || state == RecoveryState::safe_op ||
         state == RecoveryState::op;
}

// Whether the state's next AL control write acknowledges an error: when one was seen, and on the
// way into INIT unless the acknowledging write already left the error bit (see on_step_answer).
bool acknowledges(const RecoveryProgress& r) noexcept {
  return r.acknowledge || (r.state() == RecoveryState::resetting && !r.plain_request);
}

std::uint32_t word_pair(const std::array<std::uint16_t, 8>& w, std::size_t first) noexcept {
  return static_cast<std::uint32_t>(w[first]) | (static_cast<std::uint32_t>(w[first + 1]) << 16U);
}

}  // namespace

const char* to_string(RecoveryState state) noexcept {
  const auto index = static_cast<std::size_t>(state);
  return index < kRecoveryStateCount ? SlaveRecoveryTable::kStates[index].name : "?";
}

SlaveMask RecoveryService::recovering() const noexcept {
  SlaveMask mask = 0;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if (ctx_.slaves[p].recovery.state() != RecoveryState::idle) mask |= slave_bit(p);
  }
  return mask;
}

RecoveryService::Places RecoveryService::expected_places(std::size_t position) const noexcept {
  // Every slave before it that answered at bring-up occupies a place when it is known to answer
  // (in the exchange, being configured again, or refused: a foreign device is there); one searched
  // for or waiting after a failure may or may not be there.
  Places places;
  for (std::size_t q = 0; q < position; ++q) {
    if ((ctx_.present() & slave_bit(q)) == 0) continue;
    const RecoveryState s = ctx_.slaves[q].recovery.state();
    if (s == RecoveryState::searching || s == RecoveryState::failed) {
      ++places.unknown;
    } else {
      ++places.first;
    }
  }
  return places;
}

void RecoveryActions::enter_state(RecoveryContext& ctx) noexcept {
  RecoveryService& service = ctx.service;
  const std::size_t p = ctx.position;
  RecoveryProgress& r = service.ctx_.slaves[p].recovery;
  const RecoveryState state = r.state();
  r.sub = 0;
  r.silent = 0;
  r.acknowledge = false;
  r.plain_request = false;
  const hal::Nanoseconds now = service.ctx_.now();
  r.changed_at = now;
  r.deadline = now + (state == RecoveryState::failed ? service.hold_off(r.failures) : service.ctx_.options.recovery_step_timeout);
  if (state == RecoveryState::identifying) {
    r.words = 0;
    r.sii.fill(0);
  }
  if (state == RecoveryState::mailbox && service.ctx_.plan[p].mailbox) {
    const SlaveSetup& setup = service.ctx_.slaves[p].setup;
    service.mailbox_.configure(p, setup.sm[0].start, setup.sm[0].length, setup.sm[1].start, setup.sm[1].length);
  }
  // Its PDO mapping first (read, the differences written, read back), then the owner's start-up
  // SDOs (pdo_setup_service.hpp).
  if (state == RecoveryState::startup_sdos) service.sdos_.start(p);
}

void RecoveryActions::watch_position(RecoveryContext& ctx) noexcept {
  ctx.service.ctx_.slaves[ctx.position].recovery.started_cycle = ctx.service.ctx_.cycle;
}

void RecoveryActions::withdraw_address(RecoveryContext& ctx) noexcept {
  ctx.service.ctx_.slaves[ctx.position].recovery.withdraw = true;
}

void RecoveryActions::report_failed(RecoveryContext& ctx) noexcept {
  RecoveryService& service = ctx.service;
  RecoveryProgress& r = service.ctx_.slaves[ctx.position].recovery;
  r.bounces = 0;
  // Every failure is reported; the hold-off before the next attempt (from the start: searching)
  // doubles with each failure in a row, so a slave that cannot be recovered costs little.
  ++service.stats_.failed;
  if (r.failures < 0xFF) ++r.failures;
  service.ctx_.monitor.recovery_event(LinkEventKind::recovery_failed, slave_bit(ctx.position), service.ctx_.cycle,
                                      service.ctx_.now(),
                                      {static_cast<std::uint32_t>(r.state()), r.failures,
                                       static_cast<std::uint32_t>(service.hold_off(r.failures) / hal::kNsPerMs), 0});
}

void RecoveryActions::report_refused(RecoveryContext& ctx) noexcept {
  RecoveryService& service = ctx.service;
  const RecoveryProgress& r = service.ctx_.slaves[ctx.position].recovery;
  ++service.stats_.refused;
  service.ctx_.monitor.recovery_event(LinkEventKind::recovery_refused, slave_bit(ctx.position), service.ctx_.cycle,
                                      service.ctx_.now(),
                                      {word_pair(r.sii, 0), word_pair(r.sii, 2), word_pair(r.sii, 4), word_pair(r.sii, 6)});
}

void RecoveryActions::report_recovered(RecoveryContext& ctx) noexcept {
  RecoveryService& service = ctx.service;
  RecoveryProgress& r = service.ctx_.slaves[ctx.position].recovery;
  ++service.stats_.recovered;
  r.failures = 0;
  r.bounces = 0;
  service.ctx_.monitor.recovered(slave_bit(ctx.position), service.ctx_.cycle, service.ctx_.now(),
                                 r.lost_address ? kRecoveredAfterPowerLoss : 0, service.ctx_.slaves[ctx.position].pdo.writes());
}

void RecoveryService::take_input(std::size_t p, RecoveryInput input) noexcept {
  RecoveryProgress& r = ctx_.slaves[p].recovery;
  if (input == RecoveryInput::gone && r.state() != RecoveryState::refused) {
    // A device that answers its search but falls silent in every attempt (e.g. its application
    // refuses AL control) would go round Searching for ever: after kMaxBounces such attempts the
    // attempt counts as failed (reported, retried after the hold-off).
    if (++r.bounces >= kMaxBounces) input = RecoveryInput::timeout;
  }
  RecoveryContext context{*this, p, input};
  // A (state, input) pair without a row is refused by the engine: counted (a bug if ever seen).
  if (!r.machine.dispatch(context, input).ok()) ++stats_.table_refusals;
}

bool RecoveryService::add_search(CycleFrame& frame) noexcept {
    for (std::size_t i = 0; i < kMaxSlaves; ++i) {
    const std::size_t p = (search_rotate_ + i) % kMaxSlaves;
    RecoveryProgress& r = ctx_.slaves[p].recovery;
    if (r.state() != RecoveryState::searching && r.state() != RecoveryState::refused) continue;
    search_rotate_ = p + 1;
    const auto tag = static_cast<std::uint8_t>(p | kSearchTag);
    bool added = false;
    if (r.withdraw) {
      std::array<std::uint8_t, 2> value{};
      store_le16(value.data(), r.handover);
      added = frame.add(*this, tag, Command::FPWR, make_address(ctx_.plan[p].station_address, reg::kStationAddress), 2, ConstByteSpan(value));
    } else if (r.state() == RecoveryState::searching && r.by_address) {
      // Slaves behind a power-cycled or reconnected one come back with their station address: found
      // by it wherever they are, whatever returned before them.
      added = frame.add(*this, tag, Command::FPRD, make_address(ctx_.plan[p].station_address, reg::kStationAddress), 2);
    } else {
      if (r.state() == RecoveryState::searching) {
        // Its place: after every slave known to answer, plus any of those that may be there.
        const Places places = expected_places(p);
        r.adp = position_adp(static_cast<std::uint16_t>(places.first + (r.scan % (places.unknown + 1U))));
        ++r.scan;
      }
      added = frame.add(*this, tag, Command::APRD, make_address(r.adp, reg::kStationAddress), 2);
    }
    return added;
  }
  return false;
}

void RecoveryService::on_search_answer(std::size_t p, const DatagramView& d) noexcept {
  RecoveryProgress& r = ctx_.slaves[p].recovery;
  if (r.withdraw) {
    r.withdraw = false;  // taken or not: the device is searched for again either way
    r.handover = 0;
    return;
  }
  const std::uint16_t station = d.wkc() == 1 ? load_le16(d.data().data()) : 0;
  if (r.state() == RecoveryState::refused) {
    // The foreign device keeps the station address it was given; when that place holds anything
    // else (or nothing), it has left.
    if (d.wkc() == 0 || station != ctx_.plan[p].station_address) take_input(p, RecoveryInput::gone);
    return;
  }
  if (r.state() != RecoveryState::searching) return;
  const bool by_address = r.by_address;
  r.by_address = !by_address;  // the two searches alternate
  if (by_address && d.wkc() > 1) {
    separate_devices(p);
    return;
  }
  if (d.wkc() != 1) return;
  if (by_address) {
    r.lost_address = false;
    take_input(p, RecoveryInput::answered_addressed);
    return;
  }
  if (station == 0) {
    // A blank device at that place. Several slaves searched for may expect the same place (none of
    // the slaves between them answers): the first of them in frame order is the one the device
    // must be if it is any of them; the identity check hands it on when it is another one.
    // One already taken by a slave about to address it (its APWR still waits for a place in the
    // frame) is that slave's: a second claim would give it a second station address.
    if (addressing_at(r.adp, p)) return;
    std::size_t claimant = p;
    const std::uint32_t place = static_cast<std::uint16_t>(0U - r.adp);
    for (std::size_t q = 0; q < p; ++q) {
      if (ctx_.slaves[q].recovery.state() != RecoveryState::searching || (ctx_.present() & slave_bit(q)) == 0) continue;
      const Places places = expected_places(q);
      if (place >= places.first && place <= places.first + places.unknown) {
        claimant = q;
        break;
      }
    }
    ctx_.slaves[claimant].recovery.adp = r.adp;
    ctx_.slaves[claimant].recovery.lost_address = true;
    take_input(claimant, RecoveryInput::answered_unaddressed);
  } else if (station == ctx_.plan[p].station_address) {
    r.lost_address = false;
    take_input(p, RecoveryInput::answered_addressed);
  }
  // Any other address: another slave sits at that position (this one is still absent).
}

bool RecoveryService::add_step(CycleFrame& frame, std::size_t p) noexcept {
  RecoveryProgress& r = ctx_.slaves[p].recovery;
  const SlaveRecord& slave = ctx_.slaves[p];
  const auto tag = static_cast<std::uint8_t>(p);
    const std::uint16_t station = ctx_.plan[p].station_address;
  std::array<std::uint8_t, std::size_t{2} * reg::kFmmuSize> bytes{};
  bool added = false;
  const auto write = [&](std::uint16_t ado, std::size_t length) {
    added = frame.add(*this, tag, Command::FPWR, make_address(station, ado), static_cast<std::uint16_t>(length),
                      ConstByteSpan(bytes.data(), length));
  };
  const auto read = [&](std::uint16_t ado, std::uint16_t length) {
    added = frame.add(*this, tag, Command::FPRD, make_address(station, ado), length);
  };
  if (is_al_step(r.state())) {
    if (r.sub == 0) {
      store_le16(bytes.data(), al_control_value(target_al_state(r.state()), acknowledges(r)));
      write(reg::kAlControl, 2);
    } else {
      read(reg::kAlStatus, kAlStatusReadLength);
    }
  } else {
    switch (r.state()) {
      case RecoveryState::addressing:
        store_le16(bytes.data(), station);
        added = frame.add(*this, tag, Command::APWR, make_address(r.adp, reg::kStationAddress), 2, ConstByteSpan(bytes.data(), 2));
        break;
      case RecoveryState::identifying:
        if (r.sub < 2) {
          bytes[0] = r.sub == 0 ? 0x02 : 0x00;  // SII to ECAT, forced, then kept
          write(reg::kSiiConfig, 1);
        } else if (r.sub % 2 == 0) {
          store_le16(bytes.data(), reg::kSiiCommandRead);
          store_le32(bytes.data() + 2, static_cast<std::uint32_t>(sii::kVendorId + r.words));
          write(reg::kSiiControl, 6);
        } else {
          read(reg::kSiiControl, kSiiBlockLength);
        }
        break;
      case RecoveryState::mailbox:
        fill_mailbox_sms(slave.setup, bytes.data());
        write(reg::sync_manager(0), std::size_t{2} * reg::kSyncManagerSize);
        break;
      case RecoveryState::process_data:
        if (r.sub == 0) {
          fill_process_data_sms(slave.setup, ctx_.plan[p], bytes.data());
          write(reg::sync_manager(2), std::size_t{2} * reg::kSyncManagerSize);
        } else {
          fill_fmmus(slave.setup, ctx_.plan[p], ctx_.layout.slaves[p], bytes.data());
          write(reg::fmmu(kFmmuOutputs), std::size_t{2} * reg::kFmmuSize);
        }
        break;
      case RecoveryState::clock:
        if (r.sub == kReadStandIn && clock_stand_in() == kMaxSlaves) r.sub = 1;  // the stand-in left: its old offset stays
        if (r.sub == 0) {
          read(reg::kDcSystemTime, kDcBlockLength);
        } else if (r.sub == kReadStandIn) {
          const std::size_t q = clock_stand_in();
          added = frame.add(*this, tag, Command::FPRD, make_address(ctx_.plan[q].station_address, reg::kDcSystemTime), 8);
        } else if (r.sub == 1) {
          store_le64(bytes.data(), r.offset);
          store_le32(bytes.data() + 8, ctx_.report.delays[p]);
          write(reg::kDcSystemTimeOffset, 12);
        } else {
          store_le16(bytes.data(), kDcLoopRestart);
          write(reg::kDcSpeedCounterStart, 2);
        }
        break;
      case RecoveryState::sync0: {
        const auto period = static_cast<std::uint64_t>(ctx_.options.cycle_time);
        if (r.sub == 0) {
          write(reg::kDcCyclicUnitControl, 2);  // unit to ECAT, activation off
        } else if (r.sub == 1) {
          store_le32(bytes.data(), static_cast<std::uint32_t>(period));
          write(reg::kDcSync0CycleTime, 4);
        } else if (r.sub == 2) {
          // In phase with every other slave's SYNC0: the bring-up's start plus whole periods.
          const std::uint64_t earliest = dc_.latest_reference_time() + kSync0MarginPeriods * period;
          const std::uint64_t base = ctx_.report.sync0_start;
          const std::uint64_t start = earliest <= base ? base : base + ((earliest - base) / period + 1) * period;
          store_le64(bytes.data(), start);
          write(reg::kDcStartTime, 8);
        } else {
          bytes[0] = static_cast<std::uint8_t>(reg::kDcActivateCyclic | reg::kDcActivateSync0);
          write(reg::kDcActivation, 1);
        }
        break;
      }
      default:
        return false;
    }
  }
  return added;
}

void RecoveryService::add_datagrams(CycleFrame& frame) noexcept {
  if (ctx_.state != MasterState::op) return;
  datagrams_this_cycle_ = 0;
  if (!ctx_.options.online_recovery) return;
  const unsigned budget = ctx_.options.recovery_datagrams_per_cycle;
  bool searching = false;
  for (const SlaveRecord& slave : ctx_.slaves) {
    const RecoveryProgress& r = slave.recovery;
    searching = searching || r.state() == RecoveryState::searching || r.state() == RecoveryState::refused;
  }
  // One place for a search when something is searched for and the budget has more than one.
  const unsigned for_steps = searching && budget > 1 ? budget - 1 : budget;
  for (std::size_t i = 0; i < kMaxSlaves && datagrams_this_cycle_ < for_steps; ++i) {
    const std::size_t p = (rotate_ + i) % kMaxSlaves;
    const RecoveryState s = ctx_.slaves[p].recovery.state();
    if (s == RecoveryState::idle || s == RecoveryState::searching || s == RecoveryState::refused || s == RecoveryState::failed ||
        s == RecoveryState::startup_sdos) {
      continue;
    }
    if (add_step(frame, p)) ++datagrams_this_cycle_;
  }
  rotate_ = (rotate_ + 1) % kMaxSlaves;
  if (searching && datagrams_this_cycle_ < budget && add_search(frame)) ++datagrams_this_cycle_;
  stats_.datagrams += datagrams_this_cycle_;
  if (datagrams_this_cycle_ > stats_.max_datagrams_per_cycle) {
    stats_.max_datagrams_per_cycle = datagrams_this_cycle_;
  }
}

void RecoveryService::check_identity(std::size_t p) noexcept {
  const RecoveryProgress& r = ctx_.slaves[p].recovery;
  const std::uint32_t vendor = word_pair(r.sii, 0);
  const std::uint32_t product = word_pair(r.sii, 2);
  const std::uint32_t revision = word_pair(r.sii, 4);
  const std::uint32_t serial = word_pair(r.sii, 6);
  const bool identified = ctx_.slaves[p].identified;
  const bool its_own = identified && vendor == ctx_.slaves[p].identity.vendor_id && product == ctx_.slaves[p].identity.product_code &&
                       revision == ctx_.slaves[p].identity.revision && serial == ctx_.slaves[p].identity.serial_number;
  // Another slave's device (found at the place this one expected, whatever its type: a junction
  // where a drive was expected is no foreign device when the junction is searched for): it gets
  // that slave's station address instead of 0, so that slave's search by address finds it next.
  const std::size_t owner = its_own ? kMaxSlaves : owner_of_identity(p);
  if (owner < kMaxSlaves) {
    take_input(p, RecoveryInput::not_this_one);
    ctx_.slaves[p].recovery.handover = ctx_.plan[owner].station_address;
    ctx_.slaves[owner].recovery.lost_address = true;
    ctx_.slaves[owner].recovery.by_address = true;
    return;
  }
  if (vendor != ctx_.plan[p].vendor_id || product != ctx_.plan[p].product_code) {
    take_input(p, RecoveryInput::foreign);
    return;
  }
  if (identified) {
    const FoundSlave& before = ctx_.slaves[p].identity;
    if (revision != before.revision) {
      take_input(p, RecoveryInput::foreign);
      return;
    }
    if (serial != before.serial_number) {
      // Same type, another serial number, and no slave searched for has it.
      take_input(p, RecoveryInput::not_this_one);
      return;
    }
  } else if (revision != ctx_.plan[p].revision) {
    take_input(p, RecoveryInput::foreign);
    return;
  }
  take_input(p, RecoveryInput::step_done);
}

std::size_t RecoveryService::owner_of_identity(std::size_t finder) const noexcept {
  const std::array<std::uint16_t, 8>& w = ctx_.slaves[finder].recovery.sii;
  for (std::size_t q = 0; q < kMaxSlaves; ++q) {
    if (q == finder || (ctx_.slaves[q].recovery.state() != RecoveryState::searching && ctx_.slaves[q].recovery.state() != RecoveryState::failed)) continue;
    if (!ctx_.slaves[q].identified) continue;
    const FoundSlave& before = ctx_.slaves[q].identity;
    if (word_pair(w, 0) == before.vendor_id && word_pair(w, 2) == before.product_code && word_pair(w, 4) == before.revision &&
        word_pair(w, 6) == before.serial_number) {
      return q;
    }
  }
  return kMaxSlaves;
}

bool RecoveryService::addressing_at(std::uint16_t adp, std::size_t except) const noexcept {
  for (std::size_t q = 0; q < kMaxSlaves; ++q) {
    if (q != except && ctx_.slaves[q].recovery.state() == RecoveryState::addressing && ctx_.slaves[q].recovery.adp == adp) return true;
  }
  return false;
}

std::size_t RecoveryService::clock_stand_in() const noexcept {
  const SlaveMask candidates = ctx_.dc_slaves & ctx_.monitor.in_exchange();
  for (std::size_t q = ctx_.reference_position() + 1; q < kMaxSlaves; ++q) {
    if ((candidates & slave_bit(q)) != 0) return q;
  }
  return kMaxSlaves;
}

hal::Nanoseconds RecoveryService::hold_off(std::uint8_t failures) const noexcept {
  hal::Nanoseconds wait = ctx_.options.recovery_hold_off;
  for (std::uint8_t k = 1; k < failures && wait < ctx_.options.recovery_hold_off_max; ++k) wait *= 2;
  return wait < ctx_.options.recovery_hold_off_max ? wait : ctx_.options.recovery_hold_off_max;
}

void RecoveryService::separate_devices(std::size_t p) noexcept {
  RecoveryProgress& r = ctx_.slaves[p].recovery;
  r.withdraw = true;
  r.handover = 0;
  ++stats_.shared_addresses;
}

void RecoveryService::on_step_answer(std::size_t p, const DatagramView& d) noexcept {
  RecoveryProgress& r = ctx_.slaves[p].recovery;
  if (d.wkc() > 1 && r.state() != RecoveryState::addressing) {
    // Two devices answer its station address (one given it by a wrong guess while the other kept
    // it): neither can be configured by address. The address is withdrawn from both (FPWR 0x0010
    // = 0 at it, the search's first datagram) and each is then found blank at its own place.
    separate_devices(p);
    take_input(p, RecoveryInput::gone);
    return;
  }
  if (d.wkc() != 1) {
    if (++r.silent >= kGonePeriods) take_input(p, RecoveryInput::gone);
    return;  // same step again next period
  }
  r.silent = 0;
  const std::uint8_t* data = d.data().data();
  if (is_al_step(r.state())) {
    if (r.sub == 0) {
      r.sub = 1;
      return;
    }
    const std::uint16_t status = load_le16(data);
    ctx_.slaves[p].note_al_status(data);
    const auto wanted = static_cast<std::uint16_t>(target_al_state(r.state()));
    if ((status & reg::kAlErrorBit) != 0) {
      // Acknowledge and ask again; after an acknowledging request ask for the state alone, as bring-up
      // does: a device that emulates its state machine (a junction) copies AL control into AL status,
      // acknowledge bit included, so only a request without it clears the bit there.
      const bool acknowledged = acknowledges(r);
      r.acknowledge = !acknowledged;
      r.plain_request = acknowledged;
      r.sub = 0;
    } else if ((status & reg::kAlStateMask) == wanted) {
      take_input(p, RecoveryInput::step_done);
    }
    return;
  }
  switch (r.state()) {
    case RecoveryState::addressing:
    case RecoveryState::mailbox:
      take_input(p, RecoveryInput::step_done);
      break;
    case RecoveryState::identifying: {
      if (r.sub < 2 || r.sub % 2 == 0) {
        ++r.sub;
        break;
      }
      const std::uint16_t control = load_le16(data);
      if ((control & reg::kSiiBusy) != 0) break;  // poll again
      if ((control & reg::kSiiCommandError) != 0) {
        r.sub = 2;  // command refused: issue it again
        break;
      }
      const std::size_t got = (control & reg::kSiiRead8Bytes) != 0 ? 4 : 2;
      for (std::size_t k = 0; k < got && r.words < kIdentityWords; ++k) {
        r.sii[r.words++] = load_le16(data + 6 + 2 * k);
      }
      if (r.words >= kIdentityWords) {
        check_identity(p);
      } else {
        r.sub = 2;
      }
      break;
    }
    case RecoveryState::process_data:
      if (r.sub == 0) {
        r.sub = 1;
      } else {
        take_input(p, RecoveryInput::step_done);
      }
      break;
    case RecoveryState::clock:
      if (r.sub == 0) {
        if (dc_.frame_reference_time() == 0) break;  // the reference did not answer: read again
        const std::uint64_t system_time = load_le64(data);
        const std::uint64_t old_offset = load_le64(data + 16);
        if (p == ctx_.reference_position()) {
          // The reference itself restarted (its time began again from its power-up): the network's
          // time is what the other clocks kept. Its old offset now, a stand-in's time next frame.
          r.offset = old_offset;
          r.sub = clock_stand_in() == kMaxSlaves ? 1 : kReadStandIn;
          break;
        }
        if (ctx_.reference_out()) break;  // the reference's time is not the network's yet: read again
        // Its system time should equal the reference's at the instant the frame passed it: the
        // reference's time (read by the same frame) plus the propagation delay between them.
        r.offset = old_offset + (dc_.frame_reference_time() + ctx_.report.delays[p]) - system_time;
        r.sub = 1;
      } else if (r.sub == kReadStandIn) {
        if (dc_.frame_reference_time() == 0) break;  // the reference did not answer: read again
        // The reference's time at the instant the frame passed it should be the stand-in's then less
        // the propagation delay between them (the reference's own delay is 0).
        const std::size_t q = clock_stand_in();
        if (q != kMaxSlaves) r.offset += (load_le64(data) - ctx_.report.delays[q]) - dc_.frame_reference_time();
        r.sub = 1;
      } else if (r.sub == 1) {
        r.sub = 2;
      } else {
        take_input(p, RecoveryInput::step_done);
      }
      break;
    case RecoveryState::sync0:
      if (r.sub < 3) {
        ++r.sub;
      } else {
        take_input(p, RecoveryInput::step_done);
      }
      break;
    default:
      break;
  }
}

void RecoveryService::on_answer(std::uint8_t tag, const DatagramView& d) noexcept {
  // On the ring, an answer lost with a copy is no answer, as when the frame is lost: not a silent
  // period of the slave (three in a row would take it for gone and start the attempt again).
  if (answer_lost_with_a_copy(ctx_.link.copy_returns(), d)) return;
  const std::size_t p = tag & static_cast<std::uint8_t>(~kSearchTag);
  if ((tag & kSearchTag) != 0) {
    on_search_answer(p, d);
  } else {
    on_step_answer(p, d);
  }
}

void RecoveryService::settle(CycleResult& /*result*/) noexcept {
  if (ctx_.state != MasterState::op || !ctx_.options.online_recovery) return;
  const hal::Nanoseconds now = ctx_.now();
  const SlaveMask out = ctx_.monitor.out_of_exchange() & ctx_.operated() & ~reintegration_.reintegrating();
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    const RecoveryProgress& r = ctx_.slaves[p].recovery;
    const SlaveMask bit = slave_bit(p);
    if (r.state() == RecoveryState::idle) {
      // A slave the operator parked below OP (ctl states) is not taken back behind their back.
      if ((out & bit) != 0 && !ctx_.slaves[p].parked) take_input(p, RecoveryInput::lost);
      continue;
    }
    // States with nothing to write for this slave are done at once.
    const bool skip = (r.state() == RecoveryState::mailbox && !ctx_.plan[p].mailbox) ||
                      (r.state() == RecoveryState::process_data && ctx_.plan[p].output_bytes + ctx_.plan[p].input_bytes == 0) ||
                      (r.state() == RecoveryState::clock && (ctx_.dc_slaves & bit) == 0) ||
                      (r.state() == RecoveryState::sync0 && (!ctx_.plan[p].dc_sync0 || (ctx_.dc_slaves & bit) == 0)) ||
                      (r.state() == RecoveryState::startup_sdos && sdos_.done(p));
    if (skip) {
      take_input(p, RecoveryInput::step_done);
      continue;
    }
    if (r.state() == RecoveryState::failed) {
      if (now >= r.deadline) take_input(p, RecoveryInput::retry);
      continue;
    }
    // A refused start-up SDO (the mapping could not be set) fails the attempt at once.
    if (r.state() == RecoveryState::startup_sdos && r.sdo_refused) {
      take_input(p, RecoveryInput::timeout);
      continue;
    }
    if (r.state() != RecoveryState::searching && r.state() != RecoveryState::refused && now > r.deadline) {
      take_input(p, RecoveryInput::timeout);
    }
  }
  ctx_.monitor.set_recovering(recovering());
}

}  // namespace rescue::ecat
