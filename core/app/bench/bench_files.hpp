// What the benches that write files and run Debian's python3 share (bench fig4, bench wcet): their
// script found beside the program, a file written into their checked --out directory, the script run.
#pragma once

#include <cstddef>
#include <cstdio>

#include "hal/files/trusted_file.hpp"

namespace rescue::app {

// A script of the program: `option` (the bench's --...-script) when given, else beside the program:
// the package's <prefix>/share/rescue-motion/`installed` (/usr/bin/rescue-motion ->
// /usr/share/rescue-motion/), else the source tree's `in_source` (a path from the source tree's top:
// build/PRESET/rescue-motion -> ../../). False when none is readable; `looked` lists where it looked.
bool find_script(const char* option, const char* installed, const char* in_source, char* out, std::size_t size, char* looked,
                 std::size_t looked_size) noexcept;

// `name` in the checked --out directory `dir` (hal/files/trusted_file.hpp: never through a link,
// never a FIFO or another user's file), written by `write(file, context)`; its path into `path`.
// Errors are printed with `bench`'s name.
bool write_file(const char* bench, const hal::OpenFile& dir, const char* dir_path, const char* name,
                bool (*write)(std::FILE*, const void*), const void* context, char* path, std::size_t path_size) noexcept;

// Runs /usr/bin/python3 (Debian's, with python3-scipy and python3-matplotlib) with `argv` (argv[0]
// the script, null-terminated); its standard output into `stdout_path` when not null. Returns its
// exit status, -1 when it could not be started or was killed.
int run_python(char* const* argv, const char* stdout_path) noexcept;
// Whether /usr/bin/python3 can run `import MODULES` (e.g. "matplotlib", "scipy").
bool python_imports(const char* modules) noexcept;

}  // namespace rescue::app
