// Where the joint manager publishes its drive demand after every step: an interface, and its
// implementation over the seqlock the EtherCAT handler reads every cycle (core/concurrency/seqlock.hpp).
// The joint manager owns its demand: it alone decides what each drive is told (design brief section 3).
#pragma once

#include "core/concurrency/seqlock.hpp"
#include "core/robot/joint_demand.hpp"

namespace rescue::app {

class JointDemandSink {
 public:
  JointDemandSink() = default;
  JointDemandSink(const JointDemandSink&) = delete;
  JointDemandSink& operator=(const JointDemandSink&) = delete;
  JointDemandSink(JointDemandSink&&) = delete;
  JointDemandSink& operator=(JointDemandSink&&) = delete;
  virtual ~JointDemandSink() = default;
  virtual void publish(const RobotDemand& demand) noexcept = 0;
};

class SeqlockDemandSink final : public JointDemandSink {
 public:
  explicit SeqlockDemandSink(Seqlock<RobotDemand>& published) noexcept : published_(&published) {}
  void publish(const RobotDemand& demand) noexcept override { published_->write(demand); }

 private:
  Seqlock<RobotDemand>* published_;
};

}  // namespace rescue::app
