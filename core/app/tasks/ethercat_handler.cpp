#include "core/app/tasks/ethercat_handler.hpp"

#include <cstring>

#include "drivers/cia402/cia402_enable.hpp"
#include "drivers/joint/joint_units.hpp"
#include "drivers/joint/robot_network_plan.hpp"

namespace rescue::app {
namespace {

// CiA 402 statusword: voltage enabled (bit 4) / operation enabled (bit 2) tell a powered stage.
constexpr std::uint16_t kSwOperationEnabled = 0x0004;
constexpr std::uint16_t kSwSwitchedOn = 0x0002;

std::uint16_t saturate16(std::uint32_t v) noexcept { return v > 0xFFFFu ? std::uint16_t{0xFFFF} : static_cast<std::uint16_t>(v); }

// The joint manager's demand is a record of the shared segment: a mode it never writes (it goes to
// the drive's mode of operation as it is: profile velocity, homing...) or an enable byte other than
// 0 and 1 is damage (a stray write, a bit flip). Positions are judged by the limit check (safe stop).
bool demand_whole(const RobotDemand& demand) noexcept {
  for (const JointDemand& d : demand) {
    unsigned char enable = 0;
    std::memcpy(&enable, &d.enable, 1);
    const bool mode = d.mode == 0 || d.mode == static_cast<std::int8_t>(ControlMode::cyclic_position) ||
                      d.mode == static_cast<std::int8_t>(ControlMode::cyclic_velocity) ||
                      d.mode == static_cast<std::int8_t>(ControlMode::cyclic_torque);
    if (enable > 1 || !mode) return false;
  }
  return true;
}

}  // namespace

EthercatHandler::EthercatHandler(drivers::JointBus& bus, const EthercatHandlerPorts& ports, JointMask restored_lost,
                                 const MotionIntakeSettings& intake) noexcept
    : bus_(bus),
      tracker_(*ports.reports, *ports.notices, restored_lost),
      register_relay_(bus.master(), ports.reg_requests, ports.reg_results),
      state_relay_(bus.master(), ports.states_requests, ports.states_results),
      rescan_relay_(bus.master(), ports.rescan_requests, ports.rescan_results),
      ports_(ports),
      sdo_relay_(bus, ports.sdo_requests, ports.sdo_results),
      intake_(ports.motion, intake) {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    outputs_[j].mode_of_operation = static_cast<std::int8_t>(kJoints[j].default_mode);
  }
}

void EthercatHandler::post(const HandlerEvent& event) noexcept {
  if (!events_.try_push(event)) ++events_dropped_;
}

void EthercatHandler::build_outputs() noexcept {
  RobotDemand demand{};
  if (ports_.demand->try_read(demand)) {  // else keep the last one
    if (demand_whole(demand)) {
      demand_ = demand;
    } else {
      ++damaged_demands_;  // kept the last whole one: the joint manager writes a new one every period
    }
  }
  const JointMask excluded = tracker_.excluded();
  // A joint without fresh inputs that was driven last period and that the master still holds in the
  // exchange (the frame came back late or not at all, or a short working counter is being probed)
  // is carried: no evidence about its drive, so it goes on as it was, its reference on the same path
  // and its controlword as sent; until the master takes it out of the exchange (a loss, confirmed in
  // kLossConfirmFrames) or the link's silence alarm (as long as the drives' watchdog) says that
  // nothing comes back. Before, it counted as not driven for that period: it took the joint
  // manager's reference (where it was initialized) and its drive was turned towards disabled, and
  // the next period the owner's reference restarted from there: a leap the drive could not follow
  // (0x8611 following error, both elbows in the rescue scenario; docs/motion-owner.md "A late frame").
  JointMask carried = 0;
  if (!bus_.master().monitor().silence_alarm()) {
    carried = drive_mask_ & ~feedback_.valid & ~drivers::joints_of_slaves(bus_.last_cycle().out) & ~excluded;
  }
  // The joints driven this period in position mode take the Motion owner's references (or hold).
  JointMask driven = 0;
  JointMask drive_mask = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const bool inputs = ((feedback_.valid | carried) & joint_bit(j)) != 0;
    const bool drive = demand_[j].enable && !stopping_ && !safe_stopped_ && (excluded & joint_bit(j)) == 0 && inputs;
    if (demand_[j].mode != 0) outputs_[j].mode_of_operation = demand_[j].mode;
    if (drive) drive_mask |= joint_bit(j);
    if (drive && outputs_[j].mode_of_operation == static_cast<std::int8_t>(ControlMode::cyclic_position)) {
      driven |= joint_bit(j);
    }
  }
  drive_mask_ = drive_mask;
  const std::array<double, kJointCount>& references = intake_.period(bus_.next_wakeup(), demand_, driven);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    drivers::JointOutputs& out = outputs_[j];
    const drivers::JointInputs& in = feedback_.joints[j];
    const bool valid = (feedback_.valid & joint_bit(j)) != 0;
    const bool drive = (drive_mask & joint_bit(j)) != 0;
    if (drive && !valid) {
      // Carried: the statusword is last period's, so the controlword stays as sent; the reference
      // goes on (a joint still coming back from the watchdog waits for fresh inputs).
      if ((rest_after_watchdog_ & joint_bit(j)) != 0) continue;
      reference_rad_[j] = references[j];
      out.target_position = drivers::rad_to_counts(reference_rad_[j]);
      out.target_velocity = 0;
      out.target_torque = 0;
      continue;
    }
    if (drive && (rest_after_watchdog_ & joint_bit(j)) != 0) {
      // Back from the watchdog: enabled again where it stands, not where the reference was.
      if (drivers::is_enabled(in.statusword)) {
        rest_after_watchdog_ &= ~joint_bit(j);
      } else {
        intake_.rest_at(j, drivers::counts_to_rad(in.position_actual));
        out.controlword = drivers::controlword_towards_enabled(in.statusword, out.controlword);
        out.target_position = in.position_actual;
        reference_rad_[j] = drivers::counts_to_rad(in.position_actual);  // the sample says what is sent
        out.target_velocity = 0;
        out.target_torque = 0;
        continue;
      }
    }
    if (drive) {
      out.controlword = drivers::controlword_towards_enabled(in.statusword, out.controlword);
      reference_rad_[j] = references[j];
      out.target_position = drivers::rad_to_counts(reference_rad_[j]);  // the one conversion, for the wire
    } else {
      out.controlword = drivers::controlword_towards_disabled(in.statusword);
      // A disabled drive's target follows its actual position, so enabling later moves nothing.
      if (valid) {
        out.target_position = in.position_actual;
        reference_rad_[j] = drivers::counts_to_rad(in.position_actual);
      }
    }
    // No velocity reference: the joints run in CSP, which takes positions; the fixed mapping's
    // target velocity (0x60FF, for CSV) is sent 0. The samples' velocity_ref_rad_s is the speed of
    // the position references sent (publish_sample), for a new owner to continue from.
    out.target_velocity = 0;
    out.target_torque = 0;
  }
}

void EthercatHandler::publish_sample(const drivers::JointCycleResult& result) noexcept {
  const JointMask carried = bus_.master().monitor().silence_alarm() ? 0 : ~result.out & ~tracker_.excluded();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    JointSample& s = sample_[j];
    const drivers::JointOutputs& out = outputs_[j];
    s.position_ref_rad = reference_rad_[j];
    // The rate of the references sent (the intake's; 0 where the reference is the drive's actual
    // position: back from the watchdog, or not driven).
    s.velocity_ref_rad_s = (rest_after_watchdog_ & joint_bit(j)) != 0 ? 0.0 : intake_.sent_speed(j);
    s.torque_ref_nm = drivers::per_mille_to_nm(out.target_torque, kJoints[j]);
    const bool valid = (result.valid & joint_bit(j)) != 0;
    // A joint driven this period whose inputs this frame did not bring stays reachable while it is
    // carried (build_outputs: in the exchange, no silence alarm): its values are the last its drive
    // reported. The RC tasks do not lock it, the joint manager does not judge it again.
    s.reachable = valid || ((drive_mask_ & carried) & joint_bit(j)) != 0;
    if (!valid) continue;  // last known values stay (reconfiguration step 2 reads them)
    const drivers::JointInputs& in = feedback_.joints[j];
    s.position_rad = drivers::counts_to_rad(in.position_actual);
    s.velocity_rad_s = drivers::counts_to_rad(in.velocity_actual);
    s.torque_nm = drivers::per_mille_to_nm(in.torque_actual, kJoints[j]);
    s.drive_fault = drivers::is_faulted(in.statusword);
    s.drive_error_code = in.error_code;
  }
  ports_.samples->write(sample_);
}

std::uint64_t EthercatHandler::missed_cycles(JointMask joints) const noexcept {
  std::uint64_t sum = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) != 0) sum += missed_[j];
  }
  return sum;
}

drivers::JointCycleResult EthercatHandler::cycle() noexcept {
  build_outputs();
  const drivers::JointCycleResult result = bus_.cycle(outputs_, feedback_);
  const hal::Nanoseconds now = result.received_at != 0 ? result.received_at : result.sent_at;
  handle_link_reports(result, now);
  // After the reports above: a joint back after a power cycle is queued before it shows reachable.
  publish_sample(result);
  report_waiting_for_op(result, now);
  // Reconfiguration steps 1 and 6, once the network is operational: before OP no joint is valid,
  // and the cycle that first reports OP carries inputs from before the switch; so from the next.
  const bool counting = op_seen_;
  if (result.state == ecat::MasterState::op) op_seen_ = true;
  if (counting) track_losses(result, now);
  check_limits(result, now);
  watch_drives_disabled(result, now);
  // ctl upload/download: one request judged and one completion answered, on the cyclic mailbox.
  sdo_relay_.step(result.out | tracker_.excluded(), result.state == ecat::MasterState::op);
  // ctl reg_read: one request handed to the master, one finished read answered.
  register_relay_.step();
  // ctl states: one request judged (a slave in service refused) and handed to the master, one answered.
  state_relay_.step(result.out | tracker_.excluded());
  // ctl rescan: one request handed to the master, one finished rescan answered.
  rescan_relay_.step();
  return result;
}

HandlerEvent EthercatHandler::event(HandlerEventKind kind, const drivers::JointCycleResult& result,
                                    hal::Nanoseconds now) noexcept {
  HandlerEvent e{};
  e.kind = kind;
  e.cycle = result.cycle;
  e.time = now;
  return e;
}

void EthercatHandler::handle_link_reports(const drivers::JointCycleResult& result, hal::Nanoseconds now) noexcept {
  // The ring's changes (cable redundancy: each reported once by the master), for the log.
  ecat::RingReport ring{};
  while (bus_.master().pop_ring_report(ring)) {
    HandlerEvent e = event(HandlerEventKind::ring_report, result, ring.time);
    e.ring = ring;
    post(e);
  }
  // Master's link events (lost, restored, not operational), for the log.
  drivers::JointLinkReport link{};
  while (bus_.pop_report(link)) {
    HandlerEvent e = event(HandlerEventKind::link_report, result, link.link.time);
    e.joints = link.joints;
    e.link = link.link;
    post(e);
    if (link.link.kind == ecat::LinkEventKind::watchdog_expired) {
      // The drives stopped while this handler was silent longer than their watchdog: they come back
      // holding their actual position, and the motion waits for the operator (docs/tasks.md
      // "Liveness"): a Motion owner is released and the free motion held for the operator (no RC
      // task takes it back by itself: `ctl owner N` gives it again).
      rest_after_watchdog_ |= link.joints;
      const std::uint64_t word = ports_.motion.owner->word();
      if (MotionOwner::task_of(word) < protocol::kMaxRcTasks && ports_.motion.owner->release_to_operator(word)) {
        ++owners_released_after_watchdog_;
      }
    }
    if (link.link.kind == ecat::LinkEventKind::recovered && link.link.found[0] == ecat::kRecoveredAfterPowerLoss) {
      LostJointsReport back{};
      back.cycle = result.cycle;
      back.detected_at = now;
      back.back_after_power_cycle = link.joints;
      // Full queue: counted; no automatic clear then, the operator's stays possible.
      if (!ports_.reports->try_send(back)) ++power_cycle_reports_dropped_;
    }
  }
}

void EthercatHandler::report_waiting_for_op(const drivers::JointCycleResult& result, hal::Nanoseconds now) noexcept {
  // Never silent before OP: about once a second, which slaves are not in OP yet and why.
  if (result.state == ecat::MasterState::op || op_seen_) return;
  if (not_in_op_since_ < 0) {
    not_in_op_since_ = now;
    next_waiting_word_ = now + hal::kNsPerSec;
    return;
  }
  if (now < next_waiting_word_) return;
  next_waiting_word_ += hal::kNsPerSec;
  const ecat::Master& master = bus_.master();
  HandlerEvent e = event(HandlerEventKind::waiting_for_op, result, now);
  e.link.slaves = master.not_in_op();
  e.link.time = now - not_in_op_since_;
  e.joints = drivers::joints_of_slaves(e.link.slaves);
  const std::uint8_t first = drivers::first_slave(e.link.slaves);
  if (first < ecat::kMaxSlaves) {
    e.link.al_status = master.op_al_status(first);
    e.link.al_status_code = master.op_al_status_code(first);
  }
  post(e);
}

void EthercatHandler::track_losses(const drivers::JointCycleResult& result, hal::Nanoseconds now) noexcept {
  // The master alone decides a loss (ecat/master/link_monitor.hpp): the joints it holds out of the
  // exchange are reported; a joint merely invalid this cycle (a short working counter being probed,
  // a late frame) is not.
  tracker_.on_cycle(result.cycle, now, result.out);
  if (tracker_.reports_sent() != last_reports_sent_) {
    last_reports_sent_ = tracker_.reports_sent();
    HandlerEvent e = event(HandlerEventKind::loss_reported, result, now);
    e.joints = tracker_.pending() & ~last_pending_;
    post(e);
  }
  if (tracker_.last_answer_cycle() != last_answer_cycle_) {
    last_answer_cycle_ = tracker_.last_answer_cycle();
    HandlerEvent e = event(HandlerEventKind::loss_recorded, result, now);
    e.joints = tracker_.confirmed();
    e.file_status = tracker_.last_file_status();
    post(e);
  }
  last_pending_ = tracker_.pending();
  // A frame that did not come back in time (host scheduling, a dropped frame) is counted apart: it
  // costs every joint the cycle, whatever the network's state.
  if (!result.frame_received) ++frames_missing_;
  for (std::size_t j = 0; result.frame_received && j < kJointCount; ++j) {
    if ((result.valid & joint_bit(j)) == 0) ++missed_[j];
  }
}

void EthercatHandler::check_limits(const drivers::JointCycleResult& result, hal::Nanoseconds now) noexcept {
  // The handler's own limit check over the joints it drives this cycle.
  JointMask monitored = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (demand_[j].enable && (result.valid & joint_bit(j)) != 0) monitored |= joint_bit(j);
  }
  monitored &= ~tracker_.excluded();
  SafeStopDecision decision = decide_safe_stop(sample_, monitored);
  // A reference the intake sent beyond a speed, acceleration or jerk limit is a fault like any
  // other limit (a defect of the limits: every reference passes the limiter): the same safe stop.
  if (!decision.stop && intake_.violation().active()) {
    decision.stop = true;
    decision.violating = joint_bit(intake_.violating_joint());
    decision.first_joint = static_cast<std::uint8_t>(intake_.violating_joint());
    decision.first = intake_.violation();
  }
  if (!decision.stop || safe_stopped_ || stopping_) return;
  safe_stopped_ = true;
  HandlerEvent e = event(HandlerEventKind::safe_stop, result, now);
  e.joints = decision.violating;
  e.stop = decision;
  post(e);
}

void EthercatHandler::watch_drives_disabled(const drivers::JointCycleResult& result, hal::Nanoseconds now) noexcept {
  if (!stopping_ || drives_disabled_) return;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((result.valid & joint_bit(j)) == 0) continue;
    if ((feedback_.joints[j].statusword & (kSwOperationEnabled | kSwSwitchedOn)) != 0) return;
  }
  drives_disabled_ = true;
  HandlerEvent e = event(HandlerEventKind::drives_disabled, result, now);
  e.joints = result.valid;
  post(e);
}

void EthercatHandler::publish_figures(const drivers::JointCycleResult& result, hal::Nanoseconds now,
                                      std::uint64_t late_periods) noexcept {
  publish_master_status(result, now, late_periods);
  publish_link_diag(result.cycle);
  take_diag_reset(result.cycle);
  publish_slave_info(result.cycle);
  publish_next_sii_image();
}

// ctl master: the master's counters, every period.
void EthercatHandler::publish_master_status(const drivers::JointCycleResult& result, hal::Nanoseconds now,
                                            std::uint64_t late_periods) noexcept {
  if (ports_.master_status == nullptr) return;
  const ecat::Master& m = bus_.master();
  MasterStatus& s = master_status_;
  s.state = static_cast<std::uint8_t>(result.state);
  s.cycles = result.cycle;
  s.frames_sent = result.cycle;
  s.frames_lost = frames_missing_;
  // Late periods: cycles that started more than 0.5 ms after their period began, plus periods
  // that had no cycle at all (skipped to keep the phase after an overrun or a late wake-up).
  s.late_periods = late_periods;
  const std::int64_t dc_error = bus_.last_cycle().dc_phase_error;  // the master's own figure
  s.dc_deviation_ns = dc_error;
  const std::int64_t abs_dc = dc_error < 0 ? -dc_error : dc_error;
  if (abs_dc > s.dc_max_deviation_ns) s.dc_max_deviation_ns = abs_dc;
  s.in_exchange = m.monitor().in_exchange();
  s.lost = m.monitor().lost();
  static_assert(protocol::kMaxSlaves <= ecat::kMaxSlaves, "every published slave is one of the master's");
  for (std::size_t p = 0; p < protocol::kMaxSlaves; ++p) {
    s.recovery[p] = static_cast<std::uint8_t>(m.recovery_state(p));
    const hal::Nanoseconds changed = m.recovery_changed_at(p);
    const hal::Nanoseconds age_ms = changed > 0 && now >= changed ? (now - changed) / hal::kNsPerMs : -1;
    s.recovery_age_ms[p] = age_ms < 0 || age_ms >= protocol::kRecoveryAgeNever ? protocol::kRecoveryAgeNever
                                                                                : static_cast<std::uint32_t>(age_ms);
  }
  const ecat::RingStatus& ring = m.ring_status();
  const auto saturated = [](std::uint64_t n, std::uint64_t max) { return n < max ? n : max; };
  s.ring.state = static_cast<std::uint8_t>(ring.state);
  s.ring.before = ring.before;
  s.ring.after = ring.after;
  s.ring.transients = static_cast<std::uint8_t>(saturated(ring.transients, 0xFF));
  s.ring.breaks = static_cast<std::uint16_t>(saturated(ring.breaks, 0xFFFF));
  s.ring.repairs = static_cast<std::uint16_t>(saturated(ring.repairs, 0xFFFF));
  ports_.master_status->write(s);
}

// ctl diag: the link-quality counters, published once per completed round-robin sweep (every 23
// reads, i.e. diag_interval_cycles x 23 periods), never per period: the copy is ~1 KiB. A reset
// (ctl diag --reset) publishes the zeroed table at once.
void EthercatHandler::publish_link_diag(std::uint64_t cycle) noexcept {
  if (ports_.link_diag == nullptr) return;
  const ecat::LinkDiagnostics& d = bus_.master().diagnostics();
  if (d.sweeps() == diag_sweeps_published_ && d.resets() == diag_resets_published_) return;
  diag_sweeps_published_ = d.sweeps();
  diag_resets_published_ = d.resets();
  protocol::DiagPayload out{};
  out.cycle = cycle;
  out.sweeps = d.sweeps();
  out.count = static_cast<std::uint8_t>(drivers::kRobotNetworkPlan.size());
  static_assert(drivers::kRobotNetworkPlan.size() <= protocol::kMaxSlaves, "every slave fits one diag message");
  static_assert(ecat::kEscPorts == protocol::kDiagPorts, "one record per ESC port");
  for (std::size_t p = 0; p < drivers::kRobotNetworkPlan.size(); ++p) {
    const ecat::SlaveErrorCounters& c = d.counters(p);
    protocol::DiagSlaveRecord& s = out.slaves[p];
    for (unsigned n = 0; n < ecat::kEscPorts; ++n) {
      s.ports[n].invalid_frames = saturate16(c.ports[n].invalid_frames);
      s.ports[n].rx_errors = saturate16(c.ports[n].rx_errors);
      s.ports[n].forwarded_errors = saturate16(c.ports[n].forwarded_errors);
      s.ports[n].lost_links = saturate16(c.ports[n].lost_links);
      if (d.warned(p, n)) s.warned = static_cast<std::uint8_t>(s.warned | (1U << n));
      if (d.ever_warned(p, n)) s.warned_before = static_cast<std::uint8_t>(s.warned_before | (1U << n));
    }
    s.processing_unit_errors = saturate16(c.processing_unit_errors);
    s.pdi_errors = saturate16(c.pdi_errors);
    s.reads = saturate16(c.reads);
  }
  ports_.link_diag->write(out);
}

// ctl diag --reset: a request the socket handler posted (DiagResetLink) is taken here, once per
// period, by one atomic load: the master zeroes those slaves' counters (and clears their ESCs' in
// the next frames), the zeroed table is published, then the request is marked done.
void EthercatHandler::take_diag_reset(std::uint64_t cycle) noexcept {
  if (ports_.diag_reset == nullptr) return;
  DiagResetLink& link = *ports_.diag_reset;
  const std::uint64_t word = link.requested.load(std::memory_order_acquire);
  const std::uint64_t generation = DiagResetLink::generation_of(word);
  if (generation == 0 || generation == link.done.load(std::memory_order_relaxed)) return;
  bus_.master().reset_diagnostics(DiagResetLink::slaves_of(word));
  publish_link_diag(cycle);
  link.done.store(generation, std::memory_order_release);
}

// ctl slaves -v: each slave's SII identity (bring-up) and the AL status and code the master read
// last, published when one of them changed (never per period: the copy is ~700 bytes).
void EthercatHandler::publish_slave_info(std::uint64_t cycle) noexcept {
  if (ports_.slave_info == nullptr) return;
  const ecat::Master& master = bus_.master();
  protocol::SlaveInfoTable& published = slave_info_;
  constexpr std::size_t kCount = drivers::kRobotNetworkPlan.size();
  static_assert(kCount <= protocol::kMaxSlaves, "every slave fits one slave_info message");
  bool changed = published.cycle == 0;
  for (std::size_t p = 0; p < kCount && !changed; ++p) {
    const protocol::SlaveInfoRecord& r = published.slaves[p];
    changed = r.al_status != master.last_al_status(p) || r.al_status_code != master.last_al_status_code(p) ||
              ((r.flags & protocol::kSlaveInfoAlRead) != 0) != master.al_status_read(p);
  }
  if (!changed) return;
  published.cycle = cycle == 0 ? 1 : cycle;
  published.count = static_cast<std::uint8_t>(kCount);
  for (std::size_t p = 0; p < kCount; ++p) {
    protocol::SlaveInfoRecord& r = published.slaves[p];
    r = protocol::SlaveInfoRecord{};
    r.position = static_cast<std::uint16_t>(p);
    r.station = drivers::kRobotNetworkPlan[p].station_address;
    if (const ecat::FoundSlave* id = master.identity(p); id != nullptr) {
      r.vendor_id = id->vendor_id;
      r.product_code = id->product_code;
      r.revision = id->revision;
      r.serial_number = id->serial_number;
      r.flags |= protocol::kSlaveInfoIdentity;
    }
    r.al_status = master.last_al_status(p);
    r.al_status_code = master.last_al_status_code(p);
    if (master.al_status_read(p)) r.flags |= protocol::kSlaveInfoAlRead;
  }
  ports_.slave_info->write(published);
}

// ctl sii_read: the SII images the master read at bring-up, one slave per period (a 1 KiB copy)
// until each is published; they do not change while the run lasts.
void EthercatHandler::publish_next_sii_image() noexcept {
  constexpr std::size_t kCount = drivers::kRobotNetworkPlan.size();
  if (ports_.sii_images == nullptr || sii_published_ >= kCount) return;
  const std::size_t p = sii_published_++;
  SiiImageRecord& r = sii_record_;
  r = SiiImageRecord{};
  if (const ecat::SiiImage* image = bus_.master().sii_image(p); image != nullptr) {
    r.size = image->size <= r.bytes.size() ? image->size : static_cast<std::uint16_t>(r.bytes.size());
    std::memcpy(r.bytes.data(), image->bytes.data(), r.size);
    r.flags = static_cast<std::uint8_t>(protocol::kSiiRead | (image->from_cache ? protocol::kSiiFromCache : 0) |
                                        (image->strings_skipped != 0 ? protocol::kSiiStringsSkipped : 0));
  }
  (*ports_.sii_images)[p].write(r);
}

}  // namespace rescue::app
