#include "ecat/mailbox/mailbox_client.hpp"

#include <algorithm>
#include <cstring>

#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/mailbox.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kSm1Status = reg::sync_manager(1) + reg::kSmStatus;

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
  box.present = out_size >= mbx::kHeaderSize + coe::kSdoInitiateSize && out_size <= kMaxMailboxSize &&
                in_size >= mbx::kHeaderSize + coe::kSdoInitiateSize && in_size <= kMaxMailboxSize;
}

bool MailboxClient::submit(const SdoRequest& request) noexcept { return queue_.push(request); }

bool MailboxClient::pop_completion(SdoCompletion& out) noexcept { return done_.pop(out); }

void MailboxClient::complete(SdoOutcome outcome) noexcept {
  current_.outcome = outcome;
  phase_ = Phase::none;
  if ((current_.request.tag & kMasterTagBit) != 0) {
    (void)master_done_.push_overwrite(current_);
  } else if ((current_.request.tag & kOperatorTagBit) != 0) {
    (void)operator_done_.push_overwrite(current_);
  } else {
    (void)done_.push_overwrite(current_);
  }
}

void MailboxClient::start_next(hal::Nanoseconds now) noexcept {
  while (phase_ == Phase::none && !queue_.empty()) {
    current_ = SdoCompletion{};
    (void)queue_.pop(current_.request);
    if (!has_mailbox(current_.request.position)) {
      complete(SdoOutcome::no_mailbox);
      continue;
    }
    offset_ = 0;
    expected_ = 0;
    toggle_ = false;
    if (!encode_step(Step::initiate, now)) complete(SdoOutcome::bad_response);
  }
}

std::size_t MailboxClient::download_room(bool initiate) const noexcept {
  const Box& box = boxes_[current_.request.position];
  const std::size_t overhead = mbx::kHeaderSize + coe::kCoeHeaderSize + (initiate ? coe::kSdoHeaderSize : coe::kSegmentHeaderSize);
  return box.out_size > overhead ? box.out_size - overhead : 0;
}

bool MailboxClient::encode_step(Step step, hal::Nanoseconds now) noexcept {
  const SdoRequest& r = current_.request;
  Box& box = boxes_[r.position];
  box.counter = mbx::next_counter(box.counter);
  mbx::Header header;
  header.counter = box.counter;
  coe::Sdo sdo;
  const std::size_t size = r.size < kMaxSdoData ? r.size : kMaxSdoData;
  switch (step) {
    case Step::initiate:
      if (r.direction == SdoDirection::upload) {
        sdo = coe::upload_request(r.index, r.subindex);
      } else if (size <= coe::kMaxExpeditedSize) {
        sdo = coe::download_request(r.index, r.subindex, ConstByteSpan(r.data.data(), size));
      } else {
        // Normal transfer: the complete size, and what fits SM0 now; segments carry the rest.
        const std::size_t room = download_room(true);
        chunk_ = size < room ? size : room;
        sdo = coe::download_request(r.index, r.subindex, ConstByteSpan(r.data.data(), chunk_));
        sdo.expedited = false;
        sdo.size = static_cast<std::uint32_t>(size);
      }
      break;
    case Step::upload_segment:
      sdo.kind = coe::SdoKind::upload_segment_request;
      sdo.toggle = toggle_;
      break;
    case Step::download_segment: {
      const std::size_t room = download_room(false);
      const std::size_t left = size > offset_ ? size - offset_ : 0;
      chunk_ = left < room ? left : room;
      sdo.kind = coe::SdoKind::download_segment_request;
      sdo.toggle = toggle_;
      sdo.last_segment = offset_ + chunk_ >= size;
      sdo.data = ConstByteSpan(r.data.data() + offset_, chunk_);
      break;
    }
    case Step::abort: sdo = coe::abort(r.index, r.subindex, abort_code_out_); break;
  }
  std::memset(message_.data(), 0, box.out_size);
  const Result<std::size_t> encoded = coe::encode(ByteSpan(message_.data(), box.out_size), header, sdo);
  if (!encoded.ok()) return false;
  step_ = step;
  phase_ = Phase::send;
  deadline_ = now + response_timeout_;
  return true;
}

void MailboxClient::abort_transfer(SdoOutcome outcome, std::uint32_t code) noexcept {
  // Tell the slave the transfer is over (it may hold a segmented transfer open), then complete.
  abort_outcome_ = outcome;
  abort_code_out_ = code;
  if (!encode_step(Step::abort, now_)) complete(outcome);
}

std::size_t MailboxClient::add_datagrams(FrameBuilder& frame, std::uint8_t index, hal::Nanoseconds now) noexcept {
  now_ = now;
  added_ = 0;
  sent_this_exchange_ = false;
  in_full_ = false;
  start_next(now);
  if (phase_ == Phase::none) return 0;
  const Box& box = boxes_[current_.request.position];
  const std::uint16_t station = plan_[current_.request.position].station_address;
  if (phase_ == Phase::send) {
    if (frame.remaining_data_capacity() < box.out_size) return 0;
    if (frame.add(Command::FPWR, index, make_address(station, box.out_start), box.out_size,
                  ConstByteSpan(message_.data(), box.out_size)).ok()) {
      added_ = 1;
    }
  } else {
    if (frame.remaining_data_capacity() < box.in_size + 1 + kDatagramOverhead) return 0;
    if (frame.add(Command::FPRD, index, make_address(station, kSm1Status), 1).ok() &&
        frame.add(Command::FPRD, index, make_address(station, box.in_start), box.in_size).ok()) {
      added_ = 2;
    }
  }
  if (added_ > 0) ++current_.exchanges;
  return added_;
}

void MailboxClient::on_datagram(std::size_t k, const DatagramView& d) noexcept {
  if (k >= added_) return;
  if (phase_ == Phase::send) {
    sent_this_exchange_ = d.wkc() == 1;
    return;
  }
  if (k == 0) {
    in_full_ = d.wkc() == 1 && d.length() == 1 && (d.data()[0] & reg::kSmStatusMailboxFull) != 0;
  } else if (in_full_ && d.wkc() == 1) {
    take_reply(ConstByteSpan(d.data()));
  }
}

void MailboxClient::take_reply(ConstByteSpan bytes) noexcept {
  const Result<mbx::Message> message = mbx::decode(bytes);
  if (!message.ok()) return;
  if (message.value().header.type == mbx::Type::error) {
    const Result<std::uint16_t> detail = mbx::decode_error_reply(message.value());
    current_.mailbox_error = detail.value_or(0);
    complete(SdoOutcome::mailbox_error);
    return;
  }
  const Result<coe::Message> coe_message = coe::decode(bytes);
  if (!coe_message.ok()) return;  // not CoE, or not decodable: not our answer
  const coe::Message& m = coe_message.value();
  if (m.service == coe::Service::emergency) {
    ++emergencies_;
    return;
  }
  if (m.service != coe::Service::sdo_response && m.service != coe::Service::sdo_request) return;
  const coe::Sdo& sdo = m.sdo;
  const SdoRequest& r = current_.request;
  if (step_ == Step::upload_segment || step_ == Step::download_segment) {
    if (sdo.kind == coe::SdoKind::abort) {
      if (sdo.index != r.index || sdo.subindex != r.subindex) return;
      current_.abort_code = sdo.abort_code;
      complete(SdoOutcome::aborted);
      return;
    }
    take_segment(sdo);
    return;
  }
  if (sdo.index != r.index || sdo.subindex != r.subindex) return;
  if (sdo.kind == coe::SdoKind::abort) {
    current_.abort_code = sdo.abort_code;
    complete(SdoOutcome::aborted);
    return;
  }
  if (r.direction == SdoDirection::download && sdo.kind == coe::SdoKind::download_initiate_response) {
    if (r.size <= coe::kMaxExpeditedSize || chunk_ >= r.size) {
      complete(SdoOutcome::ok);
      return;
    }
    offset_ = chunk_;
    toggle_ = false;
    current_.segmented = true;
    if (!encode_step(Step::download_segment, now_)) complete(SdoOutcome::bad_response);
    return;
  }
  if (r.direction == SdoDirection::upload && sdo.kind == coe::SdoKind::upload_initiate_response) {
    const std::size_t size = sdo.data.size();
    if (sdo.expedited) {
      if (size == 0 || size > coe::kMaxExpeditedSize) {
        complete(SdoOutcome::bad_response);
        return;
      }
      std::memcpy(current_.data.data(), sdo.data.data(), size);
      current_.size = static_cast<std::uint16_t>(size);
      complete(SdoOutcome::ok);
      return;
    }
    if (sdo.size > kMaxSdoData) {
      abort_transfer(SdoOutcome::too_long, coe::abort_code::kOutOfMemory);
      return;
    }
    if (size > sdo.size) {
      complete(SdoOutcome::bad_response);
      return;
    }
    if (size > 0) std::memcpy(current_.data.data(), sdo.data.data(), size);
    current_.size = static_cast<std::uint16_t>(size);
    if (size == sdo.size) {
      complete(SdoOutcome::ok);
      return;
    }
    // Announced more than it carries: the rest follows in upload segments.
    offset_ = size;
    expected_ = sdo.size;
    toggle_ = false;
    current_.segmented = true;
    if (!encode_step(Step::upload_segment, now_)) complete(SdoOutcome::bad_response);
  }
}

void MailboxClient::take_segment(const coe::Sdo& sdo) noexcept {
  const SdoRequest& r = current_.request;
  const bool upload = step_ == Step::upload_segment;
  if (sdo.kind != (upload ? coe::SdoKind::upload_segment_response : coe::SdoKind::download_segment_response)) return;
  if (sdo.toggle != toggle_) {
    abort_transfer(SdoOutcome::bad_response, coe::abort_code::kToggleBit);
    return;
  }
  if (upload) {
    const std::size_t n = sdo.data.size();
    if (offset_ + n > expected_) {
      abort_transfer(SdoOutcome::bad_response, coe::abort_code::kLengthTooHigh);
      return;
    }
    if (n > 0) std::memcpy(current_.data.data() + offset_, sdo.data.data(), n);
    offset_ += n;
    current_.size = static_cast<std::uint16_t>(offset_);
    if (sdo.last_segment) {
      complete(offset_ == expected_ ? SdoOutcome::ok : SdoOutcome::bad_response);
      return;
    }
    toggle_ = !toggle_;
    if (!encode_step(Step::upload_segment, now_)) complete(SdoOutcome::bad_response);
    return;
  }
  offset_ += chunk_;
  if (offset_ >= r.size) {
    complete(SdoOutcome::ok);
    return;
  }
  toggle_ = !toggle_;
  if (!encode_step(Step::download_segment, now_)) complete(SdoOutcome::bad_response);
}

void MailboxClient::end_exchange(hal::Nanoseconds now) noexcept {
  if (phase_ == Phase::send && sent_this_exchange_) {
    if (step_ == Step::abort) {
      complete(abort_outcome_);  // an abort has no answer
    } else {
      phase_ = Phase::wait;
    }
  }
  if (phase_ != Phase::none && now > deadline_) complete(SdoOutcome::timeout);
  added_ = 0;
}

Status MailboxClient::run(DatagramLink& link, hal::Nanoseconds frame_timeout, hal::Nanoseconds overall_timeout) noexcept {
  const hal::Nanoseconds give_up = link.clock().now() + overall_timeout;
  while (!idle()) {
    if (link.clock().now() > give_up) return make_error(Errc::timeout, "mailbox transfers did not finish");
    FrameBuilder& frame = link.begin();
    const std::size_t n = add_datagrams(frame, link.index(), link.clock().now());
    if (n > 0) {
      const Result<FrameView> back = link.exchange(frame_timeout, 3);
      if (back.ok()) {
        std::size_t k = 0;
        for (const DatagramView d : back.value()) on_datagram(k++, d);
      }
    }
    end_exchange(link.clock().now());
    // Give the slave's application time to answer (virtual time moves only when asked to).
    if (phase_ == Phase::wait) link.clock().sleep_until(link.clock().now() + 50 * hal::kNsPerUs);
  }
  return Status::success();
}

}  // namespace rescue::ecat
