// Master bring-up: count, reset, identify, compare, address, mailboxes, process data, states.
#include <algorithm>
#include <cstring>
#include <numeric>

#include "ecat/master/master.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/sii/sii.hpp"
#include "ecat/master/slave_config.hpp"
#include "ecat/master/station_io.hpp"

namespace rescue::ecat {
namespace {

std::uint32_t u32(std::size_t v) noexcept { return static_cast<std::uint32_t>(v); }

// Bring-up frames whose datagrams may be repeated are sent again when they do not come back.
constexpr unsigned kBringUpAttempts = 3;
constexpr hal::Nanoseconds kWaitingInterval = hal::kNsPerSec;  // MasterOptions::waiting

// Reset values real masters broadcast before configuring (SOEM ecx_set_slaves_to_default).
struct ResetWrite {
  std::uint16_t ado;
  std::uint16_t length;
  std::uint16_t value;  // little-endian into the first bytes, rest zero
};
constexpr std::array<ResetWrite, 10> kResetWrites{{
    {0x0101, 1, 0x0000},                                     // DL control: ports on automatic loop
    {reg::kRxErrorCounter, 8, 0x0000},                       // clear CRC/RX error counters
    {reg::kFmmuBase, 4 * reg::kFmmuSize, 0x0000},            // FMMU 0..3 off
    {reg::kSyncManagerBase, 4 * reg::kSyncManagerSize, 0x0000},  // SM 0..3 off
    {reg::kDcActivation, 1, 0x0000},                         // SYNC0/1 off
    {reg::kDcSpeedCounterStart, 2, 0x1000},                  // restart the drift control loop
    {reg::kDcTimeDiffFilterDepth, 2, 0x0C00},                // filter depths 0 (time diff), 12 (speed)
    {reg::kAlControl, 2, static_cast<std::uint16_t>(static_cast<std::uint16_t>(reg::AlState::init) | reg::kAlErrorBit)},
    {reg::kSiiConfig, 1, 0x0002},                            // force EEPROM access to ECAT ...
    {reg::kSiiConfig, 1, 0x0000},                            // ... and keep it there
}};

SyncManagerSetup sm_from_sii(const sii::Sii& image, std::size_t n) noexcept {
  SyncManagerSetup sm;
  if (n < image.sync_managers.size()) {
    const sii::SyncManager& s = image.sync_managers[n];
    sm.start = s.start_address;
    sm.length = s.length;
    sm.control = s.control;
    sm.present = s.start_address != 0 && s.type != sii::SyncManagerType::unused;
  }
  return sm;
}

// What a start-up transfer that did not end ok was: the slave's abort or mailbox error is a
// refusal; no answer in time is a timeout, never called a refusal; an answer the client could not
// use is malformed; a slave without a mailbox does not support it.
Errc errc_of(SdoOutcome outcome) noexcept {
  switch (outcome) {
    case SdoOutcome::aborted:
    case SdoOutcome::mailbox_error: return Errc::refused;
    case SdoOutcome::timeout: return Errc::timeout;
    case SdoOutcome::no_mailbox: return Errc::unsupported;
    case SdoOutcome::too_long: return Errc::capacity_exceeded;
    case SdoOutcome::ok:
    case SdoOutcome::bad_response: break;
  }
  return Errc::malformed;
}

}  // namespace

const char* to_string(MasterState state) noexcept {
  switch (state) {
    case MasterState::idle: return "idle";
    case MasterState::failed: return "failed";
    case MasterState::safe_op: return "SAFE-OP";
    case MasterState::going_op: return "going to OP";
    case MasterState::op: return "OP";
  }
  return "?";
}

Master::Master(hal::Nic& nic, const NetworkPlan& plan, const ProcessImageLayout& layout, ByteSpan image) noexcept
    : nic_(nic),
      main_port_(nic),
      link_(main_port_),
      plan_(plan),
      layout_(layout),
      image_(image),
      monitor_(plan, layout),
      mailbox_(plan),
      context_{link_, plan_, layout_, image_, options_, report_, state_, cycle_, slaves_, monitor_, dc_slaves_, reference_station_},
      dc_reference_(context_),
      process_data_(context_),
      ring_(context_),
      ring_dc_(context_, ring_, dc_reference_, main_port_, ring_port_),
      probes_(context_),
      reintegration_(context_),
      pdo_setup_(context_, mailbox_),
      recovery_(context_, dc_reference_, reintegration_, pdo_setup_, mailbox_),
      diagnostics_(context_),
      op_step_(context_),
      register_read_(context_),
      slave_states_(context_),
      rescan_(context_),
      mailbox_service_(context_, mailbox_) {}

Status Master::fail(const char* step, const Error& error) noexcept {
  report_.failed_step = step;
  report_.error = error;
  state_ = MasterState::failed;
  return error;
}

Status Master::bring_up(const MasterOptions& options) noexcept {
  options_ = options;
  if (options_.sync0_target_phase < 0) options_.sync0_target_phase = options_.cycle_time / 2;
  report_ = BringUpReport{};
  report_.started_at = link_.clock().now();
  const std::uint64_t frames_before = link_.stats().exchanges;
  bring_up_frames_before_ = frames_before;
  state_ = MasterState::idle;
  cycle_ = 0;
  // Nothing of an earlier bring-up carries over.
  monitor_.start(0);
  // With a ring a short merged counter is the sum of what each port reached: it cannot be placed as
  // "the first k of the branch" (link_monitor.cpp), only by the probes.
  monitor_.set_redundant(link_.redundant());
  ring_.stop();
  ring_dc_.reset();
  reintegration_.reset();
  recovery_.reset();
  diagnostics_.reset();
  for (SlaveRecord& record : slaves_) {
    record.recovery = RecoveryProgress{};
    record.setup = SlaveSetup{};
    record.identified = false;
  }
  if (image_.size() < layout_.total_bytes) {
    return fail("plan", make_error(Errc::invalid_argument, "image smaller than the layout", u32(image_.size()), layout_.total_bytes));
  }
  std::memset(image_.data(), 0, image_.size());
  // The reference time's datagram, then one LRW per branch.
  const std::size_t cyclic_bytes = std::accumulate(
      layout_.branches.begin(), layout_.branches.end(), kDatagramOverhead + 8,
      [](std::size_t sum, const BranchLayout& branch) { return sum + kDatagramOverhead + branch.length; });
  if (cyclic_bytes + kCycleFrameReserve > kMaxEcatPayload) {
    return fail("plan", make_error(Errc::capacity_exceeded, "process image does not fit one frame", u32(cyclic_bytes)));
  }

  // Bring-up's repeated exchanges wait out a host that did not run the segment's end for a while
  // (DatagramLink::set_repeat_silence); after bring-up nothing repeats by blocking.
  link_.set_repeat_silence(options_.repeat_silence);
  Status st = check_stop("count");
  if (st.ok()) st = count_and_reset();
  if (st.ok()) st = check_stop("identify");
  if (st.ok()) st = identify();
  if (st.ok()) st = check_stop("address");
  if (st.ok()) st = assign_addresses();
  if (st.ok()) st = check_stop("INIT");
  if (st.ok()) {
    const Status init = request_al_state(link_, plan_, operated(), reg::AlState::init, options_.al, report_.al_failure);
    if (!init.ok()) st = fail("INIT", init.error());
  }
  if (st.ok()) st = check_stop("mailbox");
  if (st.ok()) st = configure_mailboxes();
  if (st.ok()) st = check_stop("PRE-OP");
  if (st.ok()) {
    const Status pre_op = request_al_state(link_, plan_, operated(), reg::AlState::pre_op, options_.al, report_.al_failure);
    if (!pre_op.ok()) st = fail("PRE-OP", pre_op.error());
  }
  if (st.ok()) st = check_stop("PRE-OP SDO");
  if (st.ok()) st = run_startup_sdos();
  if (st.ok()) st = check_stop("process data");
  if (st.ok()) st = configure_process_data();
  if (st.ok()) st = check_stop("DC");
  if (st.ok()) st = configure_dc();
  if (st.ok()) st = check_stop("DC drift");
  if (st.ok()) st = compensate_static_drift();
  if (st.ok()) st = check_stop("SYNC0");
  if (st.ok()) st = start_sync0();
  if (st.ok()) st = check_stop("SAFE-OP");
  if (st.ok()) {
    const Status safe_op = request_al_state(link_, plan_, operated(), reg::AlState::safe_op, options_.al, report_.al_failure);
    if (!safe_op.ok()) st = fail("SAFE-OP", safe_op.error());
  }
  link_.set_repeat_silence(0);
  report_.frames = link_.stats().exchanges - frames_before;
  if (!st.ok()) return st;
  report_.safe_op_at = link_.clock().now();
  ring_.start();

  // Cyclic operation starts in SAFE-OP; the first cycles request OP (slaves want valid outputs
  // flowing before they accept it).
  state_ = MasterState::going_op;
  op_step_.start();
  next_wakeup_ = dc_sync_.first_wakeup(link_.clock().now(), last_reference_read_at_, last_reference_time_);
  return Status::success();
}

Status Master::check_stop(const char* step) noexcept {
  if (report_.step_count < report_.steps.size()) {
    report_.steps[report_.step_count++] = BringUpStepMark{step, link_.clock().now(), link_.stats().exchanges - bring_up_frames_before_};
  }
  if (options_.stop_requested == nullptr || !options_.stop_requested()) return Status::success();
  return fail(step, make_error(Errc::refused, "stopped on request"));
}

// The first contact's BRD went out on both ports: a closed ring brings the main copy back on the ring
// NIC, through every slave. A ring NIC that received nothing (its cable not in the segment's last
// free port, or the wrong interface), or a ring open already, refuses the bring-up with the reason:
// never a silent single-port run. (Position-addressed bring-up datagrams go by the main port only,
// so an open ring could not be brought up whole.)
Status Master::check_ring_closes() noexcept {
  const CopyReturns& r = link_.copy_returns();
  if (r.main_back && r.main_on == Port::ring) return Status::success();
  const std::uint32_t main_reach = r.main_back && r.counters.datagrams > 0 ? r.counters.main[0] : 0U;
  const std::uint32_t ring_reach = r.ring_back && r.counters.datagrams > 0 ? r.counters.ring[0] : 0U;
  const bool ring_nic_heard = (r.main_back && r.main_on == Port::ring) || (r.ring_back && r.ring_on == Port::ring);
  if (!ring_nic_heard) {
    return fail("ring", make_error(Errc::not_found,
                                   "the ring does not close: the ring NIC received nothing (is the segment's last free "
                                   "port cabled to it?)",
                                   main_reach));
  }
  return fail("ring", make_error(Errc::refused, "the ring is open at bring-up", main_reach, ring_reach));
}

Status Master::count_and_reset() noexcept {
  // First contact, patiently: one BRD per frame_timeout until a frame comes back or
  // first_contact_timeout has passed. At least kBringUpAttempts are sent whatever the times.
  std::array<std::uint8_t, 2> type{};
  const hal::Nanoseconds give_up_at = link_.clock().now() + options_.first_contact_timeout;
  Result<std::uint16_t> counted = make_error(Errc::timeout, "no frame came back");
  report_.first_contact_frames = 0;
  const hal::Nanoseconds began = link_.clock().now();
  hal::Nanoseconds next_word = began + kWaitingInterval;
  const bool forever = options_.first_contact_timeout <= 0;
  for (;;) {
    ++report_.first_contact_frames;
    counted = link_.transfer(Command::BRD, make_address(0, reg::kType), ByteSpan(type), options_.frame_timeout, 1);
    if (counted.ok() || counted.error().code != Errc::timeout) break;
    const hal::Nanoseconds now = link_.clock().now();
    if (!forever && report_.first_contact_frames >= kBringUpAttempts && now >= give_up_at) break;
    if (now >= next_word) {
      next_word += kWaitingInterval;
      if (options_.waiting != nullptr) {
        options_.waiting(BringUpWait{"count", now - began, report_.first_contact_frames, options_.first_contact_timeout},
                         options_.waiting_context);
      }
      const Status stop = check_stop("count");
      if (!stop.ok()) return stop;
    }
  }
  if (!counted.ok() && counted.error().code == Errc::timeout) {
    const auto waited_ms = static_cast<std::uint32_t>(options_.first_contact_timeout / hal::kNsPerMs);
    return fail("count", make_error(Errc::timeout,
                                    "no EtherCAT frame came back: is the segment cabled to this interface and powered, "
                                    "or `rescue-motion sim --iface` running at its end?",
                                    report_.first_contact_frames, waited_ms));
  }
  if (!counted.ok()) return fail("count", counted.error());
  report_.slaves_counted = counted.value();
  if (counted.value() == 0) return fail("count", make_error(Errc::not_found, "no slave answers"));
  if (link_.redundant()) {
    const Status ring = check_ring_closes();
    if (!ring.ok()) return ring;
  }

  FrameBuilder& frame = link_.begin();
  std::array<std::uint8_t, std::size_t{4} * reg::kFmmuSize> bytes{};
  for (const ResetWrite& w : kResetWrites) {
    bytes.fill(0);
    store_le16(bytes.data(), w.value);
    const Result<DatagramSlot> slot =
        frame.add(Command::BWR, link_.index(), make_address(0, w.ado), w.length, ConstByteSpan(bytes.data(), w.length));
    if (!slot.ok()) return fail("reset", slot.error());
  }
  const Result<FrameView> back = link_.exchange(options_.frame_timeout, kBringUpAttempts);
  if (!back.ok()) return fail("reset", back.error());
  return Status::success();
}

Status Master::identify() noexcept {
  const std::size_t n = std::min<std::size_t>(report_.slaves_counted, kMaxFoundSlaves);
  const Result<SiiReadStats> read = read_sii_images(link_, Span<SiiImage>(sii_.data(), n), options_.sii, options_.sii_cache);
  if (!read.ok()) return fail("identify", read.error());
  report_.sii = read.value();
  std::array<SlaveSetup, kMaxFoundSlaves> found_setup{};
  report_.found.clear();
  for (std::size_t a = 0; a < n; ++a) {
    if (sii_[a].error.code != Errc::ok) return fail("identify", sii_[a].error);
    const Result<sii::Sii> parsed = sii::Sii::parse(sii_[a].view(), sii::ChecksumPolicy::require);
    if (!parsed.ok()) {
      Error e = parsed.error();
      e.detail0 = u32(a);  // which slave; the parser's `what` names the field
      return fail("identify", e);
    }
    if (!sii_[a].from_cache && options_.sii_cache != nullptr) (void)options_.sii_cache->remember(sii_[a]);  // a full cache reads whole
    const sii::Sii& info = parsed.value();
    FoundSlave f;
    f.vendor_id = info.identity.vendor_id;
    f.product_code = info.identity.product_code;
    f.revision = info.identity.revision;
    f.serial_number = info.identity.serial_number;
    f.station_alias = info.config.station_alias;
    f.output_bits = info.default_bits_of_sync_manager(2);
    f.input_bits = info.default_bits_of_sync_manager(3);
    f.pdo_sizes_known = !info.rx_pdos.empty() || !info.tx_pdos.empty();
    const std::string_view name = info.name();
    // An SII without a name string gives an empty view whose data() may be null: copy nothing.
    if (!name.empty()) std::memcpy(f.name.data(), name.data(), std::min(name.size(), f.name.size() - 1));
    (void)report_.found.push_back(f);  // capacity kMaxFoundSlaves >= n

    SlaveSetup& found = found_setup[a];
    for (std::size_t s = 0; s < found.sm.size(); ++s) found.sm[s] = sm_from_sii(info, s);
    found.mailbox = info.standard_mailbox.present() && info.supports(sii::kMailboxCoE);
    found.complete_access = found.mailbox && info.has_general && (info.general.coe_details & sii::kCoeDetailSdoCompleteAccess) != 0;
    if (found.mailbox) {
      // The standard mailbox words are authoritative for SM0/SM1 (the SM category may be absent).
      found.sm[0] = SyncManagerSetup{info.standard_mailbox.receive_offset, info.standard_mailbox.receive_size,
                                     found.sm[0].present ? found.sm[0].control : kSmControlMailboxOut, true};
      found.sm[1] = SyncManagerSetup{info.standard_mailbox.send_offset, info.standard_mailbox.send_size,
                                     found.sm[1].present ? found.sm[1].control : kSmControlMailboxIn, true};
    }
  }
  report_.match = match_network(plan_, report_.found.span(), options_.held_out);
  record_identities();
  if (report_.match.fatal) {
    const auto fatal = std::count_if(report_.match.differences.begin(), report_.match.differences.end(),
                                     [](const NetworkDifference& d) { return is_fatal(d.kind); });
    return fail("compare", make_error(Errc::mismatch, "network differs from the plan", u32(static_cast<std::size_t>(fatal)), u32(n)));
  }
  for (std::size_t a = 0; a < n; ++a) {
    const std::uint8_t slot = report_.match.slot_of_found[a];
    if (slot != kNoPosition) slaves_[slot].setup = found_setup[a];
  }
  return Status::success();
}

Status Master::assign_addresses() noexcept {
  FrameBuilder& frame = link_.begin();
  std::array<std::uint8_t, 2> address{};
  for (std::size_t a = 0; a < report_.found.size(); ++a) {
    const std::uint8_t slot = report_.match.slot_of_found[a];
    if (slot == kNoPosition) continue;
    store_le16(address.data(), plan_[slot].station_address);
    const Result<DatagramSlot> added = frame.add(Command::APWR, link_.index(),
                                                 make_address(position_adp(static_cast<std::uint16_t>(a)), reg::kStationAddress),
                                                 2, ConstByteSpan(address));
    if (!added.ok()) return fail("address", added.error());
  }
  const Result<FrameView> back = link_.exchange(options_.frame_timeout, kBringUpAttempts);
  if (!back.ok()) return fail("address", back.error());
  for (const DatagramView d : back.value()) {
    // cppcheck-suppress useStlAlgorithm ; frame views have no standard iterators
    if (d.wkc() != 1) return fail("address", make_error(Errc::io_error, "station address not taken", d.index_in_frame()));
  }
  // Read the addresses back through them: each must answer exactly once.
  SlaveMask confirmed = 0;
  const Status st = for_each_slave(
      link_, plan_, present(), Command::FPRD, reg::kStationAddress, 2, [](std::size_t, ByteSpan) {},
      [&](std::size_t p, std::uint16_t wkc, ConstByteSpan data) {
        if (wkc == 1 && load_le16(data.data()) == plan_[p].station_address) confirmed |= slave_bit(p);
      },
      options_.frame_timeout);
  if (!st.ok()) return fail("address", st.error());
  if (confirmed != present()) {
    return fail("address", make_error(Errc::mismatch, "station address not confirmed", present() & ~confirmed));
  }
  return Status::success();
}

Status Master::configure_mailboxes() noexcept {
  SlaveMask with_mailbox = 0;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((operated() & slave_bit(p)) != 0 && plan_[p].mailbox) {
      if (!slaves_[p].setup.mailbox) return fail("mailbox", make_error(Errc::unsupported, "planned CoE mailbox missing in SII", u32(p)));
      with_mailbox |= slave_bit(p);
      mailbox_.configure(p, slaves_[p].setup.sm[0].start, slaves_[p].setup.sm[0].length, slaves_[p].setup.sm[1].start, slaves_[p].setup.sm[1].length);
    }
  }
  SlaveMask refused = 0;
  const Status st = for_each_slave(
      link_, plan_, with_mailbox, Command::FPWR, reg::sync_manager(0), 2 * reg::kSyncManagerSize,
      [&](std::size_t p, ByteSpan out) { fill_mailbox_sms(slaves_[p].setup, out.data()); },
      [&](std::size_t p, std::uint16_t wkc, ConstByteSpan) {
        if (wkc != 1) refused |= slave_bit(p);
      },
      options_.frame_timeout);
  if (!st.ok()) return fail("mailbox", st.error());
  if (refused != 0) return fail("mailbox", make_error(Errc::io_error, "mailbox SyncManagers not written", refused));
  return Status::success();
}

Status Master::set_up_pdo_mappings() noexcept {
  SlaveMask busy = 0;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    slaves_[p].pdo = PdoSetup{};
    if ((operated() & slave_bit(p)) == 0 || plan_[p].pdo == nullptr || !mailbox_.has_mailbox(p)) continue;
    slaves_[p].pdo.start(static_cast<std::uint8_t>(p), plan_[p].pdo, slaves_[p].setup.complete_access);
    busy |= slave_bit(p);
  }
  // Each slave one transfer at a time (its writes stay in order), all slaves side by side: a
  // queue place each at most.
  while (busy != 0) {
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      if ((busy & slave_bit(p)) == 0) continue;
      SdoRequest request;
      if (mailbox_.free_slots() > 0 && slaves_[p].pdo.next(request) && !mailbox_.submit(request)) slaves_[p].pdo.unsubmit();
    }
    const Status ran = mailbox_.run(link_, options_.frame_timeout, options_.startup_sdo_timeout);
    SdoCompletion done;
    while (mailbox_.pop_master_completion(done)) {
      if (done.request.position < kMaxSlaves) slaves_[done.request.position].pdo.on_completion(done);
    }
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      const PdoSetup& mapping = slaves_[p].pdo;
      if ((busy & slave_bit(p)) == 0) continue;
      if (mapping.failed()) {
        report_.failed_sdo = mapping.failure();
        const SdoRequest& r = mapping.failure().request;
        return fail("PRE-OP SDO", make_error(errc_of(mapping.failure().outcome), "PDO mapping not set", u32(p),
                                             (static_cast<std::uint32_t>(r.index) << 8U) | r.subindex));
      }
      if (mapping.finished()) {
        busy &= ~slave_bit(p);
        report_.pdo_reads += mapping.reads();
        report_.pdo_writes += mapping.writes();
        if (mapping.writes() != 0) report_.pdo_rewritten |= slave_bit(p);
      }
    }
    if (!ran.ok()) return fail("PRE-OP SDO", ran.error());
  }
  return Status::success();
}

Status Master::run_startup_sdos() noexcept {
  const Status pdo = set_up_pdo_mappings();
  if (!pdo.ok()) return pdo;
  std::size_t next = 0;
  while (next < options_.startup_sdos.size()) {
    // As many as the queue holds, then run them (each slave answers in turn).
    while (next < options_.startup_sdos.size()) {
      const SdoRequest& r = options_.startup_sdos[next];
      if (r.position < kMaxSlaves && (operated() & slave_bit(r.position)) != 0 && !mailbox_.submit(r)) break;
      ++next;
    }
    const Status ran = mailbox_.run(link_, options_.frame_timeout, options_.startup_sdo_timeout);
    SdoCompletion done;
    while (mailbox_.pop_completion(done)) {
      if (done.outcome != SdoOutcome::ok) {
        report_.failed_sdo = done;
        const Errc code = errc_of(done.outcome);
        const char* what = code == Errc::refused   ? "start-up SDO refused"
                           : code == Errc::timeout ? "start-up SDO not answered in time"
                                                   : "start-up SDO failed";
        return fail("PRE-OP SDO", make_error(code, what, done.request.position,
                                             (static_cast<std::uint32_t>(done.request.index) << 8U) | done.request.subindex));
      }
      ++report_.startup_sdos_done;
    }
    if (!ran.ok()) return fail("PRE-OP SDO", ran.error());
  }
  return Status::success();
}

Status Master::configure_process_data() noexcept {
  SlaveMask with_data = 0;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((operated() & slave_bit(p)) == 0 || plan_[p].output_bytes + plan_[p].input_bytes == 0) continue;
    if (!slaves_[p].setup.sm[2].present || !slaves_[p].setup.sm[3].present) {
      return fail("process data", make_error(Errc::unsupported, "SII gives no SM2/SM3 for a slave with process data", u32(p)));
    }
    with_data |= slave_bit(p);
  }
  SlaveMask refused = 0;
  const auto check = [&](std::size_t p, std::uint16_t wkc, ConstByteSpan) {
    if (wkc != 1) refused |= slave_bit(p);
  };
  Status st = for_each_slave(
      link_, plan_, with_data, Command::FPWR, reg::sync_manager(2), 2 * reg::kSyncManagerSize,
      [&](std::size_t p, ByteSpan out) { fill_process_data_sms(slaves_[p].setup, plan_[p], out.data()); },
      check, options_.frame_timeout);
  if (st.ok()) {
    st = for_each_slave(
        link_, plan_, with_data, Command::FPWR, reg::fmmu(kFmmuOutputs), 2 * reg::kFmmuSize,
        [&](std::size_t p, ByteSpan out) { fill_fmmus(slaves_[p].setup, plan_[p], layout_.slaves[p], out.data()); },
        check, options_.frame_timeout);
  }
  if (!st.ok()) return fail("process data", st.error());
  if (refused != 0) return fail("process data", make_error(Errc::io_error, "SM/FMMU configuration not written", refused));
  return Status::success();
}

}  // namespace rescue::ecat
