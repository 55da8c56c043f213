# One line per fuzz target: rescue_add_fuzzer(fuzz_NAME SOURCES fuzz_NAME.cpp DEPS libs...)
