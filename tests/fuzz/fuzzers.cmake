# One line per fuzz target: rescue_add_fuzzer(fuzz_NAME SOURCES fuzz_NAME.cpp DEPS libs...)
rescue_add_fuzzer(fuzz_error_joints_file SOURCES fuzz_error_joints_file.cpp DEPS rescue_core)
