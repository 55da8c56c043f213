#include "ecat/mailbox/mailbox_client.hpp"

#include <algorithm>
#include <cstring>

#include "core/base/endian.hpp"
#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/coe_information.hpp"
#include "ecat/mailbox/mailbox.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kSm1Status = reg::sync_manager(1) + reg::kSmStatus;
constexpr std::uint16_t kSm1Activate = reg::sync_manager(1) + reg::kSmActivate;
constexpr std::uint8_t kRepeatAck = 0x02;  // PDI control [1]: the slave's answer to the repeat bit

}  // namespace

const char* to_string(SdoOutcome outcome) noexcept {
  switch (outcome) {
    case SdoOutcome::ok: return "ok";
    case SdoOutcome::aborted: return "aborted";
    case SdoOutcome::mailbox_error: return "mailbox error";
    case SdoOutcome::timeout: return "timeout";
    case SdoOutcome::no_mailbox: return "no mailbox";
    case SdoOutcome::bad_response: return "bad response";
    case SdoOutcome::too_long: return "value too long";
  }
  return "?";
}

SdoRequest sdo_download(std::uint8_t position, std::uint16_t index, std::uint8_t subindex, std::uint32_t value,
                        std::uint8_t size, std::uint32_t tag) noexcept {
  SdoRequest r;
  r.position = position;
  r.direction = SdoDirection::download;
  r.index = index;
  r.subindex = subindex;
  r.size = size == 0 || size > 4 ? 4 : size;
  store_le32(r.data.data(), value);
  r.tag = tag;
  return r;
}

SdoRequest sdo_download_bytes(std::uint8_t position, std::uint16_t index, std::uint8_t subindex, ConstByteSpan bytes,
                              std::uint32_t tag) noexcept {
  SdoRequest r;
  r.position = position;
  r.direction = SdoDirection::download;
  r.index = index;
  r.subindex = subindex;
  const std::size_t n = bytes.size() < kMaxSdoData ? bytes.size() : kMaxSdoData;
  std::copy_n(bytes.data(), n, r.data.data());
  r.size = static_cast<std::uint16_t>(n);
  r.tag = tag;
  return r;
}

SdoRequest sdo_upload(std::uint8_t position, std::uint16_t index, std::uint8_t subindex, std::uint32_t tag) noexcept {
  SdoRequest r;
  r.position = position;
  r.direction = SdoDirection::upload;
  r.index = index;
  r.subindex = subindex;
  r.tag = tag;
  return r;
}

SdoRequest sdo_information(std::uint8_t position, std::uint8_t opcode, std::uint16_t index, std::uint8_t subindex,
                           std::uint16_t skip, std::uint32_t tag) noexcept {
  SdoRequest r;
  r.position = position;
  r.direction = SdoDirection::information;
  r.info_opcode = opcode;
  r.index = index;
  r.subindex = subindex;
  r.info_skip = skip;
  r.tag = tag;
  return r;
}

std::uint32_t sdo_value(const SdoCompletion& c) noexcept {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < c.size && i < 4; ++i) v |= static_cast<std::uint32_t>(c.data[i]) << (8U * i);
  return v;
}

void MailboxClient::configure(std::size_t position, std::uint16_t out_start, std::uint16_t out_size,
                              std::uint16_t in_start, std::uint16_t in_size) noexcept {
  if (position >= kMaxSlaves) return;
  Box& box = boxes_[position];
  box.out_start = out_start;
  box.out_size = out_size;
  box.in_start = in_start;
  box.in_size = in_size;
  // The SyncManager was written anew (activate = enable, repeat 0) after the slave went through
  // INIT: the messages it sends count anew.
  box.in_counter = 0;
  box.repeat = 0;
  box.present = out_size >= mbx::kHeaderSize + coe::kSdoInitiateSize && out_size <= kMaxMailboxSize &&
                in_size >= mbx::kHeaderSize + coe::kSdoInitiateSize && in_size <= kMaxMailboxSize;
}

bool MailboxClient::submit(const SdoRequest& request) noexcept {
  if (!queue_.push(request)) return false;
  may_start_ = true;
  return true;
}

bool MailboxClient::pop_completion(SdoCompletion& out) noexcept { return done_.pop(out); }

void MailboxClient::complete(Channel& c, SdoOutcome outcome) noexcept {
  c.current.outcome = outcome;
  c.phase = Phase::none;
  if (c.current.request.position < kMaxSlaves) busy_ &= ~slave_bit(c.current.request.position);
  may_start_ = true;
  deliver(c.current);
}

void MailboxClient::deliver(const SdoCompletion& done) noexcept {
  if ((done.request.tag & kMasterTagBit) != 0) {
    (void)master_done_.push_overwrite(done);
  } else if ((done.request.tag & kOperatorTagBit) != 0) {
    (void)operator_done_.push_overwrite(done);
  } else {
    (void)done_.push_overwrite(done);
  }
}

void MailboxClient::start_transfers(hal::Nanoseconds now) noexcept {
  // Each queued request whose slave is free starts; the others go back in their order, and a
  // slave's later request never overtakes its earlier one (`held`).
  if (!may_start_) return;
  may_start_ = false;
  SlaveMask held = 0;
  const std::size_t queued = queue_.size();
  for (std::size_t n = 0; n < queued; ++n) {
    SdoRequest request;
    if (!queue_.pop(request)) break;
    const std::size_t p = request.position;
    if (!has_mailbox(p)) {
      SdoCompletion none;  // completes at once: no channel needed
      none.request = request;
      none.outcome = SdoOutcome::no_mailbox;
      deliver(none);
      continue;
    }
    if ((busy_ & slave_bit(p)) != 0 || (held & slave_bit(p)) != 0) {
      held |= slave_bit(p);
      (void)queue_.push(request);  // the place it was taken from is free
      continue;
    }
    Channel& c = channels_[p];
    c.current = SdoCompletion{};
    c.current.request = request;
    start(c, now);
  }
}

void MailboxClient::start(Channel& c, hal::Nanoseconds now) noexcept {
  busy_ |= slave_bit(c.current.request.position);
  c.offset = 0;
  c.expected = 0;
  c.toggle = false;
  if (!encode_step(c, Step::initiate, now)) complete(c, SdoOutcome::bad_response);
}

std::size_t MailboxClient::download_room(const Channel& c, bool initiate) const noexcept {
  const Box& box = boxes_[c.current.request.position];
  const std::size_t overhead = mbx::kHeaderSize + coe::kCoeHeaderSize + (initiate ? coe::kSdoHeaderSize : coe::kSegmentHeaderSize);
  return box.out_size > overhead ? box.out_size - overhead : 0;
}

bool MailboxClient::encode_step(Channel& c, Step step, hal::Nanoseconds now) noexcept {
  const SdoRequest& r = c.current.request;
  Box& box = boxes_[r.position];
  box.counter = mbx::next_counter(box.counter);
  mbx::Header header;
  header.counter = box.counter;
  coe::Sdo sdo;
  const std::size_t size = r.size < kMaxSdoData ? r.size : kMaxSdoData;
  switch (step) {
    case Step::initiate:
      if (r.direction != SdoDirection::download) {  // information: encoded below, on its own
        sdo = coe::upload_request(r.index, r.subindex, r.complete_access);
      } else if (size <= coe::kMaxExpeditedSize) {
        sdo = coe::download_request(r.index, r.subindex, ConstByteSpan(r.data.data(), size));
      } else {
        // Normal transfer: the complete size, and what fits SM0 now; segments carry the rest.
        const std::size_t room = download_room(c, true);
        c.chunk = size < room ? size : room;
        sdo = coe::download_request(r.index, r.subindex, ConstByteSpan(r.data.data(), c.chunk));
        sdo.expedited = false;
        sdo.size = static_cast<std::uint32_t>(size);
      }
      break;
    case Step::upload_segment:
      sdo.kind = coe::SdoKind::upload_segment_request;
      sdo.toggle = c.toggle;
      break;
    case Step::download_segment: {
      const std::size_t room = download_room(c, false);
      const std::size_t left = size > c.offset ? size - c.offset : 0;
      c.chunk = left < room ? left : room;
      sdo.kind = coe::SdoKind::download_segment_request;
      sdo.toggle = c.toggle;
      sdo.last_segment = c.offset + c.chunk >= size;
      sdo.data = ConstByteSpan(r.data.data() + c.offset, c.chunk);
      break;
    }
    case Step::abort: sdo = coe::abort(r.index, r.subindex, c.abort_code_out); break;
  }
  std::memset(c.message.data(), 0, box.out_size);
  const ByteSpan out(c.message.data(), box.out_size);
  const Result<std::size_t> encoded =
      r.direction == SdoDirection::information && step == Step::initiate
          ? coe::info::encode_request(out, header, r.info_opcode, r.index, r.subindex)
          : coe::encode(out, header, sdo);
  if (!encoded.ok()) return false;
  c.step = step;
  c.phase = Phase::send;
  c.deadline = now + response_timeout_;
  c.late_polls = 0;
  return true;
}

void MailboxClient::abort_transfer(Channel& c, SdoOutcome outcome, std::uint32_t code) noexcept {
  // Tell the slave the transfer is over (it may hold a segmented transfer open), then complete.
  c.abort_outcome = outcome;
  c.abort_code_out = code;
  if (!encode_step(c, Step::abort, now_)) complete(c, outcome);
}

std::size_t MailboxClient::add_channel_datagrams(Channel& c, FrameBuilder& frame, std::uint8_t index) noexcept {
  const std::size_t p = c.current.request.position;
  const Box& box = boxes_[p];
  const std::uint16_t station = plan_[p].station_address;
  std::size_t n = 0;
  if (c.phase == Phase::send) {
    if (frame.remaining_data_capacity() < box.out_size) return 0;
    if (frame.add(Command::FPWR, index, make_address(station, box.out_start), box.out_size,
                  ConstByteSpan(c.message.data(), box.out_size)).ok()) {
      n = 1;
    }
  } else if (c.phase == Phase::repeat) {
    // SM1's registers read, and the repeat bit written only after a read found SM1 enabled where
    // this mailbox has it: the activate byte holds the enable bit too, and a slave that restarted
    // meanwhile (its mailbox not yet configured again) must not get an SM1 enabled by this write.
    if (c.repeat_write) {
      const auto activate = static_cast<std::uint8_t>(reg::kSmEnable | box.repeat);
      if (frame.add(Command::FPWR, index, make_address(station, kSm1Activate), 1, ConstByteSpan(&activate, 1)).ok()) n = 1;
    } else if (frame.add(Command::FPRD, index, make_address(station, reg::sync_manager(1)), reg::kSyncManagerSize).ok()) {
      n = 1;
    }
  } else {
    if (frame.remaining_data_capacity() < box.in_size + 1 + kDatagramOverhead) return 0;
    if (frame.add(Command::FPRD, index, make_address(station, kSm1Status), 1).ok() &&
        frame.add(Command::FPRD, index, make_address(station, box.in_start), box.in_size).ok()) {
      n = 2;
    }
  }
  c.added = static_cast<std::uint8_t>(n);
  if (n > 0) ++c.current.exchanges;
  return n;
}

std::size_t MailboxClient::add_datagrams(FrameBuilder& frame, std::uint8_t index, hal::Nanoseconds now,
                                         std::size_t max_slaves) noexcept {
  now_ = now;
  added_ = 0;
  moved_ = false;
  for (Channel& c : channels_) {
    c.added = 0;
    c.sent_this_exchange = false;
    c.in_full = false;
    c.answered = false;
    c.repeat_acked = false;
  }
  start_transfers(now);
  if (busy_ == 0) return 0;
  // The slaves in turn from next_turn_, so that a full frame never starves the last ones.
  std::size_t slaves = 0;
  for (std::size_t k = 0; k < kMaxSlaves && slaves < max_slaves; ++k) {
    const std::size_t p = (next_turn_ + k) % kMaxSlaves;
    if ((busy_ & slave_bit(p)) == 0) continue;
    const std::size_t n = add_channel_datagrams(channels_[p], frame, index);
    if (n == 0) break;  // the frame is full
    for (std::size_t i = 0; i < n; ++i) exchange_slave_[added_++] = static_cast<std::uint8_t>(p);
    ++slaves;
  }
  next_turn_ = (next_turn_ + 1) % kMaxSlaves;
  return added_;
}

void MailboxClient::on_datagram(std::size_t k, const DatagramView& d) noexcept {
  if (k >= added_) return;
  const std::size_t p = exchange_slave_[k];
  Channel& c = channels_[p];
  // The slave's first datagram of this exchange is k, or k - 1 (its buffer read after its status).
  const bool first = k == 0 || exchange_slave_[k - 1] != p;
  c.answered = true;
  if (c.phase == Phase::repeat) {
    on_repeat_answer(c, d);
    return;
  }
  if (c.phase == Phase::send) {
    c.sent_this_exchange = d.wkc() == 1;
    moved_ = moved_ || c.sent_this_exchange;
    return;
  }
  if (c.phase != Phase::wait) return;
  if (first) {
    c.in_full = d.wkc() == 1 && d.length() == 1 && (d.data()[0] & reg::kSmStatusMailboxFull) != 0;
    moved_ = moved_ || c.in_full;
  } else if (c.in_full && d.wkc() == 1) {
    take_reply(c, ConstByteSpan(d.data()));
  }
}

void MailboxClient::on_repeat_answer(Channel& c, const DatagramView& d) noexcept {
  if (c.repeat_write) {  // written (or not: read again, and written again if still unacknowledged)
    c.repeat_write = false;
    return;
  }
  if (d.wkc() != 1 || d.length() != reg::kSyncManagerSize) return;
  const Box& box = boxes_[c.current.request.position];
  const std::uint8_t* r = d.data().data();
  if ((r[reg::kSmPdiControl] & kRepeatAck) == box.repeat) {
    c.repeat_acked = true;
    return;
  }
  c.repeat_write = (r[reg::kSmActivate] & reg::kSmEnable) != 0 && load_le16(r + reg::kSmPhysicalStart) == box.in_start &&
                   load_le16(r + reg::kSmLength) == box.in_size;
}

void MailboxClient::take_reply(Channel& c, ConstByteSpan bytes) noexcept {
  const Result<mbx::Message> message = mbx::decode(bytes);
  if (!message.ok()) return;
  // A message with the counter of the one taken before is that one again (ETG.1000.4: the slave
  // counts its messages 1..7): the answer to a request written twice, or put back on a repeat
  // request when nothing had been lost.
  Box& box = boxes_[c.current.request.position];
  const std::uint8_t counter = message.value().header.counter;
  if (counter != 0 && counter == box.in_counter) {
    ++stats_.duplicates_dropped;
    return;
  }
  box.in_counter = counter;
  if (message.value().header.type == mbx::Type::error) {
    const Result<std::uint16_t> detail = mbx::decode_error_reply(message.value());
    c.current.mailbox_error = detail.value_or(0);
    complete(c, SdoOutcome::mailbox_error);
    return;
  }
  const Result<coe::Message> coe_message = coe::decode(bytes);
  if (!coe_message.ok()) return;  // not CoE, or not decodable: not our answer
  const coe::Message& m = coe_message.value();
  if (m.service == coe::Service::emergency) {
    ++emergencies_;
    return;
  }
  if (c.current.request.direction == SdoDirection::information) {
    if (m.service == coe::Service::sdo_information) take_information(c, m.payload);
    return;
  }
  if (m.service != coe::Service::sdo_response && m.service != coe::Service::sdo_request) return;
  const coe::Sdo& sdo = m.sdo;
  const SdoRequest& r = c.current.request;
  if (c.step == Step::upload_segment || c.step == Step::download_segment) {
    if (sdo.kind == coe::SdoKind::abort) {
      if (sdo.index != r.index || sdo.subindex != r.subindex) return;
      c.current.abort_code = sdo.abort_code;
      complete(c, SdoOutcome::aborted);
      return;
    }
    take_segment(c, sdo);
    return;
  }
  if (sdo.index != r.index || sdo.subindex != r.subindex) return;
  if (sdo.kind == coe::SdoKind::abort) {
    c.current.abort_code = sdo.abort_code;
    complete(c, SdoOutcome::aborted);
    return;
  }
  if (r.direction == SdoDirection::download && sdo.kind == coe::SdoKind::download_initiate_response) {
    if (r.size <= coe::kMaxExpeditedSize || c.chunk >= r.size) {
      complete(c, SdoOutcome::ok);
      return;
    }
    c.offset = c.chunk;
    c.toggle = false;
    c.current.segmented = true;
    if (!encode_step(c, Step::download_segment, now_)) complete(c, SdoOutcome::bad_response);
    return;
  }
  if (r.direction == SdoDirection::upload && sdo.kind == coe::SdoKind::upload_initiate_response) {
    const std::size_t size = sdo.data.size();
    if (sdo.expedited) {
      if (size == 0 || size > coe::kMaxExpeditedSize) {
        complete(c, SdoOutcome::bad_response);
        return;
      }
      std::memcpy(c.current.data.data(), sdo.data.data(), size);
      c.current.size = static_cast<std::uint16_t>(size);
      complete(c, SdoOutcome::ok);
      return;
    }
    if (sdo.size > kMaxSdoData) {
      abort_transfer(c, SdoOutcome::too_long, coe::abort_code::kOutOfMemory);
      return;
    }
    if (size > sdo.size) {
      complete(c, SdoOutcome::bad_response);
      return;
    }
    if (size > 0) std::memcpy(c.current.data.data(), sdo.data.data(), size);
    c.current.size = static_cast<std::uint16_t>(size);
    if (size == sdo.size) {
      complete(c, SdoOutcome::ok);
      return;
    }
    // Announced more than it carries: the rest follows in upload segments.
    c.offset = size;
    c.expected = sdo.size;
    c.toggle = false;
    c.current.segmented = true;
    if (!encode_step(c, Step::upload_segment, now_)) complete(c, SdoOutcome::bad_response);
  }
}

void MailboxClient::take_segment(Channel& c, const coe::Sdo& sdo) noexcept {
  const SdoRequest& r = c.current.request;
  const bool upload = c.step == Step::upload_segment;
  if (sdo.kind != (upload ? coe::SdoKind::upload_segment_response : coe::SdoKind::download_segment_response)) return;
  if (sdo.toggle != c.toggle) {
    abort_transfer(c, SdoOutcome::bad_response, coe::abort_code::kToggleBit);
    return;
  }
  if (upload) {
    const std::size_t n = sdo.data.size();
    if (c.offset + n > c.expected) {
      abort_transfer(c, SdoOutcome::bad_response, coe::abort_code::kLengthTooHigh);
      return;
    }
    if (n > 0) std::memcpy(c.current.data.data() + c.offset, sdo.data.data(), n);
    c.offset += n;
    c.current.size = static_cast<std::uint16_t>(c.offset);
    if (sdo.last_segment) {
      complete(c, c.offset == c.expected ? SdoOutcome::ok : SdoOutcome::bad_response);
      return;
    }
    c.toggle = !c.toggle;
    if (!encode_step(c, Step::upload_segment, now_)) complete(c, SdoOutcome::bad_response);
    return;
  }
  c.offset += c.chunk;
  if (c.offset >= r.size) {
    complete(c, SdoOutcome::ok);
    return;
  }
  c.toggle = !c.toggle;
  if (!encode_step(c, Step::download_segment, now_)) complete(c, SdoOutcome::bad_response);
}

void MailboxClient::take_information(Channel& c, ConstByteSpan coe_payload) noexcept {
  const Result<coe::info::Fragment> decoded = coe::info::decode_fragment(coe_payload);
  if (!decoded.ok()) {
    complete(c, SdoOutcome::bad_response);
    return;
  }
  const coe::info::Fragment& f = decoded.value();
  const SdoRequest& r = c.current.request;
  if (f.opcode == coe::info::kErrorRequest) {
    if (f.data.size() < 4) {
      complete(c, SdoOutcome::bad_response);
      return;
    }
    c.current.abort_code = load_le32(f.data.data());
    complete(c, SdoOutcome::aborted);
    return;
  }
  if (f.opcode != r.info_opcode + 1U) return;  // not the answer to this request
  // A fragment after the first counts down by one; one that does not is a lost or foreign fragment.
  if (c.current.segmented && std::uint32_t{f.fragments_left} + 1U != c.expected) {
    complete(c, SdoOutcome::bad_response);
    return;
  }
  // Keep the bytes of [info_skip, info_skip + kMaxSdoData) of the whole response's data.
  const std::size_t begin = c.offset;
  const std::size_t end = begin + f.data.size();
  const std::size_t skip = r.info_skip;
  const std::size_t keep_from = std::max(begin, skip);
  const std::size_t keep_to = std::min(end, skip + kMaxSdoData);
  if (keep_to > keep_from) {
    std::memcpy(c.current.data.data() + (keep_from - skip), f.data.data() + (keep_from - begin), keep_to - keep_from);
  }
  c.offset = end;
  c.current.info_total = static_cast<std::uint32_t>(std::min<std::size_t>(end, 0xFFFFFFFFU));
  c.current.size = static_cast<std::uint16_t>(end > skip ? std::min(end - skip, kMaxSdoData) : 0);
  if (f.fragments_left == 0) {
    complete(c, SdoOutcome::ok);
    return;
  }
  // More to come: wait for the next fragment (the slave posts it when SM1 was read), with a fresh timeout.
  c.expected = f.fragments_left;
  c.current.segmented = true;
  c.deadline = now_ + response_timeout_;
  c.late_polls = 0;
}

void MailboxClient::on_lost_exchange(Channel& c) noexcept {
  // The ESCs carried out the lost frame's datagrams all the same.
  if (c.phase == Phase::wait) {
    // Its SM1 read may have emptied the mailbox, the answer lost with the frame: ask the slave to
    // put its last message back (toggle SM1's repeat bit, wait for its ack, poll again). If
    // nothing was lost, the message put back is the one taken before: dropped by its counter.
    Box& box = boxes_[c.current.request.position];
    box.repeat = static_cast<std::uint8_t>(box.repeat ^ reg::kSmRepeat);
    c.phase = Phase::repeat;
    c.repeat_write = false;
    c.deadline = now_ + response_timeout_;
    c.late_polls = 0;
    ++stats_.repeat_requests;
  } else if (c.phase == Phase::send) {
    // The slave may have taken the write: it goes again unchanged, its mailbox counter the same,
    // so that the slave knows it for a repeat (and answers it at most once more: dropped).
    ++stats_.rewrites;
  }
}

void MailboxClient::end_exchange(hal::Nanoseconds now) noexcept {
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((busy_ & slave_bit(p)) == 0) continue;
    Channel& c = channels_[p];
    if (c.added > 0 && !c.answered) on_lost_exchange(c);
    if (c.phase == Phase::repeat && c.repeat_acked) c.phase = Phase::wait;
    if (c.phase == Phase::send && c.sent_this_exchange) {
      if (c.step == Step::abort) {
        complete(c, c.abort_outcome);  // an abort has no answer
        continue;
      }
      c.phase = Phase::wait;
    }
    if (c.phase == Phase::none || now <= c.deadline) continue;
    // A poll counts against the slave only when it reached the slave (its datagrams came back). A
    // frame lost or late is the host's or the cable's: it counts only once nothing came back for a
    // further response timeout, so a segment gone silent still ends the transfer.
    const bool counts = c.answered || now_ > c.deadline + response_timeout_;
    if (c.added > 0 && counts && now_ > c.deadline && c.late_polls < kLatePolls) ++c.late_polls;
    if (c.late_polls >= kLatePolls) {
      ++stats_.timeouts;
      complete(c, SdoOutcome::timeout);
    }
  }
  added_ = 0;
}

Status MailboxClient::run(DatagramLink& link, hal::Nanoseconds frame_timeout, hal::Nanoseconds overall_timeout) noexcept {
  const hal::Nanoseconds give_up = link.clock().now() + overall_timeout;
  while (!idle()) {
    if (link.clock().now() > give_up) return make_error(Errc::timeout, "mailbox transfers did not finish");
    FrameBuilder& frame = link.begin();
    const std::size_t n = add_datagrams(frame, link.index(), link.clock().now());
    if (n > 0) {
      // One send: a frame that is not back in time is lost for the mailbox too (end_exchange asks the
      // slave to repeat). Sent again blind, it could find SM1 emptied by the first copy, whose
      // answer came back late and was dropped: the slave's answer gone, the transfer timed out.
      const Result<FrameView> back = link.exchange(frame_timeout, 1);
      if (back.ok()) {
        std::size_t k = 0;
        for (const DatagramView d : back.value()) {
          // On the ring, an answer lost with a copy counts as lost with the frame (MailboxService).
          if (!answer_lost_with_a_copy(link.copy_returns(), d)) on_datagram(k, d);
          ++k;
        }
      }
    }
    end_exchange(link.clock().now());
    // Give the slaves' applications time to answer (virtual time moves only when asked to), but only
    // when this exchange moved nothing: a message taken or an answer found means the next exchange
    // has work at once (the other slaves' steps, the next message).
    bool waiting = false;
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      const Phase phase = channels_[p].phase;
      waiting = waiting || ((busy_ & slave_bit(p)) != 0 && (phase == Phase::wait || phase == Phase::repeat));
    }
    if (waiting && !moved_) link.clock().sleep_until(link.clock().now() + kEmptyPollPause);
  }
  return Status::success();
}

}  // namespace rescue::ecat
