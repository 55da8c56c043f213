# One line per fuzz target: rescue_add_fuzzer(fuzz_NAME SOURCES fuzz_NAME.cpp DEPS libs...)
rescue_add_fuzzer(fuzz_nic_input SOURCES fuzz_nic_input.cpp DEPS rescue_app)
