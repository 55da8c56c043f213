// ctl's queries about the robot as a whole: status, master, tasks, version, owner (ctl_robot_queries.cpp).
// Each prints its answer as a table, or with --json as one object.
#pragma once

#include "core/app/links/protocol_messages.hpp"

namespace rescue::app {

void print_status(const protocol::Message& m, bool json) noexcept;
void print_master(const protocol::Message& m, bool json) noexcept;
void print_tasks(const protocol::Message& m, bool json) noexcept;
void print_version(const protocol::Message& m, bool json) noexcept;
void print_owner(const protocol::Message& m, bool json) noexcept;

}  // namespace rescue::app
