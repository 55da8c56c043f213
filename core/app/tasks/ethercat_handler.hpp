// The EtherCAT handler task (design brief section 3; paper III-B): the highest-priority task, one
// period per millisecond on CPU thread 3. Per period, cycle():
//   1. builds every joint's outputs: joints the joint manager has Enabled (and the handler has not
//      stopped or excluded) are driven towards Operation enabled and follow their reference: in
//      position mode the Motion owner's (MotionIntake: on time, or hold; docs/motion-owner.md),
//      else the joint manager's; every other reachable joint is driven towards a disabled power
//      stage, its worm gear holding;
//   2. exchanges one frame with all slaves (drivers::JointBus: the master);
//   3. publishes every joint's values (seqlock; an unreachable joint keeps its last values);
//   4. reconfiguration steps 1 and 6 (LostJointTracker): the joints of the slaves the master took
//      out of the exchange (its link monitor alone confirms a loss) are excluded at once, reported
//      on a queue to the joint manager, and the healthy branches go on;
//   5. its own limit check (decide_safe_stop): any monitored joint over a limit stops the robot
//      safely, whatever the joint manager does: every drive disabled, worm gears holding;
//   6. queues what happened (HandlerEvent) for a lower-priority logger to print;
//   7. relays the operator's SDO transfers (ctl upload/download) to the master's cyclic mailbox
//      channel and answers them (SdoRelay, core/app/tasks/sdo_relay.hpp), and its ESC register
//      reads (ctl reg_read) to the master's cyclic FPRD (RegisterRelay, register_relay.hpp);
//   8. relays the operator's AL states for slaves out of service (ctl states) to the master, and
//      refuses a slave whose joints it commands (SlaveStateRelay, slave_state_relay.hpp), and its
//      rescans (ctl rescan) to the master's cyclic identification (RescanRelay, rescan_relay.hpp).
// After each cycle its loop calls publish_figures(): the master's figures for the operator (ctl
// master, ctl diag and its reset, ctl slaves -v), each through its port.
// No heap, no locks, no syscalls but the NIC's; bounded work.
#pragma once

#include <array>
#include <cstdint>

#include "core/app/links/control_messages.hpp"
#include "core/app/links/joint_messages.hpp"
#include "core/app/tasks/lost_joint_tracker.hpp"
#include "core/app/tasks/motion_intake.hpp"
#include "core/app/tasks/register_relay.hpp"
#include "core/app/tasks/rescan_relay.hpp"
#include "core/app/tasks/sdo_relay.hpp"
#include "core/app/tasks/slave_state_relay.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/concurrency/spsc_queue.hpp"
#include "core/robot/joint_demand.hpp"
#include "core/robot/joint_limits.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "ecat/master/link_monitor.hpp"
#include "ecat/master/ring_monitor.hpp"

namespace rescue::app {

enum class HandlerEventKind : std::uint8_t {
  link_report,      // the master established a lost / restored / not-operational set
  loss_reported,    // reconfiguration step 1: lost joints reported to the joint manager
  loss_recorded,    // step 4 answer read: the joint manager recorded them (file status inside)
  safe_stop,        // the handler's own limit check stopped the robot
  drives_disabled,  // shutdown: every reachable drive reports its power stage off
  waiting_for_op,   // about once a second while the network is not in OP: the slaves not in OP yet
                    // (link.slaves; link.al_status/al_status_code of the first), link.time = since
  ring_report,      // cable redundancy: the ring opened, split or closed again (ring: where)
};

struct HandlerEvent {
  HandlerEventKind kind{HandlerEventKind::link_report};
  std::uint64_t cycle{0};
  hal::Nanoseconds time{0};
  JointMask joints{0};
  ecat::LinkReport link{};       // link_report (its slaves; `joints` holds their joints)
  Errc file_status{Errc::ok};    // loss_recorded
  SafeStopDecision stop{};       // safe_stop
  ecat::RingReport ring{};       // ring_report
};

// What the handler reaches of the tasks' shared state, each at the end it uses (built with the other
// tasks' ports, core/app/runtime/task_ports.hpp).
struct EthercatHandlerPorts {
  const Seqlock<RobotDemand>* demand{nullptr};          // the joint manager's drive demand
  Seqlock<RobotSample>* samples{nullptr};               // every joint's values, published each cycle
  MessageSink<LostJointsReport>* reports{nullptr};      // to the joint manager (step 1; back after a power cycle)
  MessageSource<JointManagerNotice>* notices{nullptr};  // from the joint manager (step 4)
  MotionIntakePorts motion{};  // the Motion owner's references; its word (released after a watchdog stall)
  // ctl upload/download from the socket handler, and their answers (both null: no SDO relay).
  MessageSource<SdoLinkRequest>* sdo_requests{nullptr};
  MessageSink<SdoLinkResult>* sdo_results{nullptr};
  // ctl reg_read from the socket handler, and its answer (both null: no register reads).
  MessageSource<RegReadLinkRequest>* reg_requests{nullptr};
  MessageSink<RegReadLinkResult>* reg_results{nullptr};
  // ctl states from the socket handler, and its answer (both null: no AL states on request).
  MessageSource<StatesLinkRequest>* states_requests{nullptr};
  MessageSink<StatesLinkResult>* states_results{nullptr};
  // ctl rescan from the socket handler, and its answer (both null: no rescans).
  MessageSource<RescanLinkRequest>* rescan_requests{nullptr};
  MessageSink<RescanLinkResult>* rescan_results{nullptr};
  // The master's figures for the operator, written by publish_figures() (null: not published): its
  // counters every period (ctl master), the link-quality table once per diagnostics sweep (ctl
  // diag), each slave's identity and AL status when one changed (ctl slaves -v), and the socket
  // handler's ctl diag --reset request, polled once per period and marked done.
  Seqlock<MasterStatus>* master_status{nullptr};
  Seqlock<protocol::DiagPayload>* link_diag{nullptr};
  Seqlock<protocol::SlaveInfoTable>* slave_info{nullptr};
  DiagResetLink* diag_reset{nullptr};
  // ctl sii_read: each slave's SII image as the master read it at bring-up, published once, one
  // slave per period (null: not published).
  std::array<Seqlock<SiiImageRecord>, protocol::kMaxSlaves>* sii_images{nullptr};
};

class EthercatHandler {
 public:
  static constexpr std::size_t kEventQueueDepth = 64;

  // Every port must be non-null; `restored_lost`: the joints the error-joints file lists (excluded
  // from the first cycle on).
  EthercatHandler(drivers::JointBus& bus, const EthercatHandlerPorts& ports, JointMask restored_lost,
                  const MotionIntakeSettings& intake = default_intake_settings()) noexcept;

  // One period; call at bus().next_wakeup() once the bus is up.
  drivers::JointCycleResult cycle() noexcept;

  // After cycle() returned `result` at `now`: publishes the master's figures through their ports
  // (those that are null are skipped). `late_periods`: the loop's count of late and skipped periods,
  // the handler's missed periods in ctl master. Bounded; the two large records only when they changed.
  void publish_figures(const drivers::JointCycleResult& result, hal::Nanoseconds now, std::uint64_t late_periods) noexcept;

  // Shutdown: from now on every drive is driven to a disabled power stage.
  void stop_drives() noexcept { stopping_ = true; }
  // True once every reachable joint's statusword shows its power stage off (after stop_drives()).
  bool drives_disabled() const noexcept { return drives_disabled_; }
  bool safe_stopped() const noexcept { return safe_stopped_; }

  // Events for the logger (single consumer).
  [[nodiscard]] bool pop_event(HandlerEvent& out) noexcept { return events_.try_pop(out); }
  std::uint64_t events_dropped() const noexcept { return events_dropped_; }
  // Motion owners released because the drives' watchdog expired during a silence of this handler.
  std::uint64_t owners_released_after_watchdog() const noexcept { return owners_released_after_watchdog_; }
  // "Back after a power cycle" reports a full report queue could not take (no automatic clear then).
  std::uint64_t power_cycle_reports_dropped() const noexcept { return power_cycle_reports_dropped_; }
  // Demands of the joint manager refused as damaged (a mode or enable byte it never writes): the
  // last whole demand was kept.
  std::uint64_t damaged_demands() const noexcept { return damaged_demands_; }

  const LostJointTracker& tracker() const noexcept { return tracker_; }
  drivers::JointBus& bus() noexcept { return bus_; }
  const RobotSample& sample() const noexcept { return sample_; }
  // The outputs built last cycle, as sent to the drives (what a demand turned into).
  const drivers::JointReferences& outputs() const noexcept { return outputs_; }
  // Cycles since OP whose frame came back but without valid inputs of joints of `joints`, summed
  // over the joints. With `joints` = the joints never lost, this is the "healthy branches miss no
  // cycle" figure.
  std::uint64_t missed_cycles(JointMask joints) const noexcept;
  // Cycles since OP whose frame did not come back before its deadline (late or lost frame).
  std::uint64_t frames_missing() const noexcept { return frames_missing_; }
  // The Motion owner's references as this handler took them (misses, releases).
  const MotionIntake& motion_intake() const noexcept { return intake_; }
  const SdoRelay& sdo_relay() const noexcept { return sdo_relay_; }

 private:
  void build_outputs() noexcept;
  void publish_sample(const drivers::JointCycleResult& result) noexcept;
  void post(const HandlerEvent& event) noexcept;
  // cycle()'s parts, in its order.
  static HandlerEvent event(HandlerEventKind kind, const drivers::JointCycleResult& result, hal::Nanoseconds now) noexcept;
  void handle_link_reports(const drivers::JointCycleResult& result, hal::Nanoseconds now) noexcept;
  void report_waiting_for_op(const drivers::JointCycleResult& result, hal::Nanoseconds now) noexcept;
  void track_losses(const drivers::JointCycleResult& result, hal::Nanoseconds now) noexcept;
  void check_limits(const drivers::JointCycleResult& result, hal::Nanoseconds now) noexcept;
  void watch_drives_disabled(const drivers::JointCycleResult& result, hal::Nanoseconds now) noexcept;
  void publish_master_status(const drivers::JointCycleResult& result, hal::Nanoseconds now, std::uint64_t late_periods) noexcept;
  void publish_link_diag(std::uint64_t cycle) noexcept;
  void take_diag_reset(std::uint64_t cycle) noexcept;
  void publish_slave_info(std::uint64_t cycle) noexcept;
  void publish_next_sii_image() noexcept;

  // Largest and most aligned first (the event queue's indices sit on cache lines of their own).
  // Members in the order clang-analyzer-optin.performance.Padding finds optimal (no padding).
  SpscQueue<HandlerEvent, kEventQueueDepth> events_;
  drivers::JointBus& bus_;
  std::size_t sii_published_{0};  // slaves whose SII image is published (in position order)
  std::uint64_t diag_sweeps_published_{0};
  std::uint64_t diag_resets_published_{0};
  std::uint64_t events_dropped_{0};
  std::uint64_t owners_released_after_watchdog_{0};
  std::uint64_t power_cycle_reports_dropped_{0};
  std::uint64_t damaged_demands_{0};
  std::uint64_t last_answer_cycle_{0};
  std::uint64_t frames_missing_{0};
  hal::Nanoseconds not_in_op_since_{-1};   // first cycle without OP (-1: none yet)
  hal::Nanoseconds next_waiting_word_{0};  // when the next waiting_for_op event is due
  LostJointTracker tracker_;
  RegisterRelay register_relay_;
  SlaveStateRelay state_relay_;
  RescanRelay rescan_relay_;
  EthercatHandlerPorts ports_;
  std::array<double, kJointCount> reference_rad_{};  // each joint's position reference as sent (radians)
  std::array<std::uint64_t, kJointCount> missed_{};  // per joint, cycles without valid inputs since OP
  // What publish_figures() published last: the master's counters (its DC maximum carries over), the
  // slave table (compared each period), the diagnostics sweep and reset it published the table at.
  MasterStatus master_status_{};
  RobotDemand demand_{};
  protocol::SlaveInfoTable slave_info_{};
  SdoRelay sdo_relay_;
  RobotSample sample_{};
  MotionIntake intake_;
  JointMask last_pending_{0};
  std::uint32_t last_reports_sent_{0};
  JointMask drive_mask_{0};  // joints driven last period (any mode; build_outputs)
  // Joints whose drives the SyncManager watchdog stopped during a silence of this handler (a stall
  // longer than 100 ms): until each drive is enabled again its target is its actual position, so
  // it comes back holding where it stands (docs/tasks.md "Liveness").
  JointMask rest_after_watchdog_{0};
  drivers::JointReferences outputs_{};
  drivers::JointFeedback feedback_{};
  SiiImageRecord sii_record_{};   // the one being published (not on the stack: 1 KiB)
  bool op_seen_{false};
  bool stopping_{false};
  bool drives_disabled_{false};
  bool safe_stopped_{false};
};

}  // namespace rescue::app
