#include "core/app/bench/bench_files.hpp"

#include <fcntl.h>
#include <sched.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>

extern char** environ;  // NOLINT(readability-redundant-declaration): posix_spawn passes it on

namespace rescue::app {

bool find_script(const char* option, const char* installed, const char* in_source, char* out, std::size_t size, char* looked,
                 std::size_t looked_size) noexcept {
  looked[0] = '\0';
  if (option != nullptr) {
    (void)std::snprintf(out, size, "%s", option);
    (void)std::snprintf(looked, looked_size, "%s (--plot-script)", option);
    return ::access(option, R_OK) == 0;
  }
  char exe[512];
  const ssize_t n = ::readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) return false;
  exe[n] = '\0';
  char* slash = std::strrchr(exe, '/');
  if (slash == nullptr) return false;
  *slash = '\0';  // the program's directory
  char installed_path[256];
  char source_path[256];
  (void)std::snprintf(installed_path, sizeof installed_path, "../share/rescue-motion/%s", installed);
  (void)std::snprintf(source_path, sizeof source_path, "../../%s", in_source);
  const char* const candidates[] = {installed_path, source_path};
  std::size_t used = 0;
  for (const char* relative : candidates) {
    (void)std::snprintf(out, size, "%s/%s", exe, relative);
    const int w = std::snprintf(looked + used, looked_size - used, "%s%s", used == 0 ? "" : ", ", out);
    if (w > 0 && used + static_cast<std::size_t>(w) < looked_size) used += static_cast<std::size_t>(w);
    if (::access(out, R_OK) == 0) return true;
  }
  out[0] = '\0';
  return false;
}

bool write_file(const char* bench, const hal::OpenFile& dir, const char* dir_path, const char* name,
                bool (*write)(std::FILE*, const void*), const void* context, char* path, std::size_t path_size) noexcept {
  const int n = std::snprintf(path, path_size, "%s/%s", dir_path, name);
  if (n < 0 || static_cast<std::size_t>(n) >= path_size) return false;
  hal::FileProblem why;
  Result<hal::OpenFile> file = hal::create_regular_in(dir, dir_path, name, 0644, why);
  if (!file.ok()) {
    (void)std::fprintf(stderr, "rescue-motion bench: %s: %s\n", bench, why.c_str());
    return false;
  }
  std::FILE* out = ::fdopen(file.value().fd(), "w");
  if (out == nullptr) return false;
  (void)file.value().release();  // fclose closes it
  const bool written = write(out, context);
  return std::fclose(out) == 0 && written;
}

int run_python(char* const* argv, const char* stdout_path) noexcept {
  char python[] = "/usr/bin/python3";
  char* full[16] = {python};
  std::size_t n = 1;
  for (; argv[n - 1] != nullptr && n < 15; ++n) full[n] = argv[n - 1];
  full[n] = nullptr;
  posix_spawn_file_actions_t actions;
  if (posix_spawn_file_actions_init(&actions) != 0) return -1;
  if (stdout_path != nullptr &&
      posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, stdout_path, O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW, 0644) != 0) {
    (void)posix_spawn_file_actions_destroy(&actions);
    return -1;
  }
  // The script runs at normal scheduling whatever the bench's own thread runs at (bench wcet measures
  // at SCHED_FIFO): minutes of statistics must not hold a CPU from everything else.
  posix_spawnattr_t attributes;
  if (posix_spawnattr_init(&attributes) != 0) {
    (void)posix_spawn_file_actions_destroy(&actions);
    return -1;
  }
  sched_param normal{};
  normal.sched_priority = 0;
  (void)posix_spawnattr_setschedpolicy(&attributes, SCHED_OTHER);
  (void)posix_spawnattr_setschedparam(&attributes, &normal);
  (void)posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSCHEDULER);
  pid_t pid = -1;
  const int spawned = posix_spawn(&pid, python, &actions, &attributes, full, environ);
  (void)posix_spawn_file_actions_destroy(&actions);
  (void)posix_spawnattr_destroy(&attributes);
  if (spawned != 0) return -1;
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool python_imports(const char* modules) noexcept {
  char dash_c[] = "-c";
  char code[128];
  (void)std::snprintf(code, sizeof code, "import %s", modules);
  char* argv[] = {dash_c, code, nullptr};
  if (::access("/usr/bin/python3", X_OK) != 0) return false;
  return run_python(argv, nullptr) == 0;
}

}  // namespace rescue::app
