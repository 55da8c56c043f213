# `cmake --build <dir> --target static-analysis` runs clang-tidy and cppcheck over the firmware
# (core, hal, ecat, fsm, drivers) using this build's compile_commands.json; any finding fails it.
add_custom_target(static-analysis
  COMMAND ${PROJECT_SOURCE_DIR}/toolchain/static-analysis.sh ${PROJECT_SOURCE_DIR} ${CMAKE_BINARY_DIR}
  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
  USES_TERMINAL
  COMMENT "clang-tidy + cppcheck over firmware sources")
