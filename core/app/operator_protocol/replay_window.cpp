#include "core/app/operator_protocol/replay_window.hpp"

#include <algorithm>
#include <cstring>

#include "core/base/crc32.hpp"
#include "core/base/endian.hpp"
#include "hal/files/durable_file.hpp"

namespace rescue::app::protocol {
namespace {

constexpr std::array<std::uint8_t, 4> kFileMagic{{0x52, 0x4D, 0x52, 0x57}};  // "RMRW"
constexpr std::uint16_t kFileVersion = 1;

}  // namespace

Result<std::size_t> encode_replay_file(const PersistedLimits& limits, ByteSpan out) noexcept {
  const std::size_t size = kReplayFileHeaderSize + limits.size() * kReplayFileRecordSize + 4;
  if (out.size() < size) return make_error(Errc::capacity_exceeded, "replay file buffer too small");
  std::uint8_t* p = out.data();
  std::memset(p, 0, size);
  std::memcpy(p, kFileMagic.data(), kFileMagic.size());
  store_le16(p + 4, kFileVersion);
  store_le16(p + 6, static_cast<std::uint16_t>(limits.size()));
  // bytes 8..15 reserved, 0
  for (std::size_t i = 0; i < limits.size(); ++i) {
    std::uint8_t* r = p + kReplayFileHeaderSize + i * kReplayFileRecordSize;
    store_le32(r, limits[i].sender);
    // bytes 4..7 reserved, 0
    store_le64(r + 8, limits[i].limit);
  }
  store_le32(p + size - 4, crc32(ConstByteSpan(p, size - 4)));
  return size;
}

Result<PersistedLimits> decode_replay_file(ConstByteSpan bytes) noexcept {
  if (bytes.size() < kReplayFileHeaderSize + 4) return make_error(Errc::truncated, "replay file shorter than its header");
  if (bytes.size() > kReplayFileMaxSize) return make_error(Errc::capacity_exceeded, "replay file too long");
  const std::uint8_t* p = bytes.data();
  if (std::memcmp(p, kFileMagic.data(), kFileMagic.size()) != 0) return make_error(Errc::malformed, "not a replay-window file (bad magic)");
  if (load_le16(p + 4) != kFileVersion) return make_error(Errc::version, "unsupported replay-window file version", load_le16(p + 4));
  const std::size_t count = load_le16(p + 6);
  if (count > kMaxSenders) return make_error(Errc::capacity_exceeded, "replay file lists too many senders");
  const std::size_t size = kReplayFileHeaderSize + count * kReplayFileRecordSize + 4;
  if (bytes.size() != size) return make_error(Errc::malformed, "replay file length differs from its count");
  if (load_le32(p + size - 4) != crc32(ConstByteSpan(p, size - 4))) return make_error(Errc::checksum, "replay file checksum mismatch");
  for (std::size_t i = 8; i < kReplayFileHeaderSize; ++i) {
    if (p[i] != 0) return make_error(Errc::malformed, "reserved bytes not zero");
  }
  PersistedLimits limits;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* r = p + kReplayFileHeaderSize + i * kReplayFileRecordSize;
    if (load_le32(r + 4) != 0) return make_error(Errc::malformed, "reserved bytes not zero");
    const PersistedLimit limit{load_le32(r), load_le64(r + 8)};
    if (std::any_of(limits.begin(), limits.end(), [&](const PersistedLimit& other) { return other.sender == limit.sender; })) {
      return make_error(Errc::malformed, "sender listed twice", limit.sender);
    }
    (void)limits.push_back(limit);  // count <= kMaxSenders
  }
  return limits;
}

FileReplayStore::FileReplayStore(const char* dir) noexcept {
  for (std::size_t i = 0; i + 1 < dir_.size() && dir != nullptr && dir[i] != '\0'; ++i) dir_[i] = dir[i];
}

Result<std::size_t> FileReplayStore::load(ByteSpan out) noexcept {
  const Result<hal::PathBuffer> path = hal::join_path(dir_.data(), kFileName);
  if (!path.ok()) return path.error();
  return hal::read_file_capped(path.value().c_str(), out);
}

Status FileReplayStore::write_limits(ConstByteSpan bytes) noexcept { return hal::write_file_atomically(dir_.data(), kFileName, bytes); }

RestoreOutcome ReplayWindow::restore(std::uint64_t wall_clock_unix_ns) noexcept {
  RestoreOutcome outcome;
  windows_.clear();
  floor_ = 0;
  std::array<std::uint8_t, kReplayFileMaxSize> buffer{};
  const Result<std::size_t> loaded = store_->load(ByteSpan(buffer));
  if (!loaded.ok()) {
    outcome.file_status = loaded.error();
  } else {
    const Result<PersistedLimits> limits = decode_replay_file(ConstByteSpan(buffer.data(), loaded.value()));
    if (limits.ok()) {
      for (const PersistedLimit& l : limits.value()) {
        (void)windows_.push_back(Window{l.sender, l.limit, ~std::uint64_t{0}, l.limit});
      }
      outcome.senders = windows_.size();
      return outcome;
    }
    outcome.file_status = limits.error();
  }
  // No file (a fresh robot) is no risk: nothing was ever accepted. A file that exists but cannot be
  // trusted might hide limits: every sender starts at the robot's wall clock.
  if (outcome.file_status.error().code != Errc::not_found) floor_ = wall_clock_unix_ns + kPersistBlock;
  return outcome;
}

Status ReplayWindow::persist(std::size_t changed, std::uint64_t limit) noexcept {
  PersistedLimits limits;
  for (std::size_t i = 0; i < windows_.size(); ++i) {
    (void)limits.push_back(PersistedLimit{windows_[i].sender, i == changed ? limit : windows_[i].persisted});
  }
  std::array<std::uint8_t, kReplayFileMaxSize> buffer{};
  const Result<std::size_t> size = encode_replay_file(limits, ByteSpan(buffer));
  if (!size.ok()) return size.error();
  const Status saved = store_->write_limits(ConstByteSpan(buffer.data(), size.value()));
  if (!saved.ok()) return saved;
  ++persist_writes_;
  windows_[changed].persisted = limit;
  return Status::success();
}

Status ReplayWindow::accept(std::uint32_t sender, std::uint64_t sequence) noexcept {
  std::size_t index = windows_.size();
  for (std::size_t i = 0; i < windows_.size(); ++i) {
    if (windows_[i].sender == sender) index = i;
  }
  if (index == windows_.size()) {
    if (!windows_.push_back(Window{sender, floor_, ~std::uint64_t{0}, floor_})) {
      return make_error(Errc::capacity_exceeded, "too many senders for the replay window", sender);
    }
  }
  Window& w = windows_[index];
  if (sequence <= w.highest) {
    const std::uint64_t behind = w.highest - sequence;
    if (behind >= kWindowSize) return make_error(Errc::refused, "sequence older than the replay window");
    if ((w.seen & (std::uint64_t{1} << behind)) != 0) return make_error(Errc::refused, "sequence already accepted");
    w.seen |= std::uint64_t{1} << behind;
    return Status::success();
  }
  // Ahead of the window: the limit on disk must cover it before it counts as accepted.
  if (sequence > w.persisted) {
    const std::uint64_t limit = sequence > ~std::uint64_t{0} - kPersistBlock ? ~std::uint64_t{0} : sequence + kPersistBlock;
    const Status persisted = persist(index, limit);
    if (!persisted.ok()) {
      if (w.persisted == floor_ && w.highest == floor_ && index + 1 == windows_.size()) {
        // A sender seen for the first time stays unknown: its slot is not taken by a message that failed.
        windows_.pop_back();
      }
      return make_error(Errc::io_error, "replay window limit not durable; message not accepted",
                        persisted.error().detail0);
    }
  }
  const std::uint64_t shift = sequence - w.highest;
  w.seen = shift >= kWindowSize ? 1U : ((w.seen << shift) | 1U);
  w.highest = sequence;
  return Status::success();
}

}  // namespace rescue::app::protocol
