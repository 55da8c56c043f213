// libFuzzer target: the master's bring-up against a network that answers with arbitrary bytes.
// A fake NIC returns each frame the master sends with every datagram's data and working counter
// taken from the fuzz input (the frame's structure kept, as a real ESC chain keeps it); when the
// input runs out the network goes silent. Whatever the answers, the bring-up must end (success or
// an error value) without reading or writing out of bounds: SII words, port times, AL status and
// mailbox bytes are all untrusted.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include "drivers/joint/joint_bus.hpp"
#include "ecat/codec/frame.hpp"
#include "hal/time/clock.hpp"
#include "hal/net/nic.hpp"

namespace {

using namespace rescue;

class ArbitraryNetwork final : public hal::Nic {
 public:
  ArbitraryNetwork(const std::uint8_t* data, std::size_t size) noexcept : data_(data), size_(size) {}

  Status send(ConstByteSpan frame) noexcept override {
    if (frame.size() > frame_.size()) return make_error(Errc::invalid_argument, "frame too long");
    std::memcpy(frame_.data(), frame.data(), frame.size());
    length_ = frame.size();
    pending_ = used_ < size_;
    if (!pending_) return Status::success();
    auto view = ecat::MutableFrameView::parse(ByteSpan(frame_.data(), length_));
    if (!view.ok()) return Status::success();
    for (const ecat::MutableDatagramView d : view.value()) {
      for (std::uint8_t& b : d.data()) b = next();
      d.set_wkc(static_cast<std::uint16_t>(next() % 4));  // small counters are the interesting ones
    }
    clock_.advance(10'000);
    return Status::success();
  }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    if (!pending_) {
      clock_.sleep_until(deadline);
      return make_error(Errc::timeout, "silent");
    }
    pending_ = false;
    std::memcpy(buffer.data(), frame_.data(), length_);
    return length_;
  }
  hal::Clock& clock() noexcept override { return clock_; }
  const char* name() const noexcept override { return "fuzz"; }
  hal::NicStats stats() const noexcept override { return {}; }

 private:
  std::uint8_t next() noexcept { return used_ < size_ ? data_[used_++] : 0; }

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t used_{0};
  hal::VirtualClock clock_{0};
  std::array<std::uint8_t, ecat::kMaxFrameSize> frame_{};
  std::size_t length_{0};
  bool pending_{false};
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ArbitraryNetwork network(data, size);
  auto bus = std::make_unique<drivers::JointBus>(network);  // a fuzzer may allocate; ~40 KiB
  ecat::MasterOptions options;
  options.drift_compensation_frames = 4;
  options.al.state_timeout = 2 * hal::kNsPerMs;
  options.op_timeout = 2 * hal::kNsPerMs;
  options.startup_sdo_timeout = 2 * hal::kNsPerMs;
  options.sii.busy_timeout = hal::kNsPerMs;
  if (bus->bring_up(options).ok()) {
    drivers::JointReferences refs{};
    drivers::JointFeedback feedback{};
    for (int i = 0; i < 8; ++i) (void)bus->cycle(refs, feedback);
  }
  return 0;
}
