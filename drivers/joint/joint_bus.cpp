#include "drivers/joint/joint_bus.hpp"
#include "drivers/joint/joint_units.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rescue::drivers {
namespace {

std::uint32_t saturate_u32(double v) noexcept {
  if (!(v > 0.0)) return 0;
  if (v >= 4294967295.0) return 0xFFFFFFFFU;
  return static_cast<std::uint32_t>(std::lround(v));
}

}  // namespace

std::size_t joint_limit_sdos(std::size_t joint, const JointLimits& limits, ecat::SdoRequest* out, std::size_t capacity) noexcept {
  if (joint >= kJointCount || capacity < kLimitSdosPerJoint) return 0;
  const auto position = static_cast<std::uint8_t>(slave_position_of_joint(joint));
  const JointInfo& info = kJoints[joint];
  std::size_t n = 0;
  if (!info.continuous) {
    // The drive refuses a limit that would leave min > max (0x06090036), and it may hold anything
    // (another tool's INT32_MIN for both): min widened to INT32_MIN first, then max, then min, each
    // step keeping min <= max whatever the drive held.
    const auto min_counts = static_cast<std::uint32_t>(drivers::rad_to_counts(limits.position_min_rad));
    const auto max_counts = static_cast<std::uint32_t>(drivers::rad_to_counts(limits.position_max_rad));
    out[n++] = ecat::sdo_download(position, 0x607D, 1, static_cast<std::uint32_t>(std::numeric_limits<std::int32_t>::min()), 4);
    out[n++] = ecat::sdo_download(position, 0x607D, 2, max_counts, 4);
    out[n++] = ecat::sdo_download(position, 0x607D, 1, min_counts, 4);
  }
  out[n++] = ecat::sdo_download(position, 0x607F, 0, saturate_u32(limits.velocity_max_rad_s * drivers::kCountsPerRad), 4);
  const double per_mille = info.rated_torque_nm > 0.0 ? 1000.0 * limits.torque_max_nm / info.rated_torque_nm : 0.0;
  out[n++] = ecat::sdo_download(position, 0x6072, 0, std::min<std::uint32_t>(saturate_u32(per_mille), 0xFFFF), 2);
  return n;
}

Status JointBus::bring_up(ecat::MasterOptions options, JointMask out_of_service) noexcept {
  options.held_out |= slaves_of_joints(out_of_service);
  const JointMask held_out = joints_of_slaves(options.held_out);
  std::size_t n = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((held_out & joint_bit(j)) != 0) continue;
    n += joint_limit_sdos(j, kJoints[j].limits, startup_sdos_.data() + n, startup_sdos_.size() - n);
  }
  options.startup_sdos = Span<const ecat::SdoRequest>(startup_sdos_.data(), n);
  return master_.bring_up(options);
}

JointCycleResult JointBus::cycle(const JointReferences& references, JointFeedback& feedback) noexcept {
  for (std::size_t p = 0; p < ecat::kMaxSlaves; ++p) {
    if (kJointOfSlave[p] == kNoJoint) continue;
    encode_outputs(references[kJointOfSlave[p]], ByteSpan(image_.data() + kRobotImageLayout.slaves[p].output_offset, kJointOutputBytes));
  }
  last_cycle_ = master_.cycle();  // silences the outputs of joints out of the exchange
  const ecat::CycleResult& r = last_cycle_;
  JointCycleResult result;
  result.cycle = r.cycle;
  result.state = r.state;
  result.frame_received = r.frame_received;
  result.sent_at = r.sent_at;
  result.received_at = r.received_at;
  result.valid = joints_of_slaves(r.valid);
  result.out = joints_of_slaves(r.out);
  feedback.valid = result.valid;
  for (std::size_t p = 0; p < ecat::kMaxSlaves; ++p) {
    if (kJointOfSlave[p] == kNoJoint || (r.valid & ecat::slave_bit(p)) == 0) continue;
    feedback.joints[kJointOfSlave[p]] =
        decode_inputs(ConstByteSpan(image_.data() + kRobotImageLayout.slaves[p].input_offset, kJointInputBytes));
  }
  return result;
}

bool JointBus::pop_report(JointLinkReport& out) noexcept {
  if (!master_.pop_report(out.link)) return false;
  out.joints = joints_of_slaves(out.link.slaves);
  return true;
}

bool JointBus::request_limits(std::size_t joint, const JointLimits& limits, std::uint32_t tag) noexcept {
  std::array<ecat::SdoRequest, kLimitSdosPerJoint> requests{};
  const std::size_t n = joint_limit_sdos(joint, limits, requests.data(), requests.size());
  if (n == 0 || master_.mailbox().free_slots() < n) return false;
  for (std::size_t i = 0; i < n; ++i) {
    requests[i].tag = tag;
    (void)master_.mailbox().submit(requests[i]);  // room checked above
  }
  return true;
}

}  // namespace rescue::drivers
