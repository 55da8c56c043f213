// The register blocks of a slave's configuration, encoded byte by byte (slave_config.hpp).
#include "ecat/master/slave_setup.hpp"

#include <cstring>

#include "ecat/codec/registers.hpp"
#include "ecat/master/slave_config.hpp"

namespace rescue::ecat {

void fill_mailbox_sms(const SlaveSetup& setup, std::uint8_t* out) noexcept {
  const SyncManagerEntry sm0 = sync_manager_entry(setup.sm[0].start, setup.sm[0].length, setup.sm[0].control);
  const SyncManagerEntry sm1 = sync_manager_entry(setup.sm[1].start, setup.sm[1].length, setup.sm[1].control);
  std::memcpy(out, sm0.data(), sm0.size());
  std::memcpy(out + sm0.size(), sm1.data(), sm1.size());
}

void fill_process_data_sms(const SlaveSetup& setup, const SlavePlan& plan, std::uint8_t* out) noexcept {
  const SyncManagerSetup& o = setup.sm[2];
  const SyncManagerSetup& i = setup.sm[3];
  const SyncManagerEntry sm2 = sync_manager_entry(o.start, plan.output_bytes, o.control != 0 ? o.control : kSmControlOutputs);
  const SyncManagerEntry sm3 = sync_manager_entry(i.start, plan.input_bytes, i.control != 0 ? i.control : kSmControlInputs);
  std::memcpy(out, sm2.data(), sm2.size());
  std::memcpy(out + sm2.size(), sm3.data(), sm3.size());
}

void fill_fmmus(const SlaveSetup& setup, const SlavePlan& plan, const SlaveImage& image, std::uint8_t* out) noexcept {
  const FmmuEntry outputs = fmmu_entry(image.output_offset, plan.output_bytes, setup.sm[2].start, reg::kFmmuTypeWrite);
  const FmmuEntry inputs = fmmu_entry(image.input_offset, plan.input_bytes, setup.sm[3].start, reg::kFmmuTypeRead);
  std::memcpy(out, outputs.data(), outputs.size());
  std::memcpy(out + outputs.size(), inputs.data(), inputs.size());
}

}  // namespace rescue::ecat
