// The one RunContext of the process (run_context.hpp says why it is a global).
#include "core/app/runtime/run_context.hpp"

namespace rescue::app::runner {

RunContext g_run;

}  // namespace rescue::app::runner
