# Motion PC: Intel Core i7-3517UE (Ivy Bridge), x86-64 Linux with PREEMPT_RT or Xenomai.
# The host compiler targets it directly; only the instruction set and optimisation change.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(CMAKE_CXX_COMPILER g++)
set(CMAKE_CXX_FLAGS_INIT "-march=ivybridge -mtune=ivybridge")
set(CMAKE_CXX_FLAGS_RELEASE_INIT "-O3 -DNDEBUG")
