// render-tactile's frames read and played (frame_playback.hpp).

#include "runs/frame_playback.hpp"

#include <chrono>
#include <thread>

#include "core/json.hpp"
#include "core/number.hpp"
#include "core/text.hpp"
#include "host/line_reader.hpp"

namespace tp::runs {

void for_each_frame_line(int fd, const PixelBank& bank, const FrameSink& frame) {
  host::LineReader in(fd);
  std::string line;
  for (;;) {
    if (in.next(line)) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      const std::string where = "frame " + std::to_string(in.lines());
      frame(frame_from_json(parse_json_text(line, where, "its line"), bank.columns, bank.rows,
                            where),
            where);
      continue;
    }
    if (in.at_end()) return;
    in.fill(1000);
  }
}

std::string amplitude_frame_line(const std::vector<double>& amplitudes) {
  std::string text = "{\"amplitudes\": [";
  for (std::size_t i = 0; i < amplitudes.size(); ++i)
    text += (i ? ", " : "") + Json(amplitudes[i]).dump();
  return text + "]}\n";
}

std::size_t play_frames(const Playback& p, const std::vector<std::vector<double>>& given,
                        int from_fd, const std::function<void(const std::string&)>& write) {
  using clock = std::chrono::steady_clock;
  const auto period =
      std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(1.0 / p.fps));
  const clock::time_point t0 = clock::now();
  std::size_t k = 0;
  auto emit = [&](const std::vector<double>& a) {
    std::this_thread::sleep_until(t0 + static_cast<long>(k) * period);
    write(amplitude_frame_line(a));
    ++k;
  };
  if (from_fd < 0) {
    for (const auto& a : given) emit(a);
  } else {
    for_each_frame_line(from_fd, p.bank, [&](const PadIntensities& f, const std::string& where) {
      if (!p.gamut) return emit(frame_amplitudes(p.sequence, p.profile, f, where));
      PadIntensities mapped = f;
      map_frame(p.bank, p.profile, mapped, *p.gamut);
      emit(frame_amplitudes(p.sequence, p.profile, mapped, where));
    });
  }
  if (k > 0) std::this_thread::sleep_until(t0 + static_cast<long>(k) * period);
  return k;
}

std::string playback_summary(std::size_t frames, double fps) {
  return count_text(frames, "frame") + " at " + number_text(fps) + " fps";
}

}  // namespace tp::runs
