// The gamut's colours from the bank's recruitment, and the image mapped into the gamut
// (recruitment.hpp).

#include "render/recruitment.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "core/error.hpp"
#include "core/number.hpp"
#include "fibre/population.hpp"
#include "model/primaries.hpp"
#include "render/model_profile.hpp"

namespace tp {

namespace {

// The pitch around a pad, x0, x1, z0, z1 (mm): a grid's pitches, else the pad's size.
std::array<double, 4> pitch_around(const ElectrodeArray& a, long pad) {
  const auto k = static_cast<std::size_t>(pad);
  const double px = a.pitch_mm.value_or(a.width_mm);
  const double pz = a.row_pitch_mm > 0 ? a.row_pitch_mm : a.length_mm;
  const double x = a.positions_mm[k], z = a.z_of(k);
  return {x - 0.5 * px, x + 0.5 * px, z - 0.5 * pz, z + 0.5 * pz};
}

// One mode's thresholds, per class, ascending (+infinity: none below the cap); none, with
// the reason in `why`, for a mode with no feasible pattern or no threshold below the cap.
std::optional<ModeRecruitment> sample_mode(const PixelBank& bank, std::size_t m,
                                           const fibre::FibreModel& model,
                                           const RecruitmentOptions& o, std::size_t& done,
                                           std::size_t total, std::string& why) {
  ModeRecruitment q;
  q.pad = centre_pattern(bank, m);
  if (q.pad < 0) {
    why = "the bank has no feasible pattern of it";
    return std::nullopt;
  }
  const PatternThreshold ref = pattern_threshold(bank, q.pad, m, model, o.pulse, o.max_mA);
  if (!ref.threshold_mA) {
    why = "the model gives it no threshold within " + number_text(o.max_mA) + " mA at pad " +
          std::to_string(q.pad) + " (" + ref.reason + ")";
    return std::nullopt;
  }
  q.reference_mA = *ref.threshold_mA;
  fibre::ThresholdSettings s;
  s.max_mA = o.max_mA;
  s.threads = o.threads;
  fibre::PopulationOptions po;
  po.per_class = o.per_class;
  po.seed = o.seed;
  po.threads = o.threads;
  po.region_mm = pitch_around(bank.doc.setup.array, q.pad);
  const std::size_t before = done;
  if (o.progress) po.progress = [&](std::size_t d, std::size_t) { o.progress(before + d, total); };
  const BankEntry& e = bank.entry[static_cast<std::size_t>(q.pad)][m];
  const fibre::Population pop = fibre::sample_population(
      bank.doc.setup, e.weights, model, o.pulse, s, fibre::default_afferent_classes(), po);
  for (const fibre::Afferent& a : pop.afferents) {
    const auto k = static_cast<std::size_t>(
        std::find(kPrimaries.begin(), kPrimaries.end(), a.receptor) - kPrimaries.begin());
    if (k >= 3) continue;
    q.thresholds_mA[k].push_back(a.threshold_mA.value_or(std::numeric_limits<double>::infinity()));
  }
  for (auto& t : q.thresholds_mA) std::sort(t.begin(), t.end());
  done += pop.afferents.size();
  return q;
}

}  // namespace

BankRecruitment bank_recruitment(const PixelBank& bank, const RecruitmentOptions& o,
                                 std::vector<std::string>* omitted) {
  if (!(o.per_class >= 1 && o.per_class <= 1000))
    bad_input("--population: " + std::to_string(o.per_class) + " outside [1, 1000]");
  const std::unique_ptr<fibre::FibreModel> model = fibre::make_fibre_model(o.fibre_model);
  BankRecruitment r;
  r.per_class = static_cast<long>(o.per_class);
  r.seed = o.seed;
  r.fibre_model = o.fibre_model;
  r.pulse = pulse_spec_to_json(o.pulse);
  r.max_mA = o.max_mA;
  std::size_t modes = 0;
  for (std::size_t m = 0; m < 3; ++m) modes += centre_pattern(bank, m) != kNoMode;
  const std::size_t total = modes * 3 * o.per_class;
  std::size_t done = 0;
  for (std::size_t m = 0; m < 3; ++m) {
    if (centre_pattern(bank, m) == kNoMode) continue;
    std::string why;
    r.mode[m] = sample_mode(bank, m, *model, o, done, total, why);
    if (!r.mode[m] && omitted)
      omitted->push_back(std::string("recruitment: no ") + kPrimaries[m] + " mode sampled: " +
                         why + "; render-tactile never drives it");
  }
  return r;
}

std::string recruitment_note(const BankRecruitment& r) {
  if (!r.mode[0] && !r.mode[1] && !r.mode[2])
    return "recruitment: no mode sampled (the bank carries none; render-tactile drives nothing "
           "with it)";
  std::string out = "recruitment, " + std::to_string(r.per_class) +
                    " afferents a class about each mode's centre pixel, at 2 x its threshold:";
  const char* sep = " ";
  for (std::size_t m = 0; m < 3; ++m) {
    if (!r.mode[m]) continue;
    const std::array<double, 3> f = r.mode[m]->fractions(2 * r.mode[m]->reference_mA);
    char b[128];
    std::snprintf(b, sizeof b, "%s%s mode RA %.2f SAI %.2f PC %.2f", sep, kPrimaries[m], f[0],
                  f[1], f[2]);
    out += b;
    sep = "; ";
  }
  return out;
}

GamutModes gamut_modes(const BankRecruitment& r, const Profile& profile, long pad) {
  GamutModes c;
  for (std::size_t m = 0; m < 3; ++m) {
    if (!r.mode[m]) continue;
    const bool has = profile.primary[m] || (profile.pixel.count(pad) && profile.pixel.at(pad)[m]);
    if (!has) continue;
    const PrimaryRange& range = profile.range(static_cast<int>(m), pad);
    const double at_mA = r.mode[m]->reference_mA * range.comfort_mA / range.threshold_mA;
    c.onset[m] = r.mode[m]->fractions(r.mode[m]->reference_mA);
    c.full[m] = range.colour ? *range.colour : r.mode[m]->fractions(at_mA);
  }
  return c;
}

void add_colours(Profile& profile, const BankRecruitment& r) {
  for (std::size_t m = 0; m < 3; ++m)
    if (profile.primary[m] && r.mode[m]) {
      PrimaryRange& range = *profile.primary[m];
      range.colour = r.mode[m]->fractions(r.mode[m]->reference_mA * range.comfort_mA /
                                          range.threshold_mA);
    }
}

GamutReport map_to_gamut(const PixelBank& bank, const Profile& profile, PadIntensities& image) {
  const BankRecruitment& r = *bank.recruitment;
  GamutReport g;
  g.error.assign(image.value.size(), 0.0);
  g.centre = gamut_modes(r, profile, static_cast<long>(bank.doc.setup.array.centre_index()));
  double sum = 0;
  for (std::size_t k = 0; k < image.value.size() && k < bank.pads(); ++k) {
    std::array<double, 3>& v = image.value[k];
    if (!(v[0] > 0 || v[1] > 0 || v[2] > 0)) continue;
    GamutModes c = gamut_modes(r, profile, static_cast<long>(k));
    for (std::size_t m = 0; m < 3; ++m)
      if (!bank.entry[k][m].feasible) c.onset[m] = c.full[m] = {0, 0, 0};
    const GamutAnswer a = nearest_in_gamut(c, v);
    v = a.intensity;  // 0: off; on: kLeastOn (the threshold) or more
    ++g.requested;
    g.outside += a.error > kGamutTolerance;
    g.max_error = std::max(g.max_error, a.error);
    g.error[k] = a.error;
    sum += a.error;
  }
  if (g.requested) g.mean_error = sum / static_cast<double>(g.requested);
  return g;
}

std::string unlit_by_gamut(const PixelBank& bank, const Profile& profile, const GamutReport& g) {
  std::string why;
  for (std::size_t m = 0; m < 3; ++m) {
    const std::string mode = kPrimaries[m];
    std::string reason;
    if (!bank.recruitment || !bank.recruitment->mode[m])
      reason = "the bank's recruitment has no " + mode + " mode";
    else if (!profile.primary[m] && profile.pixel.empty())
      reason = "the profile has no range for " + mode;
    if (!reason.empty()) why += (why.empty() ? "" : "; ") + mode + ": " + reason;
  }
  return count_text(g.requested, "pixel") + " ask" + (g.requested == 1 ? "s" : "") +
         " for colour, and the nearest the modes come to each is nothing (" +
         (why.empty() ? "off is nearer than any mix: the modes bring more of the other classes "
                        "than of those asked for"
                      : why) +
         ")";
}

std::string recruitment_pulse_note(const BankRecruitment& r, const PulseSpec& render_pulse) {
  // Read as any pulse is (bad input naming the field), compared by value.
  const PulseSpec theirs = pulse_spec_from_json(r.pulse, "bank: recruitment.pulse");
  if (theirs == render_pulse) return "";
  return "the bank's recruitment was sampled with a " + theirs.describe() +
         " pulse, not this render's " + render_pulse.describe() +
         " pulse: the gamut's colours are that pulse's";
}

void map_frame(const PixelBank& bank, const Profile& profile, PadIntensities& frame,
               GamutReport& tally) {
  const GamutReport g = map_to_gamut(bank, profile, frame);
  const double sum = tally.mean_error * static_cast<double>(tally.requested) +
                     g.mean_error * static_cast<double>(g.requested);
  ++tally.frames;
  tally.requested += g.requested;
  tally.outside += g.outside;
  tally.max_error = std::max(tally.max_error, g.max_error);
  tally.mean_error = tally.requested ? sum / static_cast<double>(tally.requested) : 0.0;
  if (tally.error.size() < g.error.size()) tally.error.resize(g.error.size(), 0.0);
  for (std::size_t k = 0; k < g.error.size(); ++k)
    tally.error[k] = std::max(tally.error[k], g.error[k]);
  tally.centre = g.centre;
}

Json gamut_to_json(const GamutReport& g) {
  Json j;
  if (g.frames > 0) j["frames"] = g.frames;
  j["requested"] = g.requested;
  j["outside"] = g.outside;
  j["tolerance"] = kGamutTolerance;
  j["max_error"] = g.max_error;
  j["mean_error"] = g.mean_error;
  Json colours = Json::object(), onset = Json::object();
  for (std::size_t m = 0; m < 3; ++m) {
    const auto& f = g.centre.full[m];
    const auto& o = g.centre.onset[m];
    colours[kPrimaries[m]] = Json::array({f[0], f[1], f[2]});
    onset[kPrimaries[m]] = Json::array({o[0], o[1], o[2]});
  }
  j["colours"] = colours;
  j["onset_colours"] = onset;
  j["error"] = g.error;
  return j;
}

std::string gamut_summary(const GamutReport& g) {
  char b[256];
  std::snprintf(b, sizeof b,
                "gamut: %zu of %zu pixels asked for outside the modes' gamut (error up to "
                "%.3g, mean %.3g, in fractions recruited)",
                g.outside, g.requested, g.max_error, g.mean_error);
  return g.frames > 0 ? std::string(b) + " over " + count_text(g.frames, "frame") : b;
}

}  // namespace tp
