#include "core/app/operator_protocol/protocol_auth.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "hal/files/durable_file.hpp"
#include "hal/files/state_dir.hpp"
#include "hal/files/trusted_file.hpp"

namespace rescue::app::protocol {
namespace {

static_assert(crypto_auth_BYTES == kTagSize, "the tag is crypto_auth's");
static_assert(crypto_auth_KEYBYTES == kKeySize, "the key is crypto_auth's");

constexpr std::size_t kKeyHexSize = 2 * kKeySize;
constexpr std::size_t kKeyFileMaxRead = 256;

Error os_error(const char* what) noexcept { return make_error(Errc::io_error, what, static_cast<std::uint32_t>(errno)); }

class Fd {
 public:
  explicit Fd(int fd) noexcept : fd_(fd) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  Fd(Fd&&) = delete;
  Fd& operator=(Fd&&) = delete;
  ~Fd() {
    if (fd_ >= 0) (void)::close(fd_);
  }
  int get() const noexcept { return fd_; }

 private:
  int fd_;
};

}  // namespace

Status init_crypto() noexcept {
  if (sodium_init() < 0) return make_error(Errc::unsupported, "libsodium could not be initialised");
  return Status::success();
}

Result<std::size_t> seal(const Message& message, const Key& key, ByteSpan out) noexcept {
  if (out.size() < kHeaderSize + kTagSize) return make_error(Errc::capacity_exceeded, "datagram buffer too small");
  const Result<std::size_t> payload =
      encode_payload(message, out.subspan(kHeaderSize, out.size() - kHeaderSize - kTagSize));
  if (!payload.ok()) return payload.error();
  Header header = message.header;
  header.payload_length = static_cast<std::uint16_t>(payload.value());
  encode_header(header, out.data());
  const std::size_t signed_size = kHeaderSize + payload.value();
  (void)crypto_auth(out.data() + signed_size, out.data(), signed_size, key.data());
  return signed_size + kTagSize;
}

Status verify_frame(const FrameView& frame, const Key& key) noexcept {
  if (frame.tag.size() != kTagSize) return make_error(Errc::malformed, "tag length");
  if (crypto_auth_verify(frame.tag.data(), frame.signed_bytes.data(), frame.signed_bytes.size(), key.data()) != 0) {
    return make_error(Errc::checksum, "authentication tag does not verify under the key");
  }
  return Status::success();
}

std::uint64_t new_epoch() noexcept {
  std::uint64_t epoch = 0;
  while (epoch == 0) randombytes_buf(&epoch, sizeof epoch);
  return epoch;
}

Result<Key> load_key_file(const char* path, hal::FileProblem& why) noexcept {
  // StrictModes (docs/security.md): the key, and every directory above it, ours or root's and
  // writable by nobody else; the key readable by nobody else; a link only to such a target; nothing
  // at the name can hang the open (O_NONBLOCK, fstat before reading).
  const Result<hal::OpenFile> opened = hal::open_trusted_for_read(path, hal::Secrecy::secret, why);
  if (!opened.ok()) {
    if (opened.error().code == Errc::not_found && opened.error().detail0 != 0) {
      hal::set_problem(why, "%s: key file does not exist (create it with: rescue-motion ctl keygen)", path);
      return make_error(Errc::not_found, "key file does not exist (create it with: rescue-motion ctl keygen)");
    }
    return make_error(opened.error().code, "the key file cannot be used", opened.error().detail0);
  }
  const int fd = opened.value().fd();
  struct stat st {};
  if (::fstat(fd, &st) != 0) return os_error("key file cannot be examined");
  if (st.st_size > static_cast<off_t>(kKeyFileMaxRead)) {
    hal::set_problem(why, "%s: key file too long (create it with: rescue-motion ctl keygen)", path);
    return make_error(Errc::malformed, "key file too long");
  }
  std::array<char, kKeyFileMaxRead + 1> text{};
  std::size_t got = 0;
  while (got < kKeyFileMaxRead) {
    const ssize_t n = ::read(fd, text.data() + got, kKeyFileMaxRead - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return os_error("key file cannot be read");
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  std::size_t length = got;
  while (length > 0 && (text[length - 1] == '\n' || text[length - 1] == '\r')) --length;
  Key key{};
  std::size_t decoded = 0;
  const char* end = nullptr;
  if (length != kKeyHexSize ||
      sodium_hex2bin(key.data(), key.size(), text.data(), length, nullptr, &decoded, &end) != 0 ||
      decoded != kKeySize) {
    sodium_memzero(text.data(), text.size());
    hal::set_problem(why, "%s: key file must hold 64 hex digits (create it with: rescue-motion ctl keygen)", path);
    return make_error(Errc::malformed, "key file must hold 64 hex digits (create it with: rescue-motion ctl keygen)");
  }
  sodium_memzero(text.data(), text.size());
  return key;
}

Status create_key_file(const char* path) noexcept {
  // The directory and the name, for a durable create (hal/files/durable_file.hpp): the key is
  // written under a temporary name, fsynced, and only then given its name, so a keygen stopped
  // half-way (its --timeout on a slow disk, a power cut) leaves no key file, never a partial one.
  const Result<hal::DirAndName> where = hal::split_path(path);
  if (!where.ok()) return where.error();
  Key key{};
  randombytes_buf(key.data(), key.size());
  std::array<char, kKeyHexSize + 2> text{};
  (void)sodium_bin2hex(text.data(), text.size(), key.data(), key.size());
  sodium_memzero(key.data(), key.size());
  text[kKeyHexSize] = '\n';
  std::array<std::uint8_t, kKeyHexSize + 1> line{};
  std::memcpy(line.data(), text.data(), line.size());
  sodium_memzero(text.data(), text.size());
  const Status made =
      hal::create_file_durably(where.value().dir.c_str(), where.value().name, ConstByteSpan(line.data(), line.size()), 0600);
  sodium_memzero(line.data(), line.size());
  if (!made.ok() && made.error().code == Errc::busy) return make_error(Errc::busy, "key file already exists; not overwritten");
  return made;
}

Result<hal::PathBuffer> default_key_path() noexcept {
  const Result<hal::StateDir> dir = hal::resolve_state_dir(nullptr);
  if (!dir.ok()) return dir.error();
  return hal::join_path(dir.value().path.c_str(), "operator.key");
}

}  // namespace rescue::app::protocol
