#include "render/request.hpp"

#include <chrono>
#include <cmath>

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"

namespace tp {

double render_duration_s(const RenderRequest& r, std::size_t frames) {
  if (r.duration_s) return *r.duration_s;
  if (!r.sequence) return 1.0;
  if (frames == 0) return r.options.limits.max_duration_s;
  return sequence_duration_s(frames, r.fps, r.options.limits);
}

void fit_to_bank(RenderRequest& r, const PixelBank& bank) {
  r.options.limits.max_current_mA =
      std::min(r.options.limits.max_current_mA, bank.doc.max_current_mA);
  if (!r.plan_only && bank.pads() > static_cast<std::size_t>(ranges::max_channels))
    bad_input("bank: " + count_text(bank.pads(), "pad") + ", more than a stimulator drives (" +
              std::to_string(ranges::max_channels) + "); --plan plans it");
}

RenderProfile render_profile(const RenderRequest& r, const PixelBank& bank) {
  if (r.profile) return {*r.profile, ""};
  const RenderOptions& o = r.options;
  ModelProfileOptions m;
  m.pulse.width_us = o.width_us;
  m.pulse.interphase_us = o.interphase_us;
  m.pulse.balance_width_us = o.balance_width_us;
  m.max_current_mA = o.limits.max_current_mA;
  m.comfort_factor = r.comfort_factor;
  const ModelProfile mp = model_profile(bank, m);
  std::string ranges;
  for (std::size_t p = 0; p < kPrimaries.size(); ++p) {
    if (!mp.profile.primary[p]) continue;
    const PrimaryRange& range = *mp.profile.primary[p];
    ranges += std::string(ranges.empty() ? "" : ", ") + kPrimaries[p] + " " +
              number_text(std::round(range.threshold_mA * 1e4) / 1e4) + " to " +
              number_text(std::round(range.comfort_mA * 1e4) / 1e4) + " mA" +
              (mp.capped[p] ? " (comfort held at the current limit)" : "") + " at pad " +
              std::to_string(mp.pixel[p]);
  }
  return {mp.profile, "no --profile: intensities span the fibre model's thresholds (" +
                          m.fibre_model + ", " + number_text(m.pulse.width_us) + " us) to " +
                          number_text(m.comfort_factor) + " x them, not this person's: " + ranges +
                          "; run calibrate"};
}

RenderResult run_render(const RenderRequest& request, const PixelBank& bank) {
  RenderRequest r = request;
  fit_to_bank(r, bank);
  if (!(r.fps >= 0.1 && r.fps <= 1000))
    bad_input("--fps: " + number_beside(r.fps, 0.1, 1000) + " outside [0.1, 1000]");
  RenderResult out;
  const RenderProfile profile = render_profile(r, bank);
  out.warning = profile.warning;
  RenderOptions& o = r.options;
  o.duration_s = render_duration_s(r, r.frames ? r.frames->count() : 0);
  check_render_options(o);
  const auto t0 = std::chrono::steady_clock::now();
  out.plan = !r.sequence ? plan_render(bank, profile.profile, r.image, o)
             : r.frames
                 ? plan_sequence(bank, profile.profile, *r.frames, o)
                 : plan_sequence(bank, profile.profile, SequenceFrames(bank.columns, bank.rows), o);
  out.plan_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (out.plan.lit.empty())
    bad_input(r.sequence ? "no frame lights a pixel"
                         : r.image_name + ": no pixel is lit (all black)");
  // Every check a device's mix gets (a plan for more pads than a stimulator drives is only
  // a plan, and skips them).
  if (bank.pads() <= static_cast<std::size_t>(ranges::max_channels))
    check_mix(out.plan.mix, o.limits);
  out.lowered = lowered_text(out.plan, r.sequence ? "sequence" : "image");
  out.document = r.plan_only  ? plan_to_json(out.plan)
                 : r.sequence ? sequence_to_json(out.plan, bank)
                              : mix_to_json(out.plan.mix);
  return out;
}

}  // namespace tp
