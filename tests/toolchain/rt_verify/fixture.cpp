// Fixture of tests/toolchain/test_rt_verify_catches_blocking_calls_and_deep_stacks.py: a miniature
// "handler" whose period function reaches a virtual call, a function pointer and (when
// RT_VERIFY_DELIBERATE_MALLOC is defined) a malloc, as a handler path of the firmware could.
#include <cstdlib>
#include <cstring>

namespace fixture {

void* volatile g_kept = nullptr;

struct Port {
  virtual ~Port() = default;
  virtual int send(const char* data, int size) noexcept = 0;
};

struct QueuePort final : Port {
  char slots[64]{};
  int send(const char* data, int size) noexcept override {
    std::memcpy(slots, data, static_cast<std::size_t>(size) < sizeof slots ? static_cast<std::size_t>(size) : sizeof slots);
#ifdef RT_VERIFY_DELIBERATE_MALLOC
    g_kept = std::malloc(static_cast<std::size_t>(size));  // the deliberate allocation (kept: not optimised away)
#endif
    return size;
  }
};

using HookFn = int (*)(int) noexcept;
int hook_double(int x) noexcept { return 2 * x; }
HookFn g_hook = hook_double;

__attribute__((noinline)) int fill(char* out, int n) noexcept {
  char scratch[2048];
  for (int i = 0; i < n && i < 2048; ++i) scratch[i] = static_cast<char>(i);
  std::memcpy(out, scratch, 16);
  return scratch[n % 2048];
}

#ifdef RT_VERIFY_RECURSION
__attribute__((noinline)) int walk(int n) noexcept { return n <= 1 ? n : walk(n - 1) + walk(n - 2); }
#endif

__attribute__((noinline)) int cycle(Port& port, int n) noexcept {
  char frame[32];
  int r = fill(frame, n);
  r += port.send(frame, 16);
  r += g_hook(n);
#ifdef RT_VERIFY_RECURSION
  r += walk(n);
#endif
  return r;
}

}  // namespace fixture

fixture::QueuePort g_port;
long fixture_main(long n) noexcept { return fixture::cycle(g_port, static_cast<int>(n)); }
