# aarch64 Linux cross build with Debian's g++-aarch64-linux-gnu. Builds the firmware libraries
# (RESCUE_FIRMWARE_ONLY): tests and the program need target libraries we do not install.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
# Eigen is header-only and architecture independent: the host's package config serves.
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
