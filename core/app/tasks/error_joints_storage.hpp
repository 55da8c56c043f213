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
  virtual Status save(const ErrorJointsContents& contents) noexcept = 0;
  // Keeps an unusable file for post-mortem, under another name, before a new file replaces it.
  virtual Status set_aside() noexcept = 0;
};

class ErrorJointsFileStorage final : public ErrorJointsStorage {
 public:
  static constexpr const char* kFileName = "error-joints.bin";
  static constexpr const char* kSetAsideName = "error-joints.bin.unusable";
  // Larger than any valid file (kErrorJointsMaxFileSize), so "oversized" is told apart from "too long
  // for the format"; a bigger file is refused before it is read.
  static constexpr std::size_t kReadCap = 4096;

  // `state_dir` is copied; it must exist (hal::resolve_state_dir creates it).
  explicit ErrorJointsFileStorage(const char* state_dir) noexcept;

  ErrorJointsLoad load() noexcept override;
  Status save(const ErrorJointsContents& contents) noexcept override;
  Status set_aside() noexcept override;

  const char* directory() const noexcept { return dir_.c_str(); }

 private:
  hal::PathBuffer dir_;
  bool dir_fits_{false};
};

}  // namespace rescue::app
