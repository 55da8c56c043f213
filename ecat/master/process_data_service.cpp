// The branches' LRWs: outputs out, inputs in.
#include "ecat/master/process_data_service.hpp"

#include <cstring>

namespace rescue::ecat {

void ProcessDataService::silence_outputs_of_out_slaves() noexcept {
  const SlaveMask silent = ~ctx_.operated() | ctx_.monitor.out_of_exchange();
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((silent & slave_bit(p)) == 0 || ctx_.plan[p].output_bytes == 0) continue;
    std::memset(ctx_.image.data() + ctx_.layout.slaves[p].output_offset, 0, ctx_.plan[p].output_bytes);
  }
}

void ProcessDataService::add_datagrams(CycleFrame& frame) noexcept {
  silence_outputs_of_out_slaves();
  branch_wkc_.fill(0);
  for (std::size_t b = 0; b < kMaxBranches; ++b) {
    const BranchLayout& branch = ctx_.layout.branches[b];
    if (branch.length == 0) continue;
    (void)frame.add(*this, static_cast<std::uint8_t>(b), Command::LRW, branch.logical_start, branch.length,
                    ConstByteSpan(ctx_.image.data() + branch.logical_start, branch.length));
  }
}

void ProcessDataService::on_answer(std::uint8_t b, const DatagramView& d) noexcept {
  const BranchLayout& branch = ctx_.layout.branches[b];
  branch_wkc_[b] = d.wkc();
  // Inputs only: the outputs part comes back as sent. Slaves the frame did not reach leave their
  // bytes as they were, so stale values stay and `valid` says so.
  std::memcpy(ctx_.image.data() + branch.logical_start + branch.output_length, d.data().data() + branch.output_length,
              static_cast<std::size_t>(branch.length - branch.output_length));
}

}  // namespace rescue::ecat
