// The operator and sensor protocol over UDP (docs/protocol.md): message types, their payloads as
// plain records, the limits every decoded value is checked against, and why a datagram is rejected.
// The byte layout of each record is in docs/protocol.md and in protocol_codec.cpp, field by field;
// no record here is ever overlaid on a buffer.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "core/app/links/register_messages.hpp"
#include "core/app/links/rescan_messages.hpp"
#include "core/app/links/sdo_messages.hpp"
#include "core/app/links/sii_messages.hpp"
#include "core/app/links/slave_state_messages.hpp"
#include "core/robot/robot.hpp"
#include "core/timing/period_recorder.hpp"

namespace rescue::app::protocol {

constexpr std::array<std::uint8_t, 4> kMagic{{0x52, 0x4D, 0x43, 0x50}};  // "RMCP"
constexpr std::uint8_t kVersion = 2;             // 2: the robot id and the epoch in the header (issue 23)
constexpr std::size_t kHeaderSize = 40;
constexpr std::size_t kTagSize = 32;             // crypto_auth_BYTES (HMAC-SHA-512-256)
constexpr std::size_t kKeySize = 32;             // crypto_auth_KEYBYTES
constexpr std::size_t kMaxPayload = 1024;
constexpr std::size_t kMaxDatagram = kHeaderSize + kMaxPayload + kTagSize;  // 1096 bytes
constexpr std::size_t kNameSize = 24;            // slave and task names, ASCII, NUL-padded
constexpr std::size_t kReplyTextSize = 64;       // reason of a reply, ASCII, NUL-padded
constexpr std::size_t kMaxSlaves = 23;
static_assert(kStatesSlaves == kMaxSlaves, "a states result has a record per slave");
constexpr std::uint8_t kRecoveryStates = 15;  // ecat::kRecoveryStateCount (checked where both are seen)
constexpr std::uint32_t kRecoveryAgeNever = 0xFFFFFFFFU;  // SlaveRecord: not changed since bring-up
constexpr std::size_t kMaxTasks = 7;          // tasks in one tasks answer (the run has 6; 7 records of 128 bytes and the drop counters fill a payload)
constexpr std::size_t kMaxDropCounters = 12;  // after the task records: the queues' drop counters
constexpr std::size_t kMaxRcTasks = 4;
constexpr std::uint8_t kNoOwner = 0xFF;
constexpr std::uint32_t kAnyRobot = 0;          // robot id of a get_epoch that asks whichever robot answers
constexpr std::uint32_t kDefaultRobotId = 1;

using Key = std::array<std::uint8_t, kKeySize>;
using rescue::TimingFigures;

enum class MessageType : std::uint8_t {
  // operator -> robot, control port
  get_status = 0x01,
  get_slaves = 0x02,
  get_master = 0x03,
  get_tasks = 0x04,
  get_diag = 0x05,
  get_epoch = 0x06,  // the robot's current epoch (docs/protocol.md "Replay protection"); the only request with epoch 0
  get_version = 0x07,  // the robot's program version, layout and build type (ctl version)
  get_owner = 0x08,    // which RC task owns the motion, alive, its phase (ctl owner)
  get_graph = 0x09,    // the topology as the robot sees it now (ctl graph)
  get_slave_info = 0x0A,  // each slave's SII identity and AL status code (ctl slaves -v)
  get_sii = 0x0B,         // a chunk of one slave's SII image as the master read it (ctl sii_read)
  initialize = 0x10,
  enable = 0x11,
  disable = 0x12,
  hold = 0x13,
  select_mode = 0x14,
  clear_joints = 0x15,
  clear_moved = 0x16,  // clear_joints, and the operator confirms the joints' moved positions
  diag_reset = 0x17,   // zero the link-quality counters of some slaves (ctl diag --reset), answered by a reply
  sdo_upload = 0x18,    // ctl upload: a CoE SDO upload from a joint's drive (answered by sdo_result)
  sdo_download = 0x19,  // ctl download: a CoE SDO download to a joint's drive (answered by sdo_result)
  reg_read = 0x1A,      // ctl reg_read: a read of a slave's ESC registers (answered by reg_result)
  sdo_info = 0x1B,      // ctl sdos: one CoE SDO Information request to a slave (answered by sdo_info_result)
  states = 0x1C,        // ctl states: an AL state for slaves out of service (answered by states_result)
  rescan = 0x1D,        // ctl rescan: identify the segment again, compare it with the plan (answered by rescan_result)
  move_effector = 0x20,
  hand = 0x21,
  take_owner = 0x22,
  // robot computers -> robot, sensor port
  imu = 0x40,
  gps = 0x41,
  // robot -> operator
  reply = 0x80,
  status = 0x81,
  slaves = 0x82,
  master = 0x83,
  tasks = 0x84,
  diag = 0x85,
  epoch = 0x86,  // the answer to get_epoch: the epoch and robot id are its header's
  version = 0x87,
  owner_state = 0x88,
  graph = 0x89,
  slave_info = 0x8A,
  sdo_result = 0x8B,  // the end of an sdo_upload / sdo_download: value, abort code, or refusal
  sii = 0x8C,         // the answer to get_sii
  reg_result = 0x8D,  // the end of a reg_read: the bytes, or why not
  sdo_info_result = 0x8E,  // the end of an sdo_info: a window of the response's data, or why not
  states_result = 0x8F,  // the end of a states request: each slave's AL status, or why not
  rescan_result = 0x90,  // the end of a rescan: the devices found, what differs from the plan
};

const char* to_string(MessageType type) noexcept;
bool is_known(std::uint8_t type) noexcept;
bool is_control_request(MessageType type) noexcept;  // accepted on the control port
bool is_sensor_record(MessageType type) noexcept;    // accepted on the sensor port
bool is_query(MessageType type) noexcept;            // get_*: answered by the socket handler itself

// Why a datagram was dropped; each reason has its own counter (docs/protocol.md "Rejections").
enum class Rejection : std::uint8_t {
  malformed = 0,        // shorter than its header, bad magic or version, lengths that disagree, reserved bits set
  oversized = 1,        // longer than kMaxDatagram, or a payload length above kMaxPayload
  unauthenticated = 2,  // the tag does not verify under the key
  replayed = 3,         // authentic, but its sequence was seen or is older than the window
  out_of_range = 4,     // a field's value outside its documented range (NaN included)
  unknown_type = 5,     // a type this version does not define, or not accepted on this port
  wrong_robot = 6,      // authentic, but it names another robot (its robot id is not ours)
  sender_table_full = 7,  // authentic and current, from a sender the full sender table has no room for
};
constexpr std::size_t kRejectionCount = 8;
const char* to_string(Rejection reason) noexcept;

struct Header {
  std::uint8_t version{kVersion};
  MessageType type{MessageType::get_status};
  std::uint8_t flags{0};       // reserved, 0
  std::uint32_t sender{0};     // who signed it; the replay window is per sender
  std::uint32_t robot{0};      // the robot it is for (or from): run's robot_id; kAnyRobot only in get_epoch
  std::uint64_t epoch{0};      // the robot's epoch it belongs to (random, new at every socket handler start); 0 only in get_epoch
  std::uint64_t sequence{0};   // strictly increasing per sender: its Unix time in ns
  std::uint16_t payload_length{0};
};

// initialize, enable, disable, hold, clear_joints, clear_moved; select_mode adds the mode.
struct JointsPayload {
  JointMask joints{0};
  ControlMode mode{ControlMode::none};  // select_mode only
};

enum class Effector : std::uint8_t { left_hand = 0, right_hand = 1 };
enum class HandAction : std::uint8_t { open = 0, close = 1 };

// An end-effector target for an RC task: position in metres, orientation as roll/pitch/yaw in
// radians, in the robot's base frame.
struct MovePayload {
  std::uint8_t task{0};
  Effector effector{Effector::left_hand};
  std::array<double, 3> position_m{};
  std::array<double, 3> rpy_rad{};
};
constexpr double kMaxReachM = 2.0;

struct HandPayload {
  std::uint8_t task{0};
  Effector hand{Effector::left_hand};
  HandAction action{HandAction::open};
};

struct OwnerPayload {
  std::uint8_t task{0};
};

// IMU and GPS records are trivial (published through a seqlock): value-initialise them.
// IMU record (SI units): orientation as a unit quaternion, angular velocity in rad/s, linear
// acceleration in m/s^2, in the IMU's frame; time is the sender's Unix time of the measurement.
struct ImuRecord {
  std::uint64_t time_unix_ns;
  std::array<double, 4> orientation_wxyz;
  std::array<double, 3> angular_velocity_rad_s;
  std::array<double, 3> linear_acceleration_m_s2;
};
constexpr double kMaxAngularVelocityRadS = 35.0;   // 2000 deg/s, a common gyro's full scale
constexpr double kMaxAccelerationMs2 = 160.0;      // 16 g
constexpr double kQuaternionNormTolerance = 0.01;

enum class GpsFix : std::uint8_t { none = 0, fix_2d = 1, fix_3d = 2, rtk = 3 };
// GPS record (WGS-84): latitude/longitude in degrees, altitude above the ellipsoid and accuracies
// in metres.
struct GpsRecord {
  std::uint64_t time_unix_ns;
  double latitude_deg;
  double longitude_deg;
  double altitude_m;
  double horizontal_accuracy_m;
  double vertical_accuracy_m;
  GpsFix fix;
  std::uint8_t satellites;
};

enum class Outcome : std::uint8_t { accepted = 0, refused = 1 };

// Why the robot refused an authentic, well-formed command (a reply's reason code).
enum class RefusalReason : std::uint8_t {
  none = 0,
  state_machine = 1,      // the joint status DFA has no such transition from the joint's state
  unreachable_joint = 2,  // the joint does not answer on the network (or is recorded lost)
  not_owner = 3,          // another RC task owns the motion
  no_rc_task = 4,         // no RC task running to take the input
  busy = 5,               // a queue was full or the robot did not answer in time
  bad_request = 6,        // e.g. a mode that is not CSP, CSV or CST, no joint selected
  clear_refused = 7,      // clear after repair refused (joint still unreachable, not lost, file not written)
  sender_table_full = 8,  // the robot's sender table has no room for this sender (docs/protocol.md "Senders")
};
const char* to_string(RefusalReason reason) noexcept;

// Why one joint blocked a refused joint command (a reply names every blocking joint, each with its own).
enum class JointRefusal : std::uint8_t {
  none = 0,
  state_machine = 1,     // the DFA has no transition for `input` in `state`
  unreachable = 2,       // the joint does not answer (only disable and reset are taken)
  bad_mode = 3,          // select_mode without CSP, CSV or CST
  not_lost = 4,          // clear: the joint is not recorded lost
  still_unreachable = 5, // clear: the joint does not answer yet (repair it first)
  moved = 6,             // clear: it answers away from its held position (clear --moved after checking)
  file_not_written = 7,  // clear: the error-joints file could not be written
};
constexpr std::uint8_t kJointRefusalLast = 7;
const char* to_string(JointRefusal refusal) noexcept;
// The protocol's reason for a joint refusal (state machine, unreachable joint, bad request, clear refused).
RefusalReason reason_of(JointRefusal refusal) noexcept;

// One joint's part in a refused joint command.
struct JointRefusalRecord {
  JointRefusal why{JointRefusal::none};
  std::uint8_t state{0};  // fsm::JointState when it was judged
  std::uint8_t input{0};  // fsm::JointInput it refused
};

struct ReplyPayload {
  std::uint64_t request_sequence{0};
  MessageType request_type{MessageType::get_status};
  Outcome outcome{Outcome::accepted};
  RefusalReason reason{RefusalReason::none};
  JointMask refused_joints{0};
  std::array<char, kReplyTextSize> text{};  // NUL-padded; the last byte is always NUL
  // Refused joint commands: every joint of refused_joints with its own reason (none for the others).
  std::array<JointRefusalRecord, kJointCount> joint_refusals{};
};

struct JointStatusRecord {
  std::uint8_t state{0};        // fsm::JointState
  std::int8_t mode{0};          // ControlMode
  std::uint8_t flags{0};        // kFlag*
  std::uint8_t fault{0};        // FaultReason of the (last) fault
  std::uint8_t owner{kNoOwner}; // RC task owning its motion, kNoOwner: none (the reference is held)
  double position_rad{0.0};
  double velocity_rad_s{0.0};
  double torque_nm{0.0};
};
constexpr std::uint8_t kFlagReachable = 0x01;
constexpr std::uint8_t kFlagDriveEnabled = 0x02;
constexpr std::uint8_t kFlagLost = 0x04;
constexpr std::uint8_t kFlagDriveFault = 0x08;
constexpr std::uint8_t kJointFlagsMask = 0x0F;

// How old the EtherCAT handler's figures of a status, slaves or master answer are: the time since the
// handler's latest period (its heartbeat, TaskLinks::task_heartbeat_ns) when the socket handler
// answered, and whether that is past the liveness limit (docs/tasks.md "Liveness"): the handler is
// silent and the figures are stale. On the wire: flags (bit 0 stale), 2 zero bytes, age in ms (u32,
// saturated).
struct FiguresAge {
  bool stale{false};
  std::uint32_t age_ms{0};
};
constexpr std::uint8_t kFiguresStale = 0x01;

struct StatusPayload {
  std::uint64_t cycle{0};  // the EtherCAT handler cycle of the values
  FiguresAge age{};
  std::array<JointStatusRecord, kJointCount> joints{};
};

struct SlaveRecord {
  std::uint16_t position{0};  // auto-increment position along the wire
  std::uint16_t station{0};   // configured station address
  std::uint8_t al_state{0};   // 1 INIT, 2 PRE-OP, 3 BOOT, 4 SAFE-OP, 8 OP, 0 unknown
  std::uint8_t flags{0};      // kSlave*
  std::array<char, kNameSize> name{};
  std::uint8_t recovery{0};   // ecat::RecoveryState (0 Idle: in the exchange, or not planned to run)
  std::uint32_t recovery_age_ms{kRecoveryAgeNever};  // ms since its recovery state last changed
};
constexpr std::uint8_t kSlaveInExchange = 0x01;
constexpr std::uint8_t kSlaveLost = 0x02;
constexpr std::uint8_t kSlaveOutOfService = 0x04;  // recorded lost; excluded until an operator clears it
constexpr std::uint8_t kSlaveFlagsMask = 0x07;

struct SlavesPayload {
  std::uint8_t count{0};
  FiguresAge age{};
  std::array<SlaveRecord, kMaxSlaves> slaves{};
};

struct MasterPayload {
  std::uint8_t state{0};               // ecat::MasterState
  FiguresAge age{};
  std::uint64_t cycles{0};
  std::uint64_t frames_sent{0};
  std::uint64_t frames_lost{0};        // late or lost
  std::uint64_t late_periods{0};       // periods the handler woke up after its deadline
  std::int64_t dc_deviation_ns{0};     // latest phase error of the frame in the SYNC0 period
  std::int64_t dc_max_deviation_ns{0}; // largest |phase error| seen
  std::uint64_t datagrams_accepted{0}; // socket handler
  std::array<std::uint64_t, kRejectionCount> rejected{};  // socket handler, per Rejection
};

constexpr std::uint32_t kUptimeUnknown = 0xFFFFFFFFU;
constexpr std::uint32_t kUptimeSaturated = 0xFFFFFFFEU;  // 49.7 days
struct TaskRecord {
  std::array<char, kNameSize> name{};
  std::int32_t pid{0};
  std::int16_t cpu{-1};       // the CPU the kernel reports the task's thread ran on last; -1: unknown
  std::int16_t priority{0};   // the priority the kernel reports (sched_getparam), 0: a normal policy
  std::int8_t policy{-1};     // the kernel's policy: SCHED_OTHER 0, SCHED_FIFO 1, SCHED_RR 2, ...; -1 unknown
  std::int16_t table_cpu{-1};       // what the task table asked for (on this machine)
  std::int16_t table_priority{0};
  // The task's thread (gettid; in --threads mode each task its own, `pid` the same for all), how
  // often the supervisor restarted it, and how long its current incarnation has run (ms, saturated
  // at kUptimeSaturated; kUptimeUnknown: not known).
  std::int32_t tid{0};
  std::uint16_t restarts{0};  // saturated at 65535
  std::uint32_t uptime_ms{0};
  std::uint64_t periods{0};
  std::uint64_t missed{0};
  std::uint64_t max_execution_ns{0};
  TimingFigures execution{};  // per period, ns (core/timing/period_recorder.hpp)
  TimingFigures latency{};    // wake-up latency: release to start, ns
};

struct TasksPayload {
  std::uint8_t count{0};
  FiguresAge age{};  // the EtherCAT handler's (as status): stale, the handler has stopped
  std::array<TaskRecord, kMaxTasks> tasks{};
  // What each bounded queue between the tasks dropped (or deferred), in the order of
  // core/app/links/run_control.hpp's kDropCounterNames.
  std::uint8_t drop_count{0};
  std::array<std::uint64_t, kMaxDropCounters> dropped{};
};

// Link-quality diagnostics (ecat/master/link_diagnostics.hpp): the ESC error counters of each
// slave, accumulated since bring-up (or the last diag_reset of that slave), saturated at 65535 on the wire.
constexpr std::size_t kDiagPorts = 4;
constexpr std::uint8_t kDiagWarnedMask = 0x0F;  // one bit per port
struct DiagPortRecord {
  std::uint16_t invalid_frames;
  std::uint16_t rx_errors;
  std::uint16_t forwarded_errors;
  std::uint16_t lost_links;
};
struct DiagSlaveRecord {
  std::array<DiagPortRecord, kDiagPorts> ports;
  std::uint16_t processing_unit_errors;
  std::uint16_t pdi_errors;
  std::uint16_t reads;     // answers taken
  std::uint8_t warned;     // bit n: port n's receive errors are rising now (the master warned)
  std::uint8_t warned_before;  // bit n: the master warned about port n since bring-up (sticky)
};
// Also the record the EtherCAT handler's loop publishes (TaskLinks::link_diag): trivial (copied
// by a seqlock), pointer-free, fixed size: value-initialise these records.
struct DiagPayload {
  std::uint64_t cycle;    // the handler cycle of the snapshot, 0: none published yet
  std::uint64_t sweeps;   // completed round-robin sweeps of the counters
  std::uint8_t count;
  std::array<DiagSlaveRecord, kMaxSlaves> slaves;
  // The figures' age (FiguresAge, kept trivial: this is also the handler's published record): the
  // socket handler fills them when it answers; the handler's publication leaves them 0.
  std::uint32_t age_ms;
  std::uint8_t stale;        // 0 or 1
  std::array<std::uint8_t, 3> spare;  // not on the wire; keeps Seqlock<DiagPayload> 960 bytes (TaskLinks' padding)
};

// The answer to get_epoch: the request's sequence echoed (the robot's epoch and id are in the header).
struct EpochPayload {
  std::uint64_t request_sequence{0};
};

// One decoded message: the header and the payload of its type (only that member is meaningful).
// ctl version: what the robot runs.
constexpr std::size_t kVersionTextSize = 48;
struct VersionPayload {
  std::array<char, kVersionTextSize> program{};     // git describe of the build (NUL-padded)
  std::uint32_t layout_version{0};                  // TaskLinks::kLayoutVersion
  std::uint32_t layout_hash{0};                     // the shared-memory layout hash
  std::array<char, kNameSize> build_type{};         // CMAKE_BUILD_TYPE
};

// ctl owner: the Motion owner and each RC task's liveness.
struct RcTaskRecord {
  std::uint8_t present{0};          // 1: the task exists in this run
  std::uint8_t alive{0};            // 1: heartbeat younger than 100 ms
  std::uint8_t phase{0};            // kin::RescuePhase (rescue task)
  std::uint8_t mode{0};             // RcMode
  std::uint32_t heartbeat_age_ms{0};  // 0xFFFFFFFF: never beat
};
struct OwnerStatePayload {
  std::uint8_t owner{kNoOwner};     // RC task owning the motion, kNoOwner: nobody
  FiguresAge age{};                 // the EtherCAT handler's (it applies the owner's references)
  std::uint64_t generation{0};      // the owner word's generation (every change counts)
  std::array<RcTaskRecord, kMaxRcTasks> tasks{};
};

// ctl slaves -v: per slave its identity from its SII as the master read it at bring-up, and the AL
// status register and AL status code (0x0130, 0x0134) the master read last. Also the record the
// EtherCAT handler publishes (TaskLinks::slave_info): trivial, pointer-free: value-initialise it.
struct SlaveInfoRecord {
  std::uint16_t position;
  std::uint16_t station;
  std::uint32_t vendor_id;
  std::uint32_t product_code;
  std::uint32_t revision;
  std::uint32_t serial_number;
  std::uint16_t al_status;       // register 0x0130: state (low 4 bits) and error bit 0x10
  std::uint16_t al_status_code;  // register 0x0134
  std::uint8_t flags;            // kSlaveInfo*
};
constexpr std::uint8_t kSlaveInfoIdentity = 0x01;  // the slave answered at bring-up: its identity is its SII's
constexpr std::uint8_t kSlaveInfoAlRead = 0x02;    // the master has read its AL status since bring-up
constexpr std::uint8_t kSlaveInfoFlagsMask = 0x03;
struct SlaveInfoTable {
  std::uint64_t cycle;  // the handler cycle of the publication, 0: none yet
  std::uint8_t count;
  std::array<SlaveInfoRecord, kMaxSlaves> slaves;
  std::array<std::uint64_t, 3> spare;  // not on the wire; 0: with TaskLinks::diag_reset, whole cache lines
};
static_assert(std::is_trivial_v<SlaveInfoTable>, "published through a seqlock");
struct SlaveInfoPayload {
  std::uint8_t count{0};
  FiguresAge age{};
  std::array<SlaveInfoRecord, kMaxSlaves> slaves{};
};

// ctl graph: the network's tree (each slave's upstream slave and the port of it the cable leaves
// from), each slave's joint and branch, and its state now (as in a slaves answer).
constexpr std::uint8_t kGraphNone = 0xFF;  // no upstream (the master), no joint, no branch
struct GraphRecord {
  std::uint8_t position{0};
  std::uint8_t upstream{kGraphNone};   // kGraphNone: cabled to the master
  std::uint8_t upstream_port{0};       // port of the upstream slave (0..3)
  std::uint8_t kind{0};                // 0 junction, 1 joint drive
  std::uint16_t station{0};
  std::uint8_t joint{kGraphNone};      // index into the robot's joints
  std::uint8_t branch{kGraphNone};     // process-data branch
  std::uint8_t al_state{0};            // as SlaveRecord
  std::uint8_t flags{0};               // kSlave*
  std::uint8_t recovery{0};            // ecat::RecoveryState
};
// The ring (cable redundancy, docs/redundancy.md): with a ring NIC the records' upstream cables are
// the ring configuration's line, and this says where the ring-return cable leaves the line and what
// the master judges of the ring now.
constexpr std::uint8_t kRingStateNone = 0;    // no ring NIC: a tree
constexpr std::uint8_t kRingStateClosed = 1;
constexpr std::uint8_t kRingStateOpen = 2;
constexpr std::uint8_t kRingStateLost = 3;    // slaves reachable from neither port
constexpr std::uint8_t kRingMainPort = 0xFE;  // a place at the master's main port (as ecat::kMainPort)
constexpr std::uint8_t kRingRingPort = 0xFD;  // ... at its ring port (as ecat::kRingPort)
struct GraphRing {
  std::uint8_t state{kRingStateNone};
  std::uint8_t before{kRingMainPort};  // open / lost: the last slave the main port reaches, or kRingMainPort
  std::uint8_t after{kRingRingPort};   // ... the first the ring port reaches, or kRingRingPort
  std::uint8_t return_slave{kGraphNone};  // the slave whose port the ring-return cable leaves
  std::uint8_t return_port{0};
  std::uint8_t transients{0};  // frames that were no evidence (a cable changing in flight), saturating
  std::uint16_t breaks{0};
  std::uint16_t repairs{0};
};
struct GraphPayload {
  std::uint8_t count{0};
  FiguresAge age{};
  std::array<GraphRecord, kMaxSlaves> slaves{};
  GraphRing ring{};
};

// diag_reset: the slaves whose link-quality counters are zeroed (bit = position; never 0).
struct DiagResetPayload {
  std::uint32_t slaves{0};
};

struct Message {
  Header header{};
  JointsPayload joints{};
  MovePayload move{};
  HandPayload hand{};
  OwnerPayload owner{};
  ImuRecord imu{};
  GpsRecord gps{};
  ReplyPayload reply{};
  StatusPayload status{};
  SlavesPayload slaves{};
  MasterPayload master{};
  TasksPayload tasks{};
  DiagPayload diag{};
  EpochPayload epoch{};
  VersionPayload version{};
  OwnerStatePayload owner_state{};
  SdoPayload sdo{};               // sdo_upload, sdo_download
  SdoResultPayload sdo_result{};  // sdo_result
  SiiRequestPayload sii_request{};  // get_sii
  SiiPayload sii{};                 // sii
  SlaveInfoPayload slave_info{};
  GraphPayload graph{};
  DiagResetPayload diag_reset{};
  RegReadPayload reg_read{};      // reg_read
  RegResultPayload reg_result{};  // reg_result
  SdoInfoPayload sdo_info{};                 // sdo_info
  SdoInfoResultPayload sdo_info_result{};    // sdo_info_result
  StatesPayload states{};                // states
  StatesResultPayload states_result{};  // states_result
  RescanPayload rescan{};                // rescan
  RescanResultPayload rescan_result{};  // rescan_result
};
static_assert(std::is_trivial_v<DiagPayload>, "published through a seqlock");

}  // namespace rescue::app::protocol
