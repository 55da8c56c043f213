#include "drivers/sim/devices/joint_drive_device.hpp"

#include <algorithm>
#include <cstring>

#include "core/robot/robot.hpp"
#include "drivers/sim/coe/coe_sdo_server.hpp"
#include "ecat/mailbox/mailbox.hpp"

namespace rescue::drivers {
namespace {

namespace al_code = ecat::reg::al_code;

double initial_position(std::size_t joint) noexcept {
  const JointLimits& l = kJoints[joint].limits;
  return kJoints[joint].continuous ? 0.0 : std::max(l.position_min_rad, std::min(l.position_max_rad, 0.0));
}

}  // namespace

JointDriveDevice::JointDriveDevice(std::size_t position) noexcept
    : joint_(kSlaves[position].joint),
      objects_(joint_, position),
      drive_(motor_limits_of(joint_), initial_position(joint_)),
      // Cannot fail: the content is fixed and its size is checked by the tests.
      sii_(build_joint_drive_sii(position).value_or(SiiImage{})) {
  drive_.power_up();
  objects_.store_inputs(drive_.inputs());
}

ProcessDataLayout JointDriveDevice::process_data_layout() const noexcept {
  return {kJointOutputsSyncManager, static_cast<std::uint16_t>(kJointOutputBytes), kJointInputsSyncManager,
          static_cast<std::uint16_t>(kJointInputBytes)};
}

std::uint16_t JointDriveDevice::on_state_change(AlState from, AlState to, EscPdi& esc) noexcept {
  if (from == AlState::op) lose_outputs(now_);
  if (to == AlState::init) {
    last_request_counter_ = 0;
    last_response_length_ = 0;
    segments_.active = false;
  }
  if (from == AlState::pre_op && to == AlState::safe_op) {
    const ObjectDictionary& od = objects_.od();
    const bool rx_ok = od.get_u32(0x1C12, 0) == 1 && od.get_u32(kJointRxPdoIndex, 0) == kJointRxMapping.size();
    const bool tx_ok = od.get_u32(0x1C13, 0) == 1 && od.get_u32(kJointTxPdoIndex, 0) == kJointTxMapping.size();
    if (!rx_ok) return al_code::kInvalidOutputMapping;
    if (!tx_ok) return al_code::kInvalidInputMapping;
    const DcSyncSettings dc = esc.dc_sync_settings();
    if (dc.sync0_active && dc.sync0_cycle_ns < kMinSync0CycleNs) return al_code::kDcInvalidSyncCycleTime;
  }
  return al_code::kNoError;
}

void JointDriveDevice::on_mailbox(ConstByteSpan message, EscPdi& esc) noexcept {
  mirror_inputs();  // an SDO upload may read the inputs
  auto header = ecat::mbx::decode(message);
  const std::uint8_t counter = header.ok() ? header.value().header.counter : 0;
  if (counter != 0 && counter == last_request_counter_ && last_response_length_ > 0) {
    // The master repeats a request whose response it lost: answer again, do not run it twice.
    ++mailbox_repeats_;
    (void)esc.post_mailbox(ConstByteSpan(last_response_.data(), last_response_length_));
    return;
  }
  last_request_counter_ = counter;
  const std::size_t capacity = std::min<std::size_t>(esc.mailbox_out_capacity(), last_response_.size());
  response_counter_ = ecat::mbx::next_counter(response_counter_);
  last_response_length_ = serve_sdo(message, objects_.od(), esc.al_state(), ByteSpan(last_response_.data(), capacity),
                                    response_counter_, &segments_);
  settings_stale_ = true;  // a download may have changed them
  if (last_response_length_ == 0) return;
  if (!esc.post_mailbox(ConstByteSpan(last_response_.data(), last_response_length_)).ok()) return;
  // The fragments of a long SDO Information answer follow on their own (the master reads them
  // without asking again), as many as the mailbox queue takes.
  for (std::uint16_t fragment = 1;; ++fragment) {
    const std::uint8_t next = ecat::mbx::next_counter(response_counter_);
    const std::size_t n = serve_sdo_fragment(message, objects_.od(), ByteSpan(last_response_.data(), capacity), next, fragment);
    if (n == 0 || !esc.post_mailbox(ConstByteSpan(last_response_.data(), n)).ok()) return;
    response_counter_ = next;
    last_response_length_ = n;
  }
}

void JointDriveDevice::on_cycle(ConstByteSpan outputs, ByteSpan inputs, const CycleContext& ctx, EscPdi&) noexcept {
  const bool valid = ctx.state == AlState::op && outputs.size() >= kJointOutputBytes;
  const DriveSettings& current = settings();
  if (valid) {
    const JointOutputs out = decode_outputs(outputs);
    objects_.store_outputs(out);
    drive_.apply_outputs(out, true, current, ctx.now);
  } else {
    drive_.apply_outputs(JointOutputs{}, false, current, ctx.now);
  }
  const JointInputs in = drive_.inputs();
  objects_.store_inputs(in);
  od_inputs_stale_ = false;
  if (inputs.size() >= kJointInputBytes) encode_inputs(in, inputs);
}

void JointDriveDevice::step(hal::Nanoseconds now, EscPdi&) noexcept {
  if (!started_) {
    // Segment time starts wherever its clock does: the first call only sets the time base.
    started_ = true;
    now_ = now;
    return;
  }
  if (now > now_) {
    drive_.advance(now - now_, settings());
    now_ = now;
    od_inputs_stale_ = true;
  }
}

const DriveSettings& JointDriveDevice::settings() noexcept {
  if (settings_stale_) {
    settings_ = objects_.settings();
    settings_stale_ = false;
  }
  return settings_;
}

void JointDriveDevice::mirror_inputs() noexcept {
  if (!od_inputs_stale_) return;
  objects_.store_inputs(drive_.inputs());
  od_inputs_stale_ = false;
}

void JointDriveDevice::lose_outputs(hal::Nanoseconds now) noexcept {
  drive_.apply_outputs(JointOutputs{}, false, settings(), now);
  objects_.store_inputs(drive_.inputs());
  od_inputs_stale_ = false;
}

void JointDriveDevice::inject_fault(std::uint16_t error_code) noexcept {
  drive_.inject_fault(error_code);
  objects_.store_inputs(drive_.inputs());
  od_inputs_stale_ = false;
}

Status JointDriveDevice::corrupt_pdo_mapping(PdoMappingFault fault) noexcept {
  objects_.corrupt_mapping(fault);
  return Status::success();
}

}  // namespace rescue::drivers
