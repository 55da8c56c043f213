// ctl states [SLAVES] INIT|PREOP|SAFEOP|OP (docs/operator.md "AL states", docs/protocol.md "AL
// states"): an AL state for slaves that are out of service, as it travels on the wire
// (StatesPayload, StatesResultPayload) and between the socket handler and the EtherCAT handler
// (StatesLinkRequest, StatesLinkResult: one bounded queue each way in TaskLinks, states_requests /
// states_results). The EtherCAT handler refuses a slave whose joints are in service and hands the
// rest to its master, which writes AL control in the cyclic frame
// (ecat/master/slave_state_service.hpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace rescue::app::protocol {

constexpr std::size_t kStatesSlaves = 23;  // protocol::kMaxSlaves (checked in protocol_messages.hpp)

// The AL states an operator may ask for, by their AL control value.
constexpr bool is_requestable_al_state(std::uint8_t s) noexcept { return s == 1 || s == 2 || s == 4 || s == 8; }
constexpr const char* al_state_name(std::uint8_t s) noexcept {
  switch (s) {
    case 0: return "none";  // no AL status read
    case 1: return "INIT";
    case 2: return "PREOP";
    case 3: return "BOOT";
    case 4: return "SAFEOP";
    case 8: return "OP";
    default: return "?";
  }
}

// states: the slaves (bit p = position p; at least one) and the state (1 INIT, 2 PREOP, 4 SAFEOP, 8 OP).
struct StatesPayload {
  std::uint32_t slaves{0};
  std::uint8_t state{0};
};

// How a states request ended (states_result's status).
enum class StatesStatus : std::uint8_t {
  ok = 0,           // every slave reached the state
  in_service = 1,   // refused: joints of these slaves are in service (in_service names them); nothing written
  not_reached = 2,  // written; some slave did not reach the state (its record says how)
  busy = 3,         // another states request is under way: nothing written; try again
  recovering = 4,   // the master's online recovery is configuring one of them: nothing written; try again
  not_cycling = 5,  // the master is not cycling in OP: nothing written
  no_answer = 6,    // the EtherCAT handler did not answer in time (the socket handler's own limit)
};
constexpr std::uint8_t kStatesStatusLast = 6;

constexpr const char* to_string(StatesStatus s) noexcept {
  switch (s) {
    case StatesStatus::ok: return "ok";
    case StatesStatus::in_service: return "in service";
    case StatesStatus::not_reached: return "not reached";
    case StatesStatus::busy: return "busy";
    case StatesStatus::recovering: return "recovering";
    case StatesStatus::not_cycling: return "not cycling";
    case StatesStatus::no_answer: return "no answer";
  }
  return "?";
}

// One slave's end (ecat::SlaveStateOutcome, pending excluded).
enum class StateOutcome : std::uint8_t { reached = 0, refused = 1, timeout = 2, not_answered = 3 };
constexpr std::uint8_t kStateOutcomeLast = 3;

constexpr const char* to_string(StateOutcome o) noexcept {
  switch (o) {
    case StateOutcome::reached: return "reached";
    case StateOutcome::refused: return "refused";
    case StateOutcome::timeout: return "timeout";
    case StateOutcome::not_answered: return "not answered";
  }
  return "?";
}

struct SlaveStateRecord {
  StateOutcome outcome{StateOutcome::reached};
  std::uint16_t al_status{0};  // AL status register as last read (0: none read)
  std::uint16_t al_code{0};    // AL status code as last read
};

// states_result: the request echoed, the status, the joints in service (in_service), the cyclic
// frames the request ran through, and per slave of the request its record (others zero).
struct StatesResultPayload {
  std::uint64_t request_sequence{0};
  std::uint32_t slaves{0};
  std::uint8_t state{0};
  StatesStatus status{StatesStatus::ok};
  std::uint32_t in_service{0};  // JointMask
  std::uint16_t frames{0};
  std::array<SlaveStateRecord, kStatesSlaves> records{};
};

}  // namespace rescue::app::protocol

namespace rescue::app {

// socket handler -> EtherCAT handler (TaskLinks::states_requests).
struct StatesLinkRequest {
  std::uint32_t id{0};  // the socket handler's, echoed in the result
  protocol::StatesPayload states{};
};

// EtherCAT handler -> socket handler (TaskLinks::states_results); request_sequence is the socket handler's.
struct StatesLinkResult {
  std::uint32_t id{0};
  protocol::StatesResultPayload result{};
};

}  // namespace rescue::app
