// CaptureWriter: records the frames the master sends and receives to a pcapng file that Wireshark
// and tshark open (link type Ethernet, nanosecond timestamps, direction in epb_flags).
//
//   SHB (little-endian, user application "rescue-motion")
//   IDB (link type 1, snap length 1522, if_name, if_tsresol = 9 -> nanoseconds)
//   EPB per frame (timestamp, captured = original length, data, epb_flags inbound/outbound)
//
// Real-time use: after open() nothing allocates. record() formats the block in a fixed buffer and
// hands it to the kernel with one write(); a failed write is counted (stats()), the torn block is
// cut off again so the file stays readable, and record() returns normally: capturing never stops
// the cycle. Not thread-safe: one thread (the EtherCAT handler) records.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/capture/capture_format.hpp"
#include "ecat/codec/frame.hpp"
#include "hal/files/trusted_file.hpp"
#include "hal/time/clock.hpp"

namespace rescue::ecat {

struct CaptureWriterOptions {
  const char* interface_name{"rescue-motion"};  // if_name: what Wireshark shows as the interface
  // Added to every timestamp given to record(), so that times on hal::Clock's arbitrary time base
  // show as wall-clock time in Wireshark. See unix_time_offset().
  hal::Nanoseconds timestamp_offset{0};
};

struct CaptureWriterStats {
  std::uint64_t frames_written{0};
  std::uint64_t bytes_written{0};     // file size, headers included
  std::uint64_t write_errors{0};      // frames lost because the OS refused or cut the write
  std::uint64_t frames_truncated{0};  // longer than the snap length: written cut to it
  int last_errno{0};                  // errno of the last failed write, 0 if none
};

class CaptureWriter {
 public:
  // Frames up to a VLAN-tagged maximal frame with FCS are kept whole.
  static constexpr std::uint32_t kSnapLength = kMaxFrameSize + kVlanTagSize + 4;  // 1522
  static constexpr std::size_t kMaxInterfaceNameLength = 64;

  CaptureWriter() = default;
  ~CaptureWriter();
  CaptureWriter(const CaptureWriter&) = delete;
  CaptureWriter& operator=(const CaptureWriter&) = delete;
  CaptureWriter(CaptureWriter&&) = delete;
  CaptureWriter& operator=(CaptureWriter&&) = delete;

  // Creates (or truncates) `path` and writes the section header and interface description.
  // Errors: invalid_argument "already open" / "interface name too long", io_error "open capture"
  // or "write capture header" (errno in detail0).
  Status open(const char* path, const CaptureWriterOptions& options = {}) noexcept;

  // Appends one frame (Ethernet header onwards, no FCS) seen at `timestamp` (hal::Clock time).
  // Never fails the caller; problems are counted in stats(). Does nothing when not open.
  void record(ConstByteSpan frame, hal::Nanoseconds timestamp, FrameDirection direction) noexcept;

  // Closes the file. io_error "close capture" when the kernel reports a late write error.
  Status close() noexcept;

  bool is_open() const noexcept { return fd_ >= 0; }
  // Why the last open() refused the path (the path, what was there, the fix).
  const hal::FileProblem& problem() const noexcept { return problem_; }
  const CaptureWriterStats& stats() const noexcept { return stats_; }

 private:
  // Largest enhanced packet block: fixed part, padded data, epb_flags option + end, trailer.
  static constexpr std::size_t kMaxBlockSize =
      capture::kBlockHeaderSize + capture::kEpbFixedBody + ((kSnapLength + 3) & ~std::size_t{3}) + 8 + 4 +
      capture::kBlockTrailerSize;
  static_assert(kMaxBlockSize >= 256, "the block buffer also holds the file header");

  bool write_block(std::size_t size) noexcept;

  int fd_{-1};
  hal::FileProblem problem_{};
  hal::Nanoseconds offset_{0};
  std::uint64_t good_size_{0};  // file size after the last complete block
  CaptureWriterStats stats_{};
  std::array<std::uint8_t, kMaxBlockSize> block_{};
};

// Unix time minus `clock`'s time, now: pass as CaptureWriterOptions::timestamp_offset so that
// records stamped with clock.now() carry wall-clock times.
hal::Nanoseconds unix_time_offset(hal::Clock& clock) noexcept;

}  // namespace rescue::ecat
