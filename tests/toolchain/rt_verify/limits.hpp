// Stack budget of the rt_verify fixture (read by the checker like hal::kTaskStackPrefaultBytes).
#pragma once
#include <cstddef>
inline constexpr std::size_t kFixtureStackBytes = std::size_t{64} * 1024;
