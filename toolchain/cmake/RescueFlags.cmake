# Compiler flags. Firmware code (core, hal, ecat, fsm, drivers) links rescue_firmware_flags:
# no exceptions, no RTTI, warnings are errors. Tests and benchmarks link rescue_test_flags.
add_library(rescue_firmware_flags INTERFACE)
target_compile_options(rescue_firmware_flags INTERFACE
  -fno-exceptions -fno-rtti
  -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow -Wold-style-cast
  -Wcast-align -Wnon-virtual-dtor -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion
  -Wformat=2 -Wimplicit-fallthrough -Werror)
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  target_compile_options(rescue_firmware_flags INTERFACE -Wduplicated-cond -Wlogical-op)
endif()

add_library(rescue_test_flags INTERFACE)
target_compile_options(rescue_test_flags INTERFACE -Wall -Wextra -Wshadow -Werror)
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  # GCC 12 at -O1 and above (asan/tsan presets) reports -Wmaybe-uninitialized inside libstdc++'s
  # std::regex / std::function, which tests instantiate: a false positive in system headers.
  # Firmware keeps the warning.
  target_compile_options(rescue_test_flags INTERFACE -Wno-maybe-uninitialized)
endif()

# Fuzz builds: every library is coverage-instrumented (fuzzer-no-link) and sanitized, so libFuzzer
# sees inside the decoders, not only inside the fuzz target's own file.
if(RESCUE_BUILD_FUZZERS)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()

if(RESCUE_SANITIZE)
  add_compile_options(-fsanitize=${RESCUE_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${RESCUE_SANITIZE})
  # UBSan's vptr check reads type_info, which firmware built with -fno-rtti does not emit: a test
  # (built with RTTI) using a firmware class with virtual functions would not link.
  if(RESCUE_SANITIZE MATCHES "undefined")
    add_compile_options(-fno-sanitize=vptr)
  endif()
endif()

# Helper: declare a firmware library of one folder.
function(rescue_firmware_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  if(ARG_SOURCES)
    add_library(${name} STATIC ${ARG_SOURCES})
    target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
    target_link_libraries(${name} PUBLIC ${ARG_DEPS} PRIVATE rescue_firmware_flags)
  else()
    add_library(${name} INTERFACE)
    target_include_directories(${name} INTERFACE ${PROJECT_SOURCE_DIR})
    target_link_libraries(${name} INTERFACE ${ARG_DEPS})
  endif()
endfunction()
