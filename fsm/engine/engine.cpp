#include "fsm/engine/engine.hpp"

namespace rescue::fsm {

const char* to_string(Refusal refusal) noexcept {
  switch (refusal) {
    case Refusal::none: return "none";
    case Refusal::not_in_table: return "not in table";
    case Refusal::guard_failed: return "guard failed";
  }
  return "unknown";
}

}  // namespace rescue::fsm
