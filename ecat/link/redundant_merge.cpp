#include "ecat/link/redundant_merge.hpp"

#include <cstring>

#include "core/base/endian.hpp"

namespace rescue::ecat {
namespace {

using MutableFrameView = BasicFrameView<std::uint8_t>;

// The copy carries the datagrams sent: same count, index, length, and command (or NOP in its place).
bool carries(const FrameView& sent, const FrameView& copy) noexcept {
  if (sent.datagram_count() != copy.datagram_count()) return false;
  auto s = sent.begin();
  auto c = copy.begin();
  for (std::size_t i = 0; i < sent.datagram_count(); ++i, ++s, ++c) {
    const DatagramView ds = *s;
    const DatagramView dc = *c;
    if (ds.length() != dc.length() || ds.index() != dc.index()) return false;
    if (dc.command() == ds.command() || dc.command() == Command::NOP) continue;
    if (is_ring_side_time_write(ds.command(), ds.address()) && dc.command() == Command::FPWR) continue;
    if (!is_island_time_read(ds.command(), ds.address()) || dc.command() != Command::FRMW) return false;
  }
  return true;
}

}  // namespace

Result<std::size_t> make_ring_copy(ConstByteSpan main, ByteSpan out) noexcept {
  if (main.size() > out.size() || main.size() <= kSourceMacTailOffset) {
    return make_error(Errc::invalid_argument, "ring copy does not fit");
  }
  std::memcpy(out.data(), main.data(), main.size());
  const Result<MutableFrameView> view = MutableFrameView::parse(ByteSpan(out.data(), main.size()));
  if (!view.ok()) return view.error();
  out[kSourceMacTailOffset] = kRingCopyMacTail;
  for (const MutableDatagramView d : view.value()) {
    const Command command = d.command();
    if (main_port_only(command)) d.raw()[0] = static_cast<std::uint8_t>(Command::NOP);
    if (is_ring_side_time_write(command, d.address())) d.raw()[0] = static_cast<std::uint8_t>(Command::FPWR);
    if (is_island_time_read(command, d.address())) {
      d.raw()[0] = static_cast<std::uint8_t>(Command::FRMW);
      store_le16(d.raw() + 4, reg::kDcSystemTime);  // the ADO: command, index, ADP before it
    }
  }
  return main.size();
}

bool is_ring_copy(ConstByteSpan frame) noexcept {
  return frame.size() > kSourceMacTailOffset && frame[kSourceMacTailOffset] == kRingCopyMacTail;
}

Result<FrameView> merge_copies(const FrameView& sent, const FrameView* main_copy, const FrameView* ring_copy,
                               ByteSpan out, CopyCounters& counters) noexcept {
  counters = CopyCounters{};
  if ((main_copy != nullptr && !carries(sent, *main_copy)) || (ring_copy != nullptr && !carries(sent, *ring_copy))) {
    return make_error(Errc::malformed, "returned copy differs from the frame sent");
  }
  const ConstByteSpan sent_bytes = sent.bytes();
  if (sent_bytes.size() > out.size()) return make_error(Errc::invalid_argument, "merged frame does not fit");
  std::memcpy(out.data(), sent_bytes.data(), sent_bytes.size());
  const Result<MutableFrameView> merged = MutableFrameView::parse(ByteSpan(out.data(), sent_bytes.size()));
  if (!merged.ok()) return merged.error();
  counters.datagrams = sent.datagram_count();

  auto s = sent.begin();
  auto m = merged.value().begin();
  // Views of the copies' datagrams, walked in step with the sent frame (end() when absent).
  auto a = main_copy != nullptr ? main_copy->begin() : sent.end();
  auto b = ring_copy != nullptr ? ring_copy->begin() : sent.end();
  for (std::size_t i = 0; i < sent.datagram_count(); ++i, ++s, ++m) {
    const DatagramView ds = *s;
    const MutableDatagramView dm = *m;
    std::uint32_t wkc = 0;
    std::uint8_t* data = dm.data().data();
    const std::uint8_t* sent_data = ds.data().data();
    const std::size_t length = ds.length();
    if (main_copy != nullptr) {
      const DatagramView da = *a;
      std::memcpy(data, da.data().data(), length);
      counters.main[i] = da.wkc();
      wkc += da.wkc();
      ++a;
    }
    if (ring_copy != nullptr) {
      const DatagramView db = *b;
      const std::uint8_t* ring_data = db.data().data();
      for (std::size_t k = 0; k < length; ++k) {
        if (ring_data[k] != sent_data[k]) data[k] = ring_data[k];
      }
      counters.ring[i] = db.wkc();
      wkc += db.wkc();
      ++b;
    }
    dm.set_wkc(static_cast<std::uint16_t>(wkc > 0xFFFFU ? 0xFFFFU : wkc));
  }
  return FrameView::parse(ConstByteSpan(out.data(), sent_bytes.size()));
}

Result<std::size_t> make_repeat(ConstByteSpan sent, ByteSpan out, std::uint8_t index) noexcept {
  if (sent.size() > out.size()) return make_error(Errc::invalid_argument, "repeat does not fit");
  std::memcpy(out.data(), sent.data(), sent.size());
  const Result<MutableFrameView> view = MutableFrameView::parse(ByteSpan(out.data(), sent.size()));
  if (!view.ok()) return view.error();
  bool any = false;
  for (const MutableDatagramView d : view.value()) {
    if (repeatable(d.command())) {
      any = true;
    } else {
      d.raw()[0] = static_cast<std::uint8_t>(Command::NOP);
    }
    d.raw()[1] = index;
  }
  return any ? sent.size() : 0;
}

Status take_repeated(const FrameView& repeat, const CopyCounters& repeat_counters, ByteSpan first,
                     CopyCounters& first_counters) noexcept {
  const Result<MutableFrameView> merged = MutableFrameView::parse(first);
  if (!merged.ok()) return merged.error();
  if (merged.value().datagram_count() != repeat.datagram_count() || repeat_counters.datagrams != repeat.datagram_count()) {
    return make_error(Errc::malformed, "the repeat differs from the frame sent");
  }
  auto c = repeat.begin();
  for (auto f = merged.value().begin(); f != merged.value().end(); ++c, ++f) {  // checked whole before any change
    const DatagramView dc = *c;
    if (dc.command() != Command::NOP && (dc.length() != (*f).length() || dc.command() != (*f).command())) {
      return make_error(Errc::malformed, "the repeat differs from the frame sent");
    }
  }
  auto r = repeat.begin();
  auto f = merged.value().begin();
  for (std::size_t i = 0; i < repeat.datagram_count(); ++i, ++r, ++f) {
    const DatagramView dr = *r;
    const MutableDatagramView df = *f;
    if (dr.command() == Command::NOP) continue;
    std::memcpy(df.data().data(), dr.data().data(), dr.length());
    df.set_wkc(dr.wkc());
    first_counters.main[i] = repeat_counters.main[i];
    first_counters.ring[i] = repeat_counters.ring[i];
  }
  return Status::success();
}

}  // namespace rescue::ecat
