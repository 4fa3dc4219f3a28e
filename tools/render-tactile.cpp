// render-tactile: a tactile image (R = RA, G = SAI, B = PC) on a 2-D array, at the
// intensities a person's profile gives, as one stimulus of patterns the device interleaves.
//
//   optimize-weights --bank --grid 8x8 --pitch 2 --pad 1x1 --neighbourhood 3 > bank.json
//   render-tactile --bank bank.json --profile profile.json --duration 2 picture.png
//     | stimctl --port emu --emu-channels 64   (one line)

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "io/json.hpp"
#include "io/number.hpp"
#include "render/render.hpp"

namespace {

// "RA:30,SAI:200,PC:250" (any of them; the others keep their defaults).
void parse_rates(const std::string& text, std::array<double, 3>& rate) {
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    const std::string item = text.substr(at, comma - at);
    const std::size_t colon = item.find(':');
    if (colon == std::string::npos)
      tp::bad_input("--rates: '" + item + "' is not PRIMARY:HZ (e.g. SAI:200)");
    const int p = tp::primary_index(item.substr(0, colon), "--rates");
    rate[static_cast<std::size_t>(p)] = tp::parse_finite(item.substr(colon + 1), "--rates");
    at = comma + 1;
  }
}

std::string rates_text(const tp::RenderPlan& plan) {
  std::string out;
  for (std::size_t p = 0; p < 3; ++p) {
    if (plan.groups_per_primary[p] == 0) continue;
    if (!out.empty()) out += ", ";
    out += std::string(tp::kPrimaries[p]) + " " +
           tp::number_text(std::round(plan.rate_hz[p] * 100) / 100) + " Hz (" +
           tp::number_text(plan.requested_hz[p]) + " requested; " +
           std::to_string(plan.groups_per_primary[p]) + " groups)";
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Renders a tactile image on a 2-D array: image pixel (column c, row r, row 0 at the "
      "top) drives the pixel of pad r x columns + c with R = RA, G = SAI, B = PC, each 0 to "
      "255 = 0 to 1 of the person's range (the profile: I = threshold + v (comfort - "
      "threshold); 0 delivers nothing).  Patterns that share no pad and barely reach each "
      "other's targets fire together; the groups take turns in a frame, at the requested "
      "rates or, when the image asks more than the device delivers, lower ones (said on "
      "stderr; no lit pixel is dropped).  Prints one stimulus document of the groups "
      "(stimctl plays it), or with --plan the plan.  docs/rendering.md.",
      "render-tactile"};
  std::string bank_path, profile_path, rates, duration = "1", crosstalk = "0.1", width = "200",
                                              balance;
  std::vector<std::string> images;
  bool resample = false, plan_only = false;
  app.add_option("image", images, "The picture: an 8-bit RGB PNG, - for stdin")
      ->required()
      ->type_name("PNG");
  app.add_option("--bank", bank_path, "Pattern bank (optimize-weights --bank; every pad's pixel)")
      ->required()
      ->type_name("FILE");
  app.add_option("--profile", profile_path,
                 "The person's calibration (calibrate; format tactile-primaries/profile/1)")
      ->required()
      ->type_name("FILE");
  app.add_option("--rates", rates,
                 "Requested rate per primary, Hz, 0.1 to 1000 [RA:30,SAI:200,PC:250]")
      ->type_name("P:HZ,...");
  app.add_option("--duration", duration, "Seconds, (0, 3600] [1]")->type_name("S");
  app.add_option("--crosstalk", crosstalk,
                 "Largest crosstalk between patterns that fire together, 0 to 1 [0.1]")
      ->type_name("X");
  app.add_option("--width", width, "Main phase, us, whole, 10 to 1000 [200]")->type_name("US");
  app.add_option("--balance-width", balance,
                 "Balancing phase, us, whole, from --width to 8000 [--width]")
      ->type_name("US");
  app.add_flag("--resample", resample,
               "Resample an image of another size to the array's (area-weighted)");
  app.add_flag("--plan", plan_only,
               "Print the plan (groups, slots, rates) as JSON instead of the stimulus; for "
               "arrays larger than a device");

  return tp::cli::run(app, argc, argv, [&] {
    if (images.size() != 1)
      tp::bad_input(std::to_string(images.size()) + " images: a still image takes one");
    tp::RenderOptions o;
    if (!rates.empty()) parse_rates(rates, o.rate_hz);
    o.duration_s = tp::parse_finite(duration, "--duration");
    o.crosstalk = tp::parse_finite(crosstalk, "--crosstalk");
    o.width_us = tp::parse_finite(width, "--width");
    o.balance_width_us =
        balance.empty() ? o.width_us : tp::parse_finite(balance, "--balance-width");
    tp::check_render_options(o);
    if (bank_path == "-" && profile_path == "-")
      tp::bad_input("--bank and --profile: - (stdin) given twice");
    const tp::PixelBank bank = tp::pixel_bank_from_json(tp::read_json(bank_path, "bank"));
    o.limits.max_current_mA = std::min(o.limits.max_current_mA, bank.doc.max_current_mA);
    const tp::Profile profile =
        tp::profile_from_json(tp::read_json(profile_path, "profile"), o.limits.max_current_mA,
                              static_cast<long>(bank.pads()));
    const tp::RgbImage image = tp::read_png(images[0]);
    const tp::PadIntensities pads = tp::pad_intensities(image, bank.columns, bank.rows, resample);
    const tp::RenderPlan plan = tp::plan_render(bank, profile, pads, o);
    if (plan.lit.empty()) tp::bad_input(images[0] + ": no pixel is lit (all black)");
    if (plan.lowered)
      std::fprintf(stderr,
                   "render-tactile: the image asks more than the device delivers: rates "
                   "lowered by %s, every lit pixel kept\n",
                   plan.limited_by.c_str());
    std::fprintf(stderr,
                 "render-tactile: %zu lit patterns in %zu groups, cycle %s us of %d slots, "
                 "worst crosstalk %s; refresh %s\n",
                 plan.lit.size(), plan.groups.size(), tp::number_text(plan.cycle_us).c_str(),
                 plan.slots, tp::number_text(std::round(plan.worst_crosstalk * 1e4) / 1e4).c_str(),
                 rates_text(plan).c_str());
    if (plan_only) {
      tp::cli::write_stdout(tp::dump_json(tp::plan_to_json(plan)));
      return;
    }
    tp::check_mix(plan.mix, o.limits);
    tp::cli::write_stdout(tp::dump_json(tp::mix_to_json(plan.mix)));
  });
}
