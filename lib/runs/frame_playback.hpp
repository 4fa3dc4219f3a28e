#pragma once
// render-tactile's frames: JSON-line frames read from a file descriptor as they come, and
// the paced playback of live amplitude frames (--frames; docs/rendering.md, "Sequences").
// Above both the host (its line reader) and the renderer: tp_runs.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "render/request.hpp"

namespace tp::runs {

// Each JSON-line frame on fd ({"rgb": [...]}, blank lines skipped), checked against the
// bank's grid, in order, with its name ("frame N", N its line) for messages.
void for_each_frame_line(int fd, const PixelBank& bank, const FrameSink& frame);

// A live amplitude frame's line, {"amplitudes": [...]} and a newline, every digit of each
// amplitude (the shortest text that reads back as the same double), so that a frame at full
// intensity asks exactly the pattern's configured amplitude, never 1e-11 above it.
std::string amplitude_frame_line(const std::vector<double>& amplitudes);

// --frames' playback: frame k written (`write`, a line) at k / fps s after the first; the
// PNG frames' amplitudes given (already checked), or with from_fd >= 0 the JSON-line
// frames read from that descriptor, each checked before it is written.  After the last it
// holds one frame period (so the device delivers it).  Returns the frames written.
struct Playback {
  const Sequence& sequence;
  const Profile& profile;
  const PixelBank& bank;
  double fps;
  // Where stdin's frames are mapped into the gamut (render/recruitment.hpp's map_frame)
  // before their amplitudes are taken, and the mapping told; none: played as given.
  GamutReport* gamut = nullptr;
};
std::size_t play_frames(const Playback& p, const std::vector<std::vector<double>>& given,
                        int from_fd, const std::function<void(const std::string&)>& write);

// The summary: "N frames at F fps".
std::string playback_summary(std::size_t frames, double fps);

}  // namespace tp::runs
