// A socket handler on 127.0.0.1 (ephemeral control and sensor ports), its replay window in epoch
// kEpoch, a manual wall clock, and a client socket to talk to it: the rig of the socket handler's
// unit tests. for_robot() addresses a message as a station that asked the epoch would.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>

#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/replay_window.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "hal/net/udp_socket.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::test {
namespace protocol = app::protocol;

struct LoopbackSocketHandler {
  static constexpr std::int64_t kNow = 1'700'000'000'000'000'000LL;  // the wall clock's reading
  static constexpr std::uint64_t kEpoch = 0x0123456789ABCDEFULL;

  LoopbackSocketHandler(const app::SocketHandlerPorts& ports, const protocol::Key& k)
      : wall(kNow), key(k), handler(ports, key, window, wall) {
    window.begin_epoch(kEpoch);
    app::SocketHandlerOptions options;
    options.listen = "127.0.0.1";
    options.control_port = 0;
    options.sensor_port = 0;
    EXPECT_TRUE(handler.open(options).ok());
    EXPECT_TRUE(client.open("127.0.0.1", 0).ok());
    loopback = hal::parse_ipv4("127.0.0.1").value();
  }

  // `m` for this robot in its current epoch.
  protocol::Message for_robot(protocol::Message m) const {
    m.header.version = protocol::kVersion;
    m.header.robot = handler.robot_id();
    m.header.epoch = window.epoch();
    return m;
  }

  protocol::ReplayWindow window;
  hal::ManualWallClock wall;
  protocol::Key key;  // before the handler, which copies it
  app::SocketHandler handler;
  hal::UdpSocket client;
  std::uint32_t loopback{0};
};

}  // namespace rescue::test
