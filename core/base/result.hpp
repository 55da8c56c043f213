// Error values used across the firmware: no exceptions, every failure is a value that names what
// went wrong (a static string), where (up to two numbers, e.g. datagram index and byte offset), and
// its kind. Result<T> carries either a T or an Error and must be used ([[nodiscard]]).
#pragma once

#include <cassert>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>

namespace rescue {

enum class Errc : std::uint16_t {
  ok = 0,
  invalid_argument,   // a caller passed something outside the contract
  out_of_range,       // an index, address or value outside its valid range
  capacity_exceeded,  // a fixed-capacity container or buffer is full
  truncated,          // input ended before a field it announced
  malformed,          // input is complete but inconsistent
  checksum,           // a checksum or CRC does not match
  version,            // an unsupported format version
  timeout,            // a deadline passed
  io_error,           // the OS refused an I/O operation (errno in detail)
  permission_denied,  // the OS refused for lack of privilege
  not_found,          // a named thing does not exist
  busy,               // try again later
  refused,            // a state machine or peer refused the request
  mismatch,           // the world differs from what was expected
  unsupported,        // a feature this build or device does not have
};

// Short, stable name of an error kind, for logs and CLI messages.
const char* to_string(Errc code) noexcept;

struct Error {
  Errc code{Errc::ok};
  const char* what{""};      // static string: the field, operation or reason
  std::uint32_t detail0{0};  // meaning given by `what` (e.g. datagram index, errno)
  std::uint32_t detail1{0};  // meaning given by `what` (e.g. byte offset)
};

constexpr Error make_error(Errc code, const char* what, std::uint32_t d0 = 0, std::uint32_t d1 = 0) {
  return Error{code, what, d0, d1};
}

template <typename T>
class [[nodiscard]] Result {
 public:
  // Implicit from a value or an error so `return value;` and `return make_error(...)` both read well.
  Result(const T& value) : has_value_(true) { new (&storage_) T(value); }       // NOLINT(google-explicit-constructor)
  Result(T&& value) : has_value_(true) { new (&storage_) T(std::move(value)); }  // NOLINT(google-explicit-constructor)
  Result(Error error) : has_value_(false), error_(error) {                       // NOLINT(google-explicit-constructor)
    assert(error.code != Errc::ok);
  }
  Result(const Result& other) : has_value_(other.has_value_), error_(other.error_) {
    if (has_value_) new (&storage_) T(*other.ptr());
  }
  Result(Result&& other) noexcept : has_value_(other.has_value_), error_(other.error_) {
    if (has_value_) new (&storage_) T(std::move(*other.ptr()));
  }
  Result& operator=(const Result& other) {
    if (this != &other) {
      destroy();
      has_value_ = other.has_value_;
      error_ = other.error_;
      if (has_value_) new (&storage_) T(*other.ptr());
    }
    return *this;
  }
  Result& operator=(Result&& other) noexcept {
    if (this != &other) {
      destroy();
      has_value_ = other.has_value_;
      error_ = other.error_;
      if (has_value_) new (&storage_) T(std::move(*other.ptr()));
    }
    return *this;
  }
  ~Result() { destroy(); }

  bool ok() const noexcept { return has_value_; }
  explicit operator bool() const noexcept { return has_value_; }

  T& value() & noexcept {
    assert(has_value_);
    return *ptr();
  }
  const T& value() const& noexcept {
    assert(has_value_);
    return *ptr();
  }
  T value_or(T fallback) const noexcept { return has_value_ ? *ptr() : fallback; }
  const Error& error() const noexcept {
    assert(!has_value_);
    return error_;
  }

 private:
  T* ptr() noexcept { return std::launder(reinterpret_cast<T*>(&storage_)); }  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  const T* ptr() const noexcept { return std::launder(reinterpret_cast<const T*>(&storage_)); }  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  void destroy() noexcept {
    if (has_value_) ptr()->~T();
  }

  bool has_value_;
  Error error_{};
  // NOLINTNEXTLINE(bugprone-sizeof-expression): T may itself be a pointer (Result<Queue*>)
  std::aligned_storage_t<sizeof(T), alignof(T)> storage_;
};

// Success or an Error, for operations without a value.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error) : error_(error) { assert(error.code != Errc::ok); }  // NOLINT(google-explicit-constructor)
  static Status success() { return Status{}; }

  bool ok() const noexcept { return error_.code == Errc::ok; }
  explicit operator bool() const noexcept { return ok(); }
  const Error& error() const noexcept { return error_; }

 private:
  Error error_{};
};

}  // namespace rescue

// Propagate a failed Status/Result from the current function.
#define RESCUE_TRY(expr)                                 \
  do {                                                   \
    auto rescue_try_result_ = (expr);                    \
    if (!rescue_try_result_.ok()) return rescue_try_result_.error(); \
  } while (false)
