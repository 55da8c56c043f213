// Where the joint manager reads the EtherCAT handler's published joint values: an interface, and its
// implementation over the seqlock the handler writes every cycle (core/concurrency/seqlock.hpp).
#pragma once

#include "core/robot/joint_limits.hpp"
#include "core/concurrency/seqlock.hpp"

namespace rescue::app {

// read() copies one consistent snapshot, or returns false when none could be had this time (the
// joint manager then keeps the previous one).
class JointSampleSource {
 public:
  JointSampleSource() = default;
  JointSampleSource(const JointSampleSource&) = delete;
  JointSampleSource& operator=(const JointSampleSource&) = delete;
  JointSampleSource(JointSampleSource&&) = delete;
  JointSampleSource& operator=(JointSampleSource&&) = delete;
  virtual ~JointSampleSource() = default;
  virtual bool read(RobotSample& out) noexcept = 0;
};

class SeqlockSampleSource final : public JointSampleSource {
 public:
  explicit SeqlockSampleSource(const Seqlock<RobotSample>& published) noexcept : published_(&published) {}
  bool read(RobotSample& out) noexcept override { return published_->try_read(out); }

 private:
  const Seqlock<RobotSample>* published_;
};

}  // namespace rescue::app
