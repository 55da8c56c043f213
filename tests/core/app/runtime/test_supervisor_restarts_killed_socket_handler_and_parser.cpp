// Issue 12, task processes: `run` (processes mode, the default) against the in-process simulator;
// SIGKILL the socket handler and the message parser while the robot is in OP. The supervisor logs
// each death, restarts both after their back-off, the EtherCAT handler keeps every healthy joint in
// every frame, and SIGTERM then stops everything cleanly (exit 0) with the restarts counted. The
// restarted socket handler counts on from its predecessor: garbage datagrams sent before and after
// the kill are all counted (and rejected).
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include "tests/support/background_run.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

using std::chrono::milliseconds;

void send_garbage(int port, int count) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<std::uint16_t>(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const char garbage[] = "not a rescue-motion datagram";
  for (int i = 0; i < count; ++i) {
    EXPECT_EQ(::sendto(fd, garbage, sizeof garbage, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to),
              static_cast<ssize_t>(sizeof garbage));
  }
  (void)::close(fd);
}

// The restarted socket handler serves again (its socket bound, its loop running) once ctl gets an
// answer; a loaded host may take longer than any fixed wait to start the new process.
bool robot_answers(int port, const std::string& key) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  const std::string ctl = std::string(RESCUE_BINARY_DIR) + "/rescue-motion ctl --timeout 0.5 --key " + key + " --port " +
                          std::to_string(port) + " status >/dev/null 2>&1";
  while (std::chrono::steady_clock::now() < give_up) {
    if (test::run_command(ctl).exit_status == 0) return true;
    std::this_thread::sleep_for(milliseconds(100));
  }
  return false;
}

TEST(SupervisorRestarts, KilledSocketHandlerAndParserComeBackAndTheHandlerMissesNoPeriod) {
  testing::TempStateDir dir;
  const std::string key = dir.path + "/operator.key";
  ASSERT_EQ(test::run_command(std::string(RESCUE_BINARY_DIR) + "/rescue-motion ctl keygen --key " + key).exit_status, 0);
  const int port = 20000 + 2 * (static_cast<int>(::getpid()) % 10000);  // apart from parallel tests' ports
  test::BackgroundRun run({"run", "--duration", "60", "--initialize", "--state-dir", dir.path, "--control-port",
                           std::to_string(port), "--sensor-port", std::to_string(port + 1)},
                          dir.path + "/run.log");
  ASSERT_TRUE(run.wait_for("operator: initialize: accepted", milliseconds(30000))) << run.output();
  const pid_t socket = run.pid_on_line("supervisor: started socket-handler");
  const pid_t parser = run.pid_on_line("supervisor: started message-parser");
  ASSERT_GT(socket, 0) << run.output();
  ASSERT_GT(parser, 0) << run.output();
  send_garbage(port, 5);
  std::this_thread::sleep_for(milliseconds(300));  // counted and published (every wake-up)
  ASSERT_EQ(::kill(socket, SIGKILL), 0);
  ASSERT_EQ(::kill(parser, SIGKILL), 0);
  EXPECT_TRUE(run.wait_for("supervisor: socket-handler restarted", milliseconds(5000))) << run.output();
  EXPECT_TRUE(run.wait_for("supervisor: message-parser restarted", milliseconds(5000))) << run.output();
  EXPECT_TRUE(robot_answers(port, key)) << run.output();
  send_garbage(port, 3);
  std::this_thread::sleep_for(milliseconds(300));
  ASSERT_EQ(::kill(run.pid(), SIGTERM), 0);
  const int status = run.wait_exit();
  const std::string out = run.output();
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("socket-handler (pid " + std::to_string(socket) + ") killed by signal 9"), std::string::npos) << out;
  EXPECT_NE(out.find("message-parser (pid " + std::to_string(parser) + ") killed by signal 9"), std::string::npos) << out;
  EXPECT_NE(out.find("socket-handler restarts: 1\n"), std::string::npos) << out;
  EXPECT_NE(out.find("message-parser restarts: 1\n"), std::string::npos) << out;
  EXPECT_NE(out.find("ethercat-handler restarts: 0\n"), std::string::npos) << out;
  // Every frame reached every healthy joint: the handler missed no period of the robot's.
  EXPECT_NE(out.find("healthy joints missed 0 cycles"), std::string::npos) << out;
  EXPECT_NE(out.find("stopped by signal 15 while in OP"), std::string::npos) << out;
  // 5 before the kill and 3 after it, all counted; ctl's own requests are the accepted ones.
  const std::size_t line = out.find("rescue-motion run: datagrams ");
  ASSERT_NE(line, std::string::npos) << out;
  const std::string counts = out.substr(line, out.find('\n', line) - line);
  EXPECT_NE(counts.find(", malformed 8,"), std::string::npos) << counts;
}

}  // namespace
}  // namespace rescue::app
