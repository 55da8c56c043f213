// One bring-up report, the same wherever a bring-up fails (`run`, `run --check`, `bench master`, the
// log): the step that failed and why, with every number filled in; the difference between the network
// found and the plan (each wrong device with what it is and what was expected, each missing slave,
// each extra one); the slave that refused a state with its AL status and AL status code by name; a
// refused start-up SDO with its abort code by name; the link's counters. Never truncated: each line is
// printed whole.
#pragma once

#include <cstdio>

#include "ecat/master/master.hpp"

namespace rescue::ecat {

// Prints the report of the last bring_up() of `master`: the first line "bring-up failed at STEP: WHY"
// after `first_prefix`, every other line after `prefix` (e.g. "rescue-motion run: "). Nothing when
// the bring-up succeeded.
void print_bring_up_failure(std::FILE* out, const char* first_prefix, const char* prefix, Master& master) noexcept;

}  // namespace rescue::ecat
