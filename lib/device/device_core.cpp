#include "device/device_core.hpp"

#include <cstdlib>
#include <limits>

namespace tp::device {

void DeviceCore::receive(const std::uint8_t* data, std::size_t n, std::uint64_t now_us,
                         std::vector<std::uint8_t>& out) {
  for (std::size_t i = 0; i < n; ++i) {
    if (!decoder_.push(data[i])) continue;
    const Frame& f = decoder_.frame();
    last_valid_us_ = now_us;  // any valid frame feeds the watchdog
    if (have_last_ && f.seq == last_request_.seq && f.type == last_request_.type &&
        f.payload == last_request_.payload) {
      out.insert(out.end(), last_reply_.begin(), last_reply_.end());  // retransmission
      continue;
    }
    last_reply_.clear();
    encode_frame(Frame{f.seq, static_cast<std::uint8_t>(Msg::ack), handle(f, now_us)}, last_reply_);
    last_request_ = f;
    have_last_ = true;
    out.insert(out.end(), last_reply_.begin(), last_reply_.end());
  }
  status_.rx_errors =
      static_cast<std::uint16_t>(std::min<std::uint32_t>(decoder_.errors(), 0xFFFF));
}

std::vector<std::uint8_t> DeviceCore::handle(const Frame& f, std::uint64_t now_us) {
  std::vector<std::uint8_t> body{f.type, static_cast<std::uint8_t>(Result::ok)};
  auto result = [&](Result r) {
    body[1] = static_cast<std::uint8_t>(r);
    return body;
  };
  switch (static_cast<Msg>(f.type)) {
    case Msg::identify: {
      if (!f.payload.empty()) return result(Result::bad_length);
      const auto c = encode(caps_);
      body.insert(body.end(), c.begin(), c.end());
      return body;
    }
    case Msg::configure:
      return result(configure(f.payload));
    case Msg::set_weights:
      return result(set_weights(f.payload));
    case Msg::start:
      if (!f.payload.empty()) return result(Result::bad_length);
      if (!configured_ || !weights_set_) return result(Result::not_configured);
      if (status_.state != State::running) {
        status_.state = State::running;
        status_.fault = Fault::none;
        status_.pulses = 0;
        start_us_ = next_pulse_us_ = now_us;
      }
      return body;
    case Msg::stop:
      status_.state = State::idle;  // always honoured, whatever the payload
      return body;
    case Msg::status: {
      if (!f.payload.empty()) return result(Result::bad_length);
      const auto s = encode(status_);
      body.insert(body.end(), s.begin(), s.end());
      return body;
    }
    case Msg::keepalive:
      return f.payload.empty() ? body : result(Result::bad_length);
    default:
      return result(Result::unknown_type);
  }
}

Result DeviceCore::configure(const std::vector<std::uint8_t>& payload) {
  if (status_.state == State::running) return Result::bad_state;
  const auto c = decode_config(payload);
  if (!c) return Result::bad_length;
  if (c->channels == 0 || c->channels > caps_.channels) return Result::channel_mismatch;
  if (c->width_us < caps_.min_width_us || c->width_us > caps_.max_width_us)
    return Result::out_of_range;
  if (c->balance_width_us < c->width_us || c->balance_width_us > caps_.max_balance_width_us)
    return Result::out_of_range;
  if (c->interphase_us > caps_.max_width_us) return Result::out_of_range;
  const std::uint32_t length = std::uint32_t{c->width_us} + c->interphase_us + c->balance_width_us;
  const std::uint32_t min_period = (1000000u + caps_.max_rate_hz - 1) / caps_.max_rate_hz;
  if (c->period_us <= length || c->period_us < min_period || c->period_us > 10000000u)
    return Result::out_of_range;
  config_ = *c;
  configured_ = true;
  weights_set_ = false;  // weights must be sent again for the new configuration
  return Result::ok;
}

Result DeviceCore::set_weights(const std::vector<std::uint8_t>& payload) {
  if (!configured_) return Result::not_configured;
  const auto codes = decode_weights(payload);
  if (!codes) return Result::bad_length;
  if (codes->size() != config_.channels) return Result::channel_mismatch;
  long sum = 0;
  for (std::int16_t c : *codes) {
    if (std::abs(int{c}) > caps_.max_code()) return Result::out_of_range;
    sum += c;
  }
  if (sum != 0) return Result::sum_not_zero;
  weights_ = *codes;  // applied from the next pulse on
  weights_set_ = true;
  ++status_.weight_updates;
  return Result::ok;
}

void DeviceCore::advance(std::uint64_t now_us,
                         const std::function<void(const DeliveredPulse&)>& sink) {
  if (status_.state != State::running) return;
  const std::uint64_t deadline = last_valid_us_ + std::uint64_t{caps_.watchdog_ms} * 1000u;
  while (status_.state == State::running && next_pulse_us_ <= now_us && next_pulse_us_ < deadline) {
    sink(DeliveredPulse{next_pulse_us_, start_us_, weights_, config_, caps_});
    ++status_.pulses;
    next_pulse_us_ += config_.period_us;
    if (config_.max_pulses != 0 && status_.pulses >= config_.max_pulses) {
      status_.state = State::idle;
      status_.fault = Fault::completed;
    }
  }
  if (status_.state == State::running && now_us >= deadline) {
    status_.state = State::idle;
    status_.fault = Fault::watchdog;
  }
}

void DeviceCore::link_lost() {
  if (status_.state == State::running) status_.fault = Fault::link_lost;
  status_.state = State::idle;
}

std::uint64_t DeviceCore::next_event_us() const {
  if (status_.state != State::running) return std::numeric_limits<std::uint64_t>::max();
  const std::uint64_t deadline = last_valid_us_ + std::uint64_t{caps_.watchdog_ms} * 1000u;
  return std::min(next_pulse_us_, deadline);
}

}  // namespace tp::device
