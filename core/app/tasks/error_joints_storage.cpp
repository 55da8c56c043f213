#include "core/app/tasks/error_joints_storage.hpp"

#include <array>
#include <cstring>

namespace rescue::app {

ErrorJointsFileStorage::ErrorJointsFileStorage(const char* state_dir) noexcept {
  const std::size_t len = state_dir != nullptr ? std::strlen(state_dir) : 0;
  dir_fits_ = len > 0 && len < dir_.text.size();
  if (dir_fits_) std::memcpy(dir_.text.data(), state_dir, len + 1);
}

ErrorJointsLoad ErrorJointsFileStorage::load() noexcept {
  ErrorJointsLoad out;
  if (!dir_fits_) {
    out.decoded.status = make_error(Errc::invalid_argument, "state directory path empty or too long");
    return out;
  }
  auto path = hal::join_path(dir_.c_str(), kFileName);
  if (!path.ok()) {
    out.decoded.status = path.error();
    return out;
  }
  std::array<std::uint8_t, kReadCap> buffer{};
  auto size = hal::read_file_capped(path.value().c_str(), ByteSpan(buffer));
  if (!size.ok()) {
    out.file_present = size.error().code != Errc::not_found;
    out.decoded.status = size.error();
    return out;
  }
  out.file_present = true;
  out.decoded = decode_error_joints(ConstByteSpan(buffer.data(), size.value()));
  return out;
}

Status ErrorJointsFileStorage::save(const ErrorJointsContents& contents) noexcept {
  if (!dir_fits_) return make_error(Errc::invalid_argument, "state directory path empty or too long");
  std::array<std::uint8_t, kErrorJointsMaxFileSize> image{};
  auto size = encode_error_joints(contents, ByteSpan(image));
  if (!size.ok()) return size.error();
  return hal::write_file_atomically(dir_.c_str(), kFileName, ConstByteSpan(image.data(), size.value()));
}

Status ErrorJointsFileStorage::set_aside() noexcept {
  if (!dir_fits_) return make_error(Errc::invalid_argument, "state directory path empty or too long");
  return hal::rename_durably(dir_.c_str(), kFileName, kSetAsideName);
}

}  // namespace rescue::app
