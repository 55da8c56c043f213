#include "ecat/capture/capture_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

#include "core/base/endian.hpp"

namespace rescue::ecat {
namespace {

using namespace capture;  // NOLINT(google-build-using-namespace): the format's names, in this file only

constexpr std::size_t pad4(std::size_t n) noexcept { return (n + 3) & ~std::size_t{3}; }

// Appends little-endian block fields to a buffer whose capacity the caller has checked.
class BlockPacker {
 public:
  explicit BlockPacker(std::uint8_t* out) noexcept : out_(out) {}
  void u16(std::uint16_t v) noexcept {
    store_le16(out_ + size_, v);
    size_ += 2;
  }
  void u32(std::uint32_t v) noexcept {
    store_le32(out_ + size_, v);
    size_ += 4;
  }
  void u64(std::uint64_t v) noexcept {
    store_le64(out_ + size_, v);
    size_ += 8;
  }
  // Bytes, zero-padded to a multiple of 4.
  void padded(const std::uint8_t* data, std::size_t n) noexcept {
    if (n > 0) std::memcpy(out_ + size_, data, n);
    std::memset(out_ + size_ + n, 0, pad4(n) - n);
    size_ += pad4(n);
  }
  void option(std::uint16_t code, const std::uint8_t* value, std::size_t n) noexcept {
    u16(code);
    u16(static_cast<std::uint16_t>(n));
    padded(value, n);
  }
  // Starts a block: type and a length placeholder.
  void begin(std::uint32_t type) noexcept {
    start_ = size_;
    u32(type);
    u32(0);
  }
  // Ends the block: trailing length, and the leading one patched.
  void end() noexcept {
    const auto total = static_cast<std::uint32_t>(size_ - start_ + kBlockTrailerSize);
    u32(total);
    store_le32(out_ + start_ + 4, total);
  }
  std::size_t size() const noexcept { return size_; }

 private:
  std::uint8_t* out_;
  std::size_t size_{0};
  std::size_t start_{0};
};

const char kUserApplication[] = "rescue-motion";

}  // namespace

CaptureWriter::~CaptureWriter() { (void)close(); }

Status CaptureWriter::open(const char* path, const CaptureWriterOptions& options) noexcept {
  if (is_open()) return make_error(Errc::invalid_argument, "already open");
  const char* name = options.interface_name != nullptr ? options.interface_name : "";
  const std::size_t name_length = std::strlen(name);
  if (name_length > kMaxInterfaceNameLength) {
    return make_error(Errc::invalid_argument, "interface name too long", static_cast<std::uint32_t>(name_length));
  }
  // A regular file only, created or truncated, never through a link; a FIFO or a device at the name
  // is refused at once (hal/files/trusted_file.hpp): problem() says why.
  Result<hal::OpenFile> file = hal::open_regular_for_write(path, 0644, problem_);
  if (!file.ok()) return file.error();
  fd_ = file.value().release();
  offset_ = options.timestamp_offset;
  good_size_ = 0;
  stats_ = CaptureWriterStats{};

  BlockPacker p(block_.data());
  p.begin(kBlockSectionHeader);
  p.u32(kByteOrderMagic);
  p.u16(kPcapngMajor);
  p.u16(kPcapngMinor);
  p.u64(~std::uint64_t{0});  // section length: not given (-1)
  p.option(kOptShbUserApplication, reinterpret_cast<const std::uint8_t*>(kUserApplication),  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
           sizeof kUserApplication - 1);
  p.u32(kOptEndOfOptions);
  p.end();

  p.begin(kBlockInterfaceDescription);
  p.u16(kLinkTypeEthernet);
  p.u16(0);
  p.u32(kSnapLength);
  if (name_length > 0) {
    p.option(kOptIfName, reinterpret_cast<const std::uint8_t*>(name), name_length);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  }
  const std::uint8_t resolution = kTsresolNanoseconds;
  p.option(kOptIfTimestampResolution, &resolution, 1);
  p.u32(kOptEndOfOptions);
  p.end();

  if (!write_block(p.size())) {
    const int error = stats_.last_errno;
    (void)::close(fd_);
    fd_ = -1;
    return make_error(Errc::io_error, "write capture header", static_cast<std::uint32_t>(error));
  }
  return Status::success();
}

void CaptureWriter::record(ConstByteSpan frame, hal::Nanoseconds timestamp, FrameDirection direction) noexcept {
  if (!is_open()) return;
  std::size_t captured = frame.size();
  if (captured > kSnapLength) {
    captured = kSnapLength;
    ++stats_.frames_truncated;
  }
  // Times before the Unix epoch cannot be written; they only arise from a bad offset.
  const hal::Nanoseconds unix_ns = timestamp + offset_;
  const std::uint64_t ts = unix_ns > 0 ? static_cast<std::uint64_t>(unix_ns) : 0;

  BlockPacker p(block_.data());
  p.begin(kBlockEnhancedPacket);
  p.u32(0);  // interface 0
  p.u32(static_cast<std::uint32_t>(ts >> 32));
  p.u32(static_cast<std::uint32_t>(ts));
  p.u32(static_cast<std::uint32_t>(captured));
  p.u32(static_cast<std::uint32_t>(frame.size()));
  p.padded(frame.data(), captured);
  if (direction != FrameDirection::unknown) {
    std::uint8_t flags[4];
    store_le32(flags, static_cast<std::uint32_t>(direction));
    p.option(kOptEpbFlags, flags, sizeof flags);
    p.u32(kOptEndOfOptions);
  }
  p.end();
  if (write_block(p.size())) ++stats_.frames_written;
}

bool CaptureWriter::write_block(std::size_t size) noexcept {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd_, block_.data() + done, size - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    stats_.last_errno = n < 0 ? errno : ENOSPC;  // a write of 0 bytes: the device is full
    ++stats_.write_errors;
    if (done > 0) {
      // Cut the torn block off so the file ends with a complete block. A pipe cannot be cut; its
      // reader sees a torn block, which is the best a pipe allows.
      if (::ftruncate(fd_, static_cast<off_t>(good_size_)) == 0) {
        (void)::lseek(fd_, static_cast<off_t>(good_size_), SEEK_SET);
      }
    }
    return false;
  }
  good_size_ += size;
  stats_.bytes_written = good_size_;
  return true;
}

Status CaptureWriter::close() noexcept {
  if (!is_open()) return Status::success();
  const int rc = ::close(fd_);
  fd_ = -1;
  if (rc != 0) return make_error(Errc::io_error, "close capture", static_cast<std::uint32_t>(errno));
  return Status::success();
}

hal::Nanoseconds unix_time_offset(hal::Clock& clock) noexcept {
  timespec wall{};
  (void)clock_gettime(CLOCK_REALTIME, &wall);  // cannot fail for CLOCK_REALTIME with a valid pointer
  const hal::Nanoseconds unix_now = static_cast<hal::Nanoseconds>(wall.tv_sec) * hal::kNsPerSec + wall.tv_nsec;
  return unix_now - clock.now();
}

}  // namespace rescue::ecat
