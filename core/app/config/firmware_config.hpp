// The firmware's tunables in one place (in the manner of F Prime's config headers): task priorities,
// CPUs and periods (design brief Table I), queue depths between the tasks, and time limits. Change a
// number here, rebuild, and `rescue-motion docs tasks` / docs/tasks.md show it.
#pragma once

#include <cstddef>
#include <cstdint>

namespace rescue::app::config {

// --- Tasks (design brief section 3, paper Table I, on a 4-hardware-thread motion PC) -------------
// SCHED_FIFO priorities: 1 (lowest) .. 99. Only the order matters to the paper; these leave room
// above the handler for the kernel's own threads (PREEMPT_RT's IRQ threads run at 50 by default:
// the NIC's IRQ thread should be raised above the handler's, see docs/tasks.md).
constexpr int kEthercatHandlerPriority = 80;  // highest
constexpr int kJointManagerPriority = 70;     // high
constexpr int kRcTaskPriority = 65;           // high, below the joint manager
constexpr int kSocketHandlerPriority = 20;    // low
constexpr int kMessageParserPriority = 20;    // low
constexpr int kBasicSoftwarePriority = 0;     // SCHED_OTHER: the operating system, the logger

constexpr int kEthercatHandlerCpu = 3;
constexpr int kJointManagerCpu = 2;
constexpr int kRcTaskCpu = 2;
constexpr int kSocketHandlerCpu = 1;
constexpr int kMessageParserCpu = 1;
constexpr int kBasicSoftwareCpu = 0;

constexpr std::int64_t kEthercatHandlerPeriodNs = 1'000'000;  // 1 kHz: the network's period
constexpr std::int64_t kJointManagerPeriodNs = 1'000'000;
constexpr std::int64_t kRcTaskPeriodNs = 1'000'000;
constexpr std::int64_t kLoggerPeriodNs = 5'000'000;           // drains events and capture frames
// The error-joints storage worker (core/app/tasks/error_joints_worker.hpp), normal priority: polls
// its request queue this often when idle.
constexpr std::int64_t kStorageWorkerPollNs = 1'000'000;

// The stack each real-time thread prefaults at start-up is hal::kTaskStackPrefaultBytes
// (hal/rt/rt_setup.hpp), where toolchain/rt_verify.py reads it to check the deepest stack path.

// --- Queues between the tasks (core/app/links/task_links.hpp) -------------------------------------
constexpr std::size_t kLostReportQueueDepth = 16;  // handler -> joint manager (reconfiguration step 1)
constexpr std::size_t kNoticeQueueDepth = 16;      // joint manager -> handler (step 4, clears)
constexpr std::size_t kJointCommandQueueDepth = 64;  // message parser -> joint manager (joint handle queue)
constexpr std::size_t kOperatorRequestQueueDepth = 16;  // socket handler -> message parser (operator requests)
constexpr std::size_t kSdoQueueDepth = 2;  // socket handler <-> EtherCAT handler (ctl upload/download; one in flight)
constexpr std::size_t kRegQueueDepth = 2;  // socket handler <-> EtherCAT handler (ctl reg_read; one in flight)
constexpr std::size_t kStatesQueueDepth = 2;  // socket handler <-> EtherCAT handler (ctl states; one in flight)
constexpr std::size_t kRescanQueueDepth = 2;  // socket handler <-> EtherCAT handler (ctl rescan; one in flight)
constexpr std::size_t kOperatorReplyQueueDepth = 16;    // message parser -> socket handler (replies)
constexpr std::size_t kCommandOutcomeQueueDepth = 64;   // joint manager -> message parser (command outcomes)
constexpr std::size_t kRcInputQueueDepth = 8;           // message parser -> each RC task (operator inputs)

// --- Periods and waits of the non-cyclic tasks ------------------------------------------------------
constexpr std::int64_t kMessageParserPeriodNs = 1'000'000;  // the parser drains its queues every 1 ms
constexpr int kSocketWaitMs = 5;  // the socket handler's poll() timeout: how often it looks at the stop word
// The rescue scenario runs on this long after its motion ended, so the end of the motion is in the log.
constexpr std::int64_t kRescueSettleNs = 200'000'000;
// The receive spin's limit (hal::RawSocketSettings::receive_spin) when the master's raw socket spins
// (receive wait `spin` or `adaptive`; runtime/nic_factory.hpp kMasterReceiveWait chooses, `bench
// master --receive-wait` overrides): longer than a healthy segment's round trip, so the reply is
// usually taken without a wake-up; a late one is then waited for asleep. Costs at most this much CPU
// per exchange. The in-process simulated robot on the wall clock spins as long for its frame.
constexpr std::int64_t kMasterReceiveSpinNs = 150'000;
// The adaptive receive wait sleeps through most of the learnt round trip and spins only from this long
// before the frame is expected back (covers the thread's wake-up).
constexpr std::int64_t kMasterAdaptiveLeadNs = 20'000;
// Every task thread's timer slack (prctl PR_SET_TIMERSLACK) and the process's CPU wake-up latency
// request (/dev/cpu_dma_latency), both as cyclictest sets them (hal/rt/rt_setup.hpp; docs/timing.md
// measures what they change).
constexpr unsigned long kTaskTimerSlackNs = 1;
constexpr int kCpuWakeupLatencyUs = 0;

// --- The socket handler under a flood (core/app/tasks/socket_handler.*, docs/protocol.md) ---------
// Datagrams handled per wake-up, both UDP ports together, whatever is queued: a flood costs the socket
// handler at most this much work (checks, tag, replay window) before it answers the parser's replies
// and waits again. The rest stays in the kernel's receive buffer (or is dropped by the kernel).
constexpr std::size_t kSocketDatagramsPerWakeup = 64;
constexpr std::size_t kSocketRecvBatch = 32;          // datagrams per recvmmsg call
constexpr std::size_t kSocketRepliesPerWakeup = 16;   // parser replies sent per wake-up

// --- Time limits ----------------------------------------------------------------------------------
constexpr std::int64_t kDisableTimeoutNs = 500'000'000;  // stop: drives disabled within this, or give up
// stop: the joint manager, past its last period, waits this long at most for a write of the
// error-joints file still in flight (or failing) before it reports the file not written. Below the
// supervisor's stop limit for a task (5 s, task_processes.cpp).
constexpr std::int64_t kFileDrainLimitNs = 3'000'000'000;
constexpr std::int64_t kScenarioRunOnNs = 1'000'000'000; // a scenario without --duration runs on this long

// --- The Motion owner (docs/motion-owner.md) ------------------------------------------------------
// The EtherCAT handler takes the owner's references only if the owner completed them at most this
// long before the handler's period (2 RC periods); otherwise it holds and counts an owner miss.
constexpr std::int64_t kOwnerReferenceDeadlineNs = 2'000'000;
// An owner whose heartbeat is older than this many RC periods is dead: the handler releases the
// motion in the period it notices (so within kOwnerDeadAfterPeriods + 1 handler periods of the
// owner's last period), holding position from its first missed deadline on.
constexpr std::int64_t kOwnerDeadAfterPeriods = 50;

// --- The rescue motion after damage (docs/kinematics.md "After damage") ---------------------------
// Should an arm be cut at its elbow, its palm (which may carry the person) travels on while the
// joints the cut leaves held brake to rest at their declared accelerations: the rescue task caps each
// palm's speed so that this travel stays within this budget (m). Smaller: a slower rescue motion.
constexpr double kDamagedPalmStopBudgetM = 0.005;

// --- Liveness (docs/tasks.md "Liveness") --------------------------------------------------------
// The supervisor reports a real-time task that has completed no period for this long (its heartbeat,
// TaskLinks::task_heartbeat_ns): far above a SCHED_FIFO task's wake-up jitter on a loaded host (a
// few ms), far below the drives' SyncManager watchdog (kDriveWatchdogNs). `run --config`: the
// `[supervisor]` section's `task_silent_ms`.
constexpr std::int64_t kTaskSilentAfterNs = 30'000'000;
// At most one silence line per task in this long (core/app/runtime/repeat_limiter.hpp): the silences
// in between are counted and the next line says how many, so a loaded host's log stays readable.
constexpr std::int64_t kSilenceReportIntervalNs = 10'000'000'000;
// The drives' SyncManager watchdog: without a frame for this long they disable their outputs.
constexpr std::int64_t kDriveWatchdogNs = 100'000'000;

}  // namespace rescue::app::config
