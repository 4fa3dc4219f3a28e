#include "render/sequence.hpp"

#include <cmath>
#include <map>
#include <tuple>

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/text.hpp"

namespace tp {

namespace {

// A sequence's stimulus read back: each pattern's primary, pixels and the currents they
// were made at (render-tactile --sequence's carried keys).
Sequence sequence_of(const Mix& m, std::size_t pads) {
  Sequence q;
  q.mix = m;
  std::vector<char> seen(3 * pads, 0);
  for (std::size_t g = 0; g < m.patterns.size(); ++g) {
    const Json& c = m.patterns[g].carried;
    const std::string where = "stimulus: pattern " + std::to_string(g);
    if (!c.contains("primary") || !c["primary"].is_string() || !c.contains("pixels") ||
        !c["pixels"].is_array() || c["pixels"].empty() || !c.contains("pixel_currents_mA") ||
        !c["pixel_currents_mA"].is_array() || c["pixel_currents_mA"].size() != c["pixels"].size())
      bad_input(where +
                " is not a sequence's (render-tactile --sequence: a primary, its pixels "
                "and their pixel_currents_mA)");
    q.primary.push_back(primary_index(c["primary"].get<std::string>(), where + ": primary"));
    q.pads.emplace_back();
    q.made_mA.emplace_back();
    for (std::size_t k = 0; k < c["pixels"].size(); ++k) {
      const long pad = json_int(c["pixels"][k], where + ": pixels");
      const double mA = json_finite(c["pixel_currents_mA"][k], where + ": pixel_currents_mA");
      if (pad < 0 || static_cast<std::size_t>(pad) >= pads)
        bad_input(where + "'s pixel " + std::to_string(pad) + " is not one of the bank's " +
                  count_text(pads, "pad"));
      if (!(mA > 0)) bad_input(where + ": pixel_currents_mA: not above 0");
      char& s = seen[3 * static_cast<std::size_t>(pad) + static_cast<std::size_t>(q.primary[g])];
      if (s) bad_input(where + ": pixel " + std::to_string(pad) + " in two patterns");
      s = 1;
      q.pads[g].push_back(pad);
      q.made_mA[g].push_back(mA);
    }
  }
  return q;
}

// The share of a pixel's made current that intensity v asks under the profile.
double share_of(const Sequence& q, const Profile& profile, std::size_t g, std::size_t k, double v) {
  return profile.current_mA(q.primary[g], q.pads[g][k], v) / q.made_mA[g][k];
}

constexpr double kShareTolerance = 1e-9;  // shares this close are the same (rounding)

}  // namespace

SequenceFrames::SequenceFrames(int columns, int rows) : columns_(columns), rows_(rows) {
  const std::size_t n = static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows);
  first_.columns = columns;
  first_.rows = rows;
  first_.value.assign(n, {0.0, 0.0, 0.0});
  lit_.assign(3 * n, 0);
  kin_.assign(3 * n, 0);
}

void SequenceFrames::add(const PadIntensities& frame, const std::string& where) {
  if (frame.columns != columns_ || frame.rows != rows_ || frame.value.size() != first_.value.size())
    bad_input(where + ": " + std::to_string(frame.columns) + " x " + std::to_string(frame.rows) +
              " pixels for a bank of " + std::to_string(columns_) + " x " + std::to_string(rows_) +
              " pads");
  if (count_++ == 0) first_ = frame;
  // Kin refined: the same kin before and the same intensity now (ids by first appearance).
  std::map<std::pair<long, double>, long> next;
  for (std::size_t pad = 0; pad < frame.value.size(); ++pad)
    for (std::size_t p = 0; p < 3; ++p) {
      const double v = frame.value[pad][p];
      if (v > 0) lit_[3 * pad + p] = 1;
      long& k = kin_[3 * pad + p];
      k = next.emplace(std::pair{k, v}, static_cast<long>(next.size())).first->second;
    }
}

RenderPlan plan_sequence(const PixelBank& bank, const Profile& profile,
                         const SequenceFrames& frames, const RenderOptions& o) {
  PadIntensities any;
  any.columns = bank.columns;
  any.rows = bank.rows;
  any.value.assign(bank.pads(), {0.0, 0.0, 0.0});
  // Kin: the frames' and the same range (so one amplitude sets both alike); without
  // frames, each its own.
  std::vector<long> kin(3 * bank.pads());
  std::map<std::tuple<long, double, double>, long> ids;
  for (std::size_t pad = 0; pad < bank.pads(); ++pad)
    for (std::size_t p = 0; p < 3; ++p) {
      const bool lit = frames.count() > 0 ? frames.lit(pad, p)
                                          : bank.entry[pad][p].feasible && profile.primary[p];
      if (!lit) continue;
      any.value[pad][p] = 1.0;
      const PrimaryRange& r = profile.range(static_cast<int>(p), static_cast<long>(pad));
      const long frame_kin =
          frames.count() > 0 ? frames.kin(pad, p) : static_cast<long>(3 * pad + p);
      kin[3 * pad + p] = ids.emplace(std::tuple{frame_kin, r.threshold_mA, r.comfort_mA},
                                     static_cast<long>(ids.size()))
                             .first->second;
    }
  RenderPlan plan = plan_with_kin(bank, profile, any, o, kin);
  if (plan.lit.empty()) return plan;
  plan.mix.start_amplitudes_mA = frames.count() == 0
                                     ? std::vector<double>(plan.mix.patterns.size(), 0.0)
                                     : frame_amplitudes(sequence_of(plan.mix, bank.pads()), profile,
                                                        frames.first(), "frame 1");
  return plan;
}

RenderPlan plan_sequence(const PixelBank& bank, const Profile& profile,
                         const std::vector<PadIntensities>& frames, const RenderOptions& o) {
  SequenceFrames s(bank.columns, bank.rows);
  for (std::size_t f = 0; f < frames.size(); ++f)
    s.add(frames[f], "frame " + std::to_string(f + 1));
  return plan_sequence(bank, profile, s, o);
}

Json sequence_to_json(const RenderPlan& sequence, const PixelBank& bank) {
  Json j = mix_to_json(sequence.mix);
  j["array"] = array_to_json(bank.doc.setup.array);
  return j;
}

double sequence_duration_s(std::size_t frames, double fps, const StimulusLimits& limits) {
  const double s = (static_cast<double>(frames) + 1) / fps;
  if (s > limits.max_duration_s)
    bad_input("--sequence: " + count_text(frames, "frame") + " at " + number_text(fps) +
              " fps and one frame period more last " + number_text(s) +
              " s, longer than a stimulus may (" + number_text(limits.max_duration_s) +
              " s): split the sequence, or give a higher --fps");
  return s;
}

Sequence sequence_from_json(const Json& j, const PixelBank& bank, const Profile& profile,
                            const std::string& what) {
  const Json mine = array_to_json(bank.doc.setup.array);
  if (!j.is_object() || !j.contains("array"))
    bad_input(what +
              ": records no array (render-tactile --sequence writes the bank's): make "
              "the sequence again with --sequence");
  if (j["array"] != mine) {
    const Json& a = j["array"];
    const bool grid = a.is_object() && a.contains("grid") && a["grid"].is_object() &&
                      a["grid"].contains("columns") && a["grid"].contains("rows");
    const std::string theirs =
        grid ? a["grid"]["columns"].dump() + " x " + a["grid"]["rows"].dump() : "";
    const std::string ours = std::to_string(bank.columns) + " x " + std::to_string(bank.rows);
    bad_input(what + ": a sequence made for " +
              (grid && theirs != ours
                   ? theirs + " pads (columns x rows), not the bank's " + ours
                   : "the array " + a.dump() + ", not the bank's " + mine.dump()) +
              ": give the bank it was made with, or make the sequence again with this one");
  }
  const Mix m = mix_from_json(j);
  if (m.patterns[0].currents_mA.size() != bank.pads())
    bad_input(what + ": " + count_text(m.patterns[0].currents_mA.size(), "channel") +
              " for a bank of " + count_text(bank.pads(), "pad"));
  Sequence q = sequence_of(m, bank.pads());
  // The profile against the currents each pixel was made at: never more (the pattern holds
  // no more), and a pattern's pixels in one proportion (one amplitude scales them all).
  for (std::size_t g = 0; g < q.pads.size(); ++g)
    for (std::size_t k = 0; k < q.pads[g].size(); ++k) {
      const std::string pixel = pixel_text(q.pads[g][k], bank.columns) + "'s " +
                                kPrimaries[static_cast<std::size_t>(q.primary[g])];
      const double top = share_of(q, profile, g, k, 1.0);
      if (top > 1 + kShareTolerance)
        bad_input(what + ": the profile gives " + pixel + " up to " +
                  number_text(profile.current_mA(q.primary[g], q.pads[g][k], 1.0)) +
                  " mA, above the " + number_text(q.made_mA[g][k]) +
                  " mA its pattern was made for (another profile): make the sequence again "
                  "with this profile");
      const double v = 1.0 / 255;  // the lowest intensity: the threshold's share
      if (k > 0 && (std::abs(top - share_of(q, profile, g, 0, 1.0)) > kShareTolerance ||
                    std::abs(share_of(q, profile, g, k, v) - share_of(q, profile, g, 0, v)) >
                        kShareTolerance))
        bad_input(what + ": the profile gives " + pixel + " another range than " +
                  pixel_text(q.pads[g][0], bank.columns) +
                  ", which fires with it as one pattern: make the sequence again with this "
                  "profile");
    }
  return q;
}

std::vector<double> frame_amplitudes(const Sequence& q, const Profile& profile,
                                     const PadIntensities& frame, const std::string& where) {
  // Where each (pad, primary) is: its pattern and member.
  std::vector<std::pair<long, std::size_t>> at(3 * frame.value.size(), {-1, 0});
  for (std::size_t g = 0; g < q.pads.size(); ++g)
    for (std::size_t k = 0; k < q.pads[g].size(); ++k) {
      const auto pad = static_cast<std::size_t>(q.pads[g][k]);
      if (pad >= frame.value.size())
        bad_input("stimulus: pattern " + std::to_string(g) + "'s pixel " + std::to_string(pad) +
                  " is not one of the frame's " + count_text(frame.value.size(), "pixel"));
      at[3 * pad + static_cast<std::size_t>(q.primary[g])] = {static_cast<long>(g), k};
    }
  for (std::size_t pad = 0; pad < frame.value.size(); ++pad)
    for (std::size_t p = 0; p < 3; ++p)
      if (frame.value[pad][p] > 0 && at[3 * pad + p].first < 0)
        bad_input(where + ": " + pixel_text(static_cast<long>(pad), frame.columns) + " lights " +
                  kPrimaries[p] + ", which the sequence's stimulus has no pattern for");
  std::vector<double> a(q.pads.size(), 0.0);
  for (std::size_t g = 0; g < q.pads.size(); ++g) {
    const auto p = static_cast<std::size_t>(q.primary[g]);
    auto v = [&](std::size_t k) { return frame.value[static_cast<std::size_t>(q.pads[g][k])][p]; };
    const double share = share_of(q, profile, g, 0, v(0));
    for (std::size_t k = 1; k < q.pads[g].size(); ++k)
      if (std::abs(share_of(q, profile, g, k, v(k)) - share) > kShareTolerance)
        bad_input(where + ": " + pixel_text(q.pads[g][0], frame.columns) + " and " +
                  pixel_text(q.pads[g][k], frame.columns) + " fire as one " + kPrimaries[p] +
                  " pattern of the sequence's stimulus (its frames lit them alike), but this "
                  "frame lights them unlike: make the sequence from these frames");
    if (share > 1 + kShareTolerance)
      bad_input(where + ": " + pixel_text(q.pads[g][0], frame.columns) + " asks " +
                number_text(profile.current_mA(q.primary[g], q.pads[g][0], v(0))) + " mA of " +
                kPrimaries[p] + ", above the " + number_text(q.made_mA[g][0]) +
                " mA its pattern was made for: make the sequence again with this profile");
    a[g] = std::min(share, 1.0) * q.mix.patterns[g].amplitude_mA;
  }
  return a;
}

PadIntensities frame_from_json(const Json& j, int columns, int rows, const std::string& where) {
  if (!j.is_object() || !j.contains("rgb") || !j["rgb"].is_array())
    bad_input(where + ": expected {\"rgb\": [[R, G, B], ...]}");
  const Json& a = j["rgb"];
  const auto n = static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows);
  if (a.size() != n)
    bad_input(where + ": " + count_text(a.size(), "pixel") + " for " + std::to_string(columns) +
              " x " + std::to_string(rows) + " pads");
  PadIntensities f;
  f.columns = columns;
  f.rows = rows;
  for (std::size_t k = 0; k < n; ++k) {
    if (!a[k].is_array() || a[k].size() != 3)
      bad_input(where + ": pixel " + std::to_string(k) + " is not [R, G, B]");
    std::array<double, 3> v{};
    for (std::size_t c = 0; c < 3; ++c) {
      if (!a[k][c].is_number_integer() || a[k][c].get<long>() < 0 || a[k][c].get<long>() > 255)
        bad_input(where + ": pixel " + std::to_string(k) + ": not a whole number from 0 to 255");
      v[c] = static_cast<double>(a[k][c].get<long>()) / 255.0;
    }
    f.value.push_back(v);
  }
  return f;
}

}  // namespace tp
