// Where the joint manager keeps the error-joints file: an interface (so tests can make writes fail)
// and the real one, a file in the state directory written with hal::write_file_atomically.
#pragma once

#include "core/robot/error_joints_file.hpp"
#include "core/base/result.hpp"
#include "hal/files/durable_file.hpp"

namespace rescue::app {

struct ErrorJointsLoad {
  bool file_present{false};     // false: no file (a clean robot); decoded.status says not_found
  ErrorJointsDecoded decoded;   // what could be read, and the first problem
  // The second copy (ErrorJointsFileStorage::kCopyName), written after the file on every save: a
  // single damaged file never forgets a loss.
  bool copy_present{false};
  ErrorJointsDecoded copy;
  // A complete temporary file newer than the file (or with no file): a write interrupted between the
  // temporary file's fsync and its rename. Its joints were being recorded lost.
  bool newer_temporary{false};
  ErrorJointsContents temporary;
};

class ErrorJointsStorage {
 public:
  ErrorJointsStorage() = default;
  ErrorJointsStorage(const ErrorJointsStorage&) = delete;
  ErrorJointsStorage& operator=(const ErrorJointsStorage&) = delete;
  ErrorJointsStorage(ErrorJointsStorage&&) = delete;
  ErrorJointsStorage& operator=(ErrorJointsStorage&&) = delete;
  virtual ~ErrorJointsStorage() = default;

  virtual ErrorJointsLoad load() noexcept = 0;
  // Durable and atomic: on success the new contents survive a power cut; on failure the old ones stay.
  // The file storage writes the second copy, then the file: a crash between leaves one of them newer,
  // both readable.
  virtual Status save(const ErrorJointsContents& contents) noexcept = 0;
  // Keeps an unusable file for post-mortem, under a name of its own (never replacing an earlier one),
  // before a new file replaces it. Returns the set-aside suffix (set_aside_name()).
  virtual Result<std::uint32_t> set_aside() noexcept = 0;
};

class ErrorJointsFileStorage final : public ErrorJointsStorage {
 public:
  static constexpr const char* kFileName = "error-joints.bin";
  static constexpr const char* kTemporaryName = "error-joints.bin.tmp";  // hal::write_file_atomically's
  static constexpr const char* kSetAsideName = "error-joints.bin.unusable";
  // The second copy, written (atomically) before the file itself on every save; the file's directory
  // fsync makes both durable.
  static constexpr const char* kCopyName = "error-joints.bin.copy";
  static constexpr std::uint32_t kMaxSetAside = 999;  // kSetAsideName, then kSetAsideName.1 ... .999
  // Larger than any valid file (kErrorJointsMaxFileSize), so "oversized" is told apart from "too long
  // for the format"; a bigger file is refused before it is read.
  static constexpr std::size_t kReadCap = 4096;

  // `state_dir` is copied; it must exist (hal::resolve_state_dir creates it).
  explicit ErrorJointsFileStorage(const char* state_dir) noexcept;

  ErrorJointsLoad load() noexcept override;
  Status save(const ErrorJointsContents& contents) noexcept override;
  Result<std::uint32_t> set_aside() noexcept override;

  const char* directory() const noexcept { return dir_.c_str(); }

 private:
  hal::PathBuffer dir_;
  bool dir_fits_{false};
};

// "error-joints.bin.unusable" for suffix 0, else "error-joints.bin.unusable.<suffix>".
void set_aside_name(std::uint32_t suffix, char* out, std::size_t capacity) noexcept;

}  // namespace rescue::app
