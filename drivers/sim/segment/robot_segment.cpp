#include "drivers/sim/segment/robot_segment.hpp"

#include <cmath>

#include "core/robot/robot.hpp"
#include "core/robot/robot_ring.hpp"

namespace rescue::drivers {
namespace {

// splitmix64: a small, well-mixed deterministic generator (seeded runs repeat exactly).
std::uint64_t next_random(std::uint64_t& state) noexcept {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31U);
}

// Uniform in [-1, 1].
double next_symmetric(std::uint64_t& state) noexcept {
  return static_cast<double>(next_random(state) >> 11U) / static_cast<double>(1ULL << 52U) - 1.0;
}

// Cable lengths in metres: the master's cable, inside the junction box, first joint of a branch,
// between joints along a branch.
constexpr double kMasterCable = 3.0;
constexpr double kJunctionToJunction = 0.3;
constexpr double kJunctionToBranch = 1.5;
constexpr double kJointToJoint = 0.6;
// Ring configuration only: the line from one branch's last joint to the next branch's first, and
// from l_hand back to the master.
constexpr double kBranchToBranch = 1.5;
constexpr double kRingReturnCable = 3.5;

hal::Nanoseconds cable_delay(double metres) noexcept {
  return kPhyPairDelayNs + static_cast<hal::Nanoseconds>(std::lround(metres * kCableNsPerMetre));
}

}  // namespace

EscConfig junction_esc_config() noexcept {
  EscConfig c;
  c.type = 0x11;  // ET1100
  c.revision = 0x00;
  c.build = 0x0003;
  c.fmmu_count = 8;
  c.sync_manager_count = 8;
  c.ram_kib = 8;
  c.port_count = 4;
  c.features = 0x01CC;
  c.sii_read_bytes = 8;
  return c;
}

EscConfig joint_esc_config() noexcept {
  EscConfig c;
  c.type = 0xC0;  // the drive-class ESC with MII ports seen in the SOEM capture of shared/vectors
  c.revision = 0x02;
  c.build = 0x0001;
  c.fmmu_count = 3;
  c.sync_manager_count = 4;
  c.ram_kib = 4;
  c.port_count = 2;
  c.features = 0x01CC;
  c.sii_read_bytes = 4;
  return c;
}

Status describe_robot_segment(Span<SlaveDevice* const> devices, const RobotSegmentOptions& options,
                              Span<SegmentSlave> out) noexcept {
  if (devices.size() < kSlaveCount || out.size() < kSlaveCount) {
    return make_error(Errc::invalid_argument, "need one device and one slot per slave", static_cast<std::uint32_t>(kSlaveCount));
  }
  std::uint64_t random = options.seed;
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    const SlaveInfo& info = kSlaves[p];
    if (devices[p] == nullptr) return make_error(Errc::invalid_argument, "missing device", static_cast<std::uint32_t>(p));
    SegmentSlave& s = out[p];
    s.name = info.name;
    s.device = devices[p];
    s.esc = info.kind == SlaveKind::junction ? junction_esc_config() : joint_esc_config();
    s.esc.drift_ppm = options.max_drift_ppm * next_symmetric(random);
    // Power-up instants within 50 ms of each other: local times start apart.
    s.esc.local_time_at_zero = next_random(random) % (50ULL * 1000 * 1000);
    s.esc.processing_delay_ns += std::lround(8.0 * next_symmetric(random));
    s.esc.forwarding_delay_ns += std::lround(8.0 * next_symmetric(random));
    const std::uint8_t upstream = options.ring ? kRingCabling[p].upstream : info.upstream;
    s.upstream = upstream == kMasterUpstream ? kUpstreamIsMaster : upstream;
    s.upstream_port = options.ring ? kRingCabling[p].upstream_port : info.upstream_port;
    double metres = kJointToJoint;
    if (upstream == kMasterUpstream) {
      metres = kMasterCable;
    } else if (kSlaves[upstream].kind == SlaveKind::junction) {
      metres = info.kind == SlaveKind::junction ? kJunctionToJunction : kJunctionToBranch;
    } else if (info.kind == SlaveKind::joint_drive && kJoints[kSlaves[upstream].joint].branch != kJoints[info.joint].branch) {
      metres = kBranchToBranch;
    }
    s.link_delay_ns = cable_delay(metres);
  }
  return Status::success();
}

RingCable robot_ring_cable() noexcept {
  return RingCable{kRingReturnSlave, kRingReturnPort, cable_delay(kRingReturnCable), 0};
}

}  // namespace rescue::drivers
