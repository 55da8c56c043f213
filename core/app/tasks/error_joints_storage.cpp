#include "core/app/tasks/error_joints_storage.hpp"

#include <array>
#include <cstdio>
#include <cstring>

namespace rescue::app {

namespace {

// The temporary file of an interrupted write, when it is complete and newer than what `out` holds.
void look_for_newer_temporary(const char* dir, ErrorJointsLoad& out) noexcept {
  auto path = hal::join_path(dir, ErrorJointsFileStorage::kTemporaryName);
  if (!path.ok()) return;
  std::array<std::uint8_t, ErrorJointsFileStorage::kReadCap> buffer{};
  auto size = hal::read_file_capped(path.value().c_str(), ByteSpan(buffer));
  if (!size.ok()) return;
  const ErrorJointsDecoded tmp = decode_error_joints(ConstByteSpan(buffer.data(), size.value()));
  if (!tmp.status.ok()) return;  // an incomplete temporary file is what a crash before fsync leaves
  const bool newer = !out.file_present || !out.decoded.status.ok() || tmp.contents.sequence > out.decoded.contents.sequence;
  if (!newer) return;
  out.newer_temporary = true;
  out.temporary = tmp.contents;
}

}  // namespace

ErrorJointsFileStorage::ErrorJointsFileStorage(const char* state_dir) noexcept {
  const std::size_t len = state_dir != nullptr ? std::strlen(state_dir) : 0;
  dir_fits_ = len > 0 && len < dir_.text.size();
  if (dir_fits_) std::memcpy(dir_.text.data(), state_dir, len + 1);
}

namespace {

// One of the two files: whether something is at its name, and what could be decoded.
bool read_one(const char* dir, const char* name, ErrorJointsDecoded& out) noexcept {
  auto path = hal::join_path(dir, name);
  if (!path.ok()) {
    out.status = path.error();
    return false;
  }
  std::array<std::uint8_t, ErrorJointsFileStorage::kReadCap> buffer{};
  auto size = hal::read_file_capped(path.value().c_str(), ByteSpan(buffer));
  if (!size.ok()) {
    out.status = size.error();
    return size.error().code != Errc::not_found;
  }
  out = decode_error_joints(ConstByteSpan(buffer.data(), size.value()));
  return true;
}

}  // namespace

ErrorJointsLoad ErrorJointsFileStorage::load() noexcept {
  ErrorJointsLoad out;
  if (!dir_fits_) {
    out.decoded.status = make_error(Errc::invalid_argument, "state directory path empty or too long");
    return out;
  }
  out.file_present = read_one(dir_.c_str(), kFileName, out.decoded);
  out.copy_present = read_one(dir_.c_str(), kCopyName, out.copy);
  look_for_newer_temporary(dir_.c_str(), out);
  return out;
}


void set_aside_name(std::uint32_t suffix, char* out, std::size_t capacity) noexcept {
  if (capacity == 0) return;
  if (suffix == 0) {
    (void)std::snprintf(out, capacity, "%s", ErrorJointsFileStorage::kSetAsideName);
  } else {
    (void)std::snprintf(out, capacity, "%s.%u", ErrorJointsFileStorage::kSetAsideName, suffix);
  }
}

Status ErrorJointsFileStorage::save(const ErrorJointsContents& contents) noexcept {
  if (!dir_fits_) return make_error(Errc::invalid_argument, "state directory path empty or too long");
  std::array<std::uint8_t, kErrorJointsMaxFileSize> image{};
  auto size = encode_error_joints(contents, ByteSpan(image));
  if (!size.ok()) return size.error();
  const ConstByteSpan bytes(image.data(), size.value());
  // The copy first, then the file, whose directory fsync makes both renames durable (three fsyncs, not
  // four: on a slow disk the save stays within the run's drain limit). A stop between the two leaves
  // the copy newer; start-up takes the newer of the two.
  RESCUE_TRY(hal::write_file_atomically(dir_.c_str(), kCopyName, bytes, hal::DirectorySync::later));
  return hal::write_file_atomically(dir_.c_str(), kFileName, bytes);
}

Result<std::uint32_t> ErrorJointsFileStorage::set_aside() noexcept {
  if (!dir_fits_) return make_error(Errc::invalid_argument, "state directory path empty or too long");
  return hal::set_aside_durably(dir_.c_str(), kFileName, kSetAsideName, kMaxSetAside);
}

}  // namespace rescue::app
