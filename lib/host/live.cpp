#include "host/live.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>

#include "core/error.hpp"
#include "host/session.hpp"
#include "host/stimulator.hpp"
#include "host/transport.hpp"
#include "core/json.hpp"
#include "core/number.hpp"

namespace tp::host {

LiveFrame parse_live_line(const std::string& line, const std::string& where) {
  Json j;
  try {
    j = parse_json_strict(line, where);
  } catch (const nlohmann::json::exception&) {
    bad_input(where + ": malformed JSON");
  }
  const bool currents = j.is_object() && j.contains("currents_mA");
  const bool amplitudes = j.is_object() && j.contains("amplitudes");
  if (!j.is_object() || j.size() != 1 || !(currents || amplitudes))
    bad_input(where + ": expected {\"currents_mA\": [...]} or {\"amplitudes\": [...]}, one key" +
              (j.is_object() && j.size() > 1 ? std::string(", got ") + std::to_string(j.size())
                                             : std::string()));
  LiveFrame f;
  f.kind = currents ? LiveFrame::Kind::currents : LiveFrame::Kind::amplitudes;
  f.where = where;
  const char* key = currents ? "currents_mA" : "amplitudes";
  const Json& list = j[key];
  if (!list.is_array()) bad_input(where + ": " + key + " must be a list of numbers");
  for (std::size_t i = 0; i < list.size(); ++i)
    f.values_mA.push_back(json_finite(list[i], where + " " + key + "[" + std::to_string(i) + "]"));
  return f;
}

LiveState::LiveState(const Mix& m, const StimulusLimits& limits, const device::Capabilities& caps)
    : mix_(m), limits_(limits), caps_(caps) {}

void LiveState::add(const LiveFrame& f) {
  if (f.kind == LiveFrame::Kind::amplitudes) {
    pending_.scales = amplitude_scales(f.values_mA, mix_, f.where);
    ++pending_.frames;
    return;
  }
  if (mix_.table()) bad_input(f.where + ": a mix takes {\"amplitudes\": [...]}, one per pattern");
  Stimulus s = mix_.patterns[0];
  if (f.values_mA.size() != s.currents_mA.size())
    bad_input(f.where + ": " + std::to_string(f.values_mA.size()) + " currents for " +
              std::to_string(s.currents_mA.size()) + " channels");
  s.currents_mA = f.values_mA;
  // Its own pattern: its amplitude is its largest current (see live.hpp).
  s.amplitude_mA = 0;
  std::vector<std::int16_t> codes;
  try {
    check_stimulus(s, limits_);
    codes = pattern_codes(s, caps_, current_limit_mA(s, limits_));
    if (s.shape.shaped()) check_stimulus(delivered_stimulus(s, codes, caps_), limits_);
    device::ChannelLoad load;
    device::add_dense(load, codes, pattern_timing(s, 0));
    check_load(load, caps_, "");
  } catch (const Error& e) {
    bad_input(f.where + ": " + e.what());
  }
  mix_.patterns[0] = s;
  pending_.codes = std::move(codes);
  pending_.scales.reset();  // the device sets new codes at full scale
  ++pending_.frames;
}

LiveState::Update LiveState::take() {
  Update u = std::move(pending_);
  pending_ = Update{};
  return u;
}

bool LineSource::take_lines(LiveState& state, std::int64_t deadline_ns) {
  bool any = false;
  std::string line;
  for (std::size_t n = 1; reader_.next(line); ++n) {
    any = true;
    if (line.find_first_not_of(" \t\r") != std::string::npos)
      state.add(parse_live_line(line, "input line " + std::to_string(reader_.lines())));
    if (n % 16 == 0 && monotonic_ns() >= deadline_ns) break;  // the rest: the next turn's
  }
  return any;
}

bool LineSource::pump(LiveState& state, int timeout_ms) {
  // A turn's work ends by the time the keep-alive is due (at least kMinTurnMs of it), however
  // slow this machine parses: lines not taken by then wait, read, for the next turn.
  const std::int64_t deadline_ns =
      monotonic_ns() + std::int64_t{std::max(timeout_ms, kMinTurnMs)} * 1000000;
  if (!take_lines(state, deadline_ns) && !reader_.at_end()) {
    reader_.fill(timeout_ms);
    take_lines(state, deadline_ns);
  }
  // Whatever else is there already, up to 16 reads (1 MiB) a turn.
  for (int i = 0; i < 16 && !reader_.at_end() && monotonic_ns() < deadline_ns; ++i)
    if (!reader_.fill(0) || !take_lines(state, deadline_ns)) break;
  return !reader_.at_end();
}

void FrameQueue::push(LiveFrame f) {
  {
    std::lock_guard<std::mutex> lock(m_);
    if (closed_) failure(f.where + ": the live input has ended");
    frames_.push_back(std::move(f));
  }
  cv_.notify_all();
}

void FrameQueue::close() {
  {
    std::lock_guard<std::mutex> lock(m_);
    closed_ = true;
  }
  cv_.notify_all();
}

bool FrameQueue::closed() const {
  std::lock_guard<std::mutex> lock(m_);
  return closed_;
}

bool FrameQueue::pump(LiveState& state, int timeout_ms) {
  std::deque<LiveFrame> taken;
  bool open = true;
  {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait_for(lock, std::chrono::milliseconds(timeout_ms),
                 [&] { return closed_ || !frames_.empty(); });
    taken.swap(frames_);
    open = !closed_;
  }
  for (const LiveFrame& f : taken) state.add(f);
  return open;
}

}  // namespace tp::host
