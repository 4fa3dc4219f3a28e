// Tactile images (lib/render/image.hpp): PNG through libpng, exactly, every colour type and
// depth (palettes, greys, alpha composited onto black, 16-bit rounded); resampling by
// area; the image-to-pad mapping of issue 23.
#include <catch2/catch.hpp>

#include <cmath>
#include <csetjmp>
#include <cstring>
#include <optional>
#include <random>

#include <png.h>

#include "core/error.hpp"
#include "render/image.hpp"

using namespace tp;

namespace {

RgbImage random_image(int w, int h, std::uint32_t seed) {
  std::mt19937 rng(seed);
  RgbImage im;
  im.width = w;
  im.height = h;
  for (int k = 0; k < 3 * w * h; ++k) im.rgb.push_back(static_cast<std::uint8_t>(rng() & 255));
  return im;
}

// A PNG of any colour type and depth, through libpng's own writer: `samples` are the
// file's values, channel by channel, pixel by pixel, row by row (palette indices for a
// palette image), packed here for depths below 8.
struct PngSpec {
  int type = PNG_COLOR_TYPE_RGB, depth = 8, width = 1, height = 1;
  std::vector<unsigned> samples;
  std::vector<png_color> palette;
  std::vector<png_byte> palette_alpha;      // tRNS of a palette image
  std::optional<png_color_16> transparent;  // tRNS of a grey or RGB image
  bool interlaced = false;
};

int channels_of(int type) {
  switch (type) {
    case PNG_COLOR_TYPE_GRAY:
    case PNG_COLOR_TYPE_PALETTE:
      return 1;
    case PNG_COLOR_TYPE_GRAY_ALPHA:
      return 2;
    case PNG_COLOR_TYPE_RGB:
      return 3;
    default:
      return 4;
  }
}

void append_bytes(png_structp png, png_bytep data, std::size_t n) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + n);
}

// libpng's calls, their errors longjmp'd back here (no C++ object of its own to skip).
bool write_rows(png_structp png, png_infop info, const PngSpec& s, std::vector<std::uint8_t>* out,
                png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_write_fn(png, out, append_bytes, nullptr);
  png_set_IHDR(png, info, static_cast<png_uint_32>(s.width), static_cast<png_uint_32>(s.height),
               s.depth, s.type, s.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (!s.palette.empty())
    png_set_PLTE(png, info, s.palette.data(), static_cast<int>(s.palette.size()));
  if (!s.palette_alpha.empty())
    png_set_tRNS(png, info, s.palette_alpha.data(), static_cast<int>(s.palette_alpha.size()),
                 nullptr);
  if (s.transparent) png_set_tRNS(png, info, nullptr, 0, &*s.transparent);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

std::vector<std::uint8_t> write_png(const PngSpec& s) {
  const int channels = channels_of(s.type);
  const std::size_t per_row =
      static_cast<std::size_t>(s.width) * static_cast<std::size_t>(channels);
  REQUIRE(s.samples.size() == per_row * static_cast<std::size_t>(s.height));
  std::vector<std::vector<png_byte>> rows(static_cast<std::size_t>(s.height));
  for (std::size_t y = 0; y < rows.size(); ++y) {
    auto& row = rows[y];
    row.assign((per_row * static_cast<std::size_t>(s.depth) + 7) / 8, 0);
    for (std::size_t i = 0; i < per_row; ++i) {
      const unsigned v = s.samples[y * per_row + i];
      REQUIRE(v < (1u << s.depth));
      if (s.depth == 16) {
        row[2 * i] = static_cast<png_byte>(v >> 8);
        row[2 * i + 1] = static_cast<png_byte>(v & 255);
      } else {
        const std::size_t bit = i * static_cast<std::size_t>(s.depth);  // MSB first
        row[bit / 8] = static_cast<png_byte>(row[bit / 8] | (v << (8 - s.depth - bit % 8)));
      }
    }
  }
  std::vector<std::uint8_t> out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  std::vector<png_bytep> pointers;
  for (auto& r : rows) pointers.push_back(r.data());
  const bool ok = write_rows(png, info, s, &out, pointers.data());
  png_destroy_write_struct(&png, &info);
  REQUIRE(ok);
  return out;
}

// v (of max) times alpha (of max) onto black, as 0 to 255, rounded to the nearest.
std::uint8_t onto_black(unsigned v, unsigned alpha, unsigned max) {
  return static_cast<std::uint8_t>(
      std::lround(static_cast<double>(v) * alpha * 255 / (static_cast<double>(max) * max)));
}

// The PNG with a gAMA chunk of `gamma` (x 100000) after its IHDR, its CRC-32 computed.
std::vector<std::uint8_t> with_gamma(std::vector<std::uint8_t> png, std::uint32_t gamma) {
  std::vector<std::uint8_t> chunk = {0, 0, 0, 4, 'g', 'A', 'M', 'A'};
  for (int s = 24; s >= 0; s -= 8) chunk.push_back(static_cast<std::uint8_t>(gamma >> s));
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 4; i < chunk.size(); ++i) {
    crc ^= chunk[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  crc ^= 0xFFFFFFFFu;
  for (int s = 24; s >= 0; s -= 8) chunk.push_back(static_cast<std::uint8_t>(crc >> s));
  png.insert(png.begin() + 33, chunk.begin(), chunk.end());  // 8 signature + 25 IHDR
  return png;
}

void refused(const std::vector<std::uint8_t>& bytes, const char* says) {
  try {
    decode_png(bytes, "image 'x.png'");
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
    CHECK_THAT(e.what(), Catch::Matchers::Contains(says));
  }
}

}  // namespace

TEST_CASE("an 8-bit RGB PNG decodes to exactly the pixels written", "[render][image]") {
  for (auto [w, h] : {std::pair{8, 8}, std::pair{1, 1}, std::pair{17, 3}, std::pair{4096, 2}}) {
    const RgbImage im = random_image(w, h, static_cast<std::uint32_t>(w * 31 + h));
    const RgbImage back = decode_png(encode_png(im), "test");
    CHECK(back.width == w);
    CHECK(back.height == h);
    CHECK(back.rgb == im.rgb);
  }
  // Row 0 is the top: pixel (column 2, row 1) is the seventh of a 5-wide image's bytes.
  RgbImage im = random_image(5, 2, 1);
  const auto v = im.at(2, 1);
  CHECK(v[0] == im.rgb[3 * 7]);
  CHECK(v[2] == im.rgb[3 * 7 + 2]);
}

TEST_CASE("a PNG that does not decode is bad input", "[render][image]") {
  refused({}, "not a PNG file");
  refused({'P', '6', ' ', '4', ' ', '4', ' ', '2', '5', '5'}, "not a PNG file");  // a PPM
  auto good = encode_png(random_image(64, 64, 9));
  auto truncated = good;
  truncated.resize(truncated.size() / 2);
  refused(truncated, "does not decode (truncated: the file ends early)");
  auto damaged = good;
  damaged[20] ^= 0x5A;  // inside IHDR: its CRC fails
  refused(damaged, "does not decode");
  auto no_end = good;
  no_end.resize(no_end.size() - 12);  // every pixel there, the IEND chunk gone
  refused(no_end, "does not decode");
  refused(encode_png(random_image(kMaxImageSide + 1, 1, 3)), "larger than 4096 x 4096");
  PngSpec tall;
  tall.type = PNG_COLOR_TYPE_GRAY;
  tall.depth = 1;
  tall.height = kMaxImageSide + 1;
  tall.samples.assign(static_cast<std::size_t>(tall.height), 0);
  refused(write_png(tall), "1 x 4097 pixels, larger than 4096 x 4096");
  // Values are read as written, whatever a gAMA chunk says (1.0 or sRGB's 1/2.2).
  const RgbImage im = random_image(16, 16, 4);
  CHECK(decode_png(with_gamma(encode_png(im), 100000), "x").rgb == im.rgb);
  CHECK(decode_png(with_gamma(encode_png(im), 45455), "x").rgb == im.rgb);
}

TEST_CASE("palette, grey, alpha and 16-bit PNGs read as the RGB they show, onto black",
          "[render][image]") {
  std::mt19937 rng(38);
  const int w = 7, h = 5, n = w * h;
  // A palette of 256 colours (8-bit indices) and of 4 (2-bit): the same pixels as RGB.
  for (const int depth : {8, 2, 1}) {
    PngSpec pal;
    pal.type = PNG_COLOR_TYPE_PALETTE;
    pal.depth = depth;
    pal.width = w;
    pal.height = h;
    for (int k = 0; k < (1 << depth); ++k)
      pal.palette.push_back({static_cast<png_byte>(rng() & 255), static_cast<png_byte>(rng() & 255),
                             static_cast<png_byte>(rng() & 255)});
    RgbImage want;
    want.width = w;
    want.height = h;
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<unsigned>(rng() % pal.palette.size());
      pal.samples.push_back(k);
      for (const png_byte c : {pal.palette[k].red, pal.palette[k].green, pal.palette[k].blue})
        want.rgb.push_back(c);
    }
    INFO("palette of depth " << depth);
    const RgbImage got = decode_png(write_png(pal), "p");
    CHECK(got.rgb == want.rgb);
    CHECK(got.rgb == decode_png(encode_png(want), "rgb").rgb);
    CHECK(got.translucent == 0);
    // Its tRNS: entry 0 transparent, entry 1 half: composited onto black.
    pal.palette_alpha = {0, 128};
    const RgbImage onto = decode_png(write_png(pal), "p");
    std::size_t translucent = 0;
    for (int i = 0; i < n; ++i) {
      const unsigned k = pal.samples[static_cast<std::size_t>(i)];
      const unsigned a = k < 2 ? pal.palette_alpha[k] : 255;
      translucent += a != 255;
      for (int c = 0; c < 3; ++c)
        CHECK(onto.rgb[static_cast<std::size_t>(3 * i + c)] ==
              onto_black(want.rgb[static_cast<std::size_t>(3 * i + c)], a, 255));
    }
    CHECK(onto.translucent == translucent);
  }
  // Greys of every depth: R = G = B, 16-bit rounded to the nearest of 0 to 255.
  for (const int depth : {1, 2, 4, 8, 16}) {
    PngSpec grey;
    grey.type = PNG_COLOR_TYPE_GRAY;
    grey.depth = depth;
    grey.width = w;
    grey.height = h;
    const unsigned max = (1u << depth) - 1;
    for (int i = 0; i < n; ++i)
      grey.samples.push_back(i == 0 ? max : static_cast<unsigned>(rng() % (max + 1)));
    const RgbImage got = decode_png(write_png(grey), "g");
    INFO("grey of depth " << depth);
    for (int i = 0; i < n; ++i) {
      const unsigned v = grey.samples[static_cast<std::size_t>(i)];
      const auto want = static_cast<std::uint8_t>(std::lround(v * 255.0 / max));
      for (int c = 0; c < 3; ++c) CHECK(got.rgb[static_cast<std::size_t>(3 * i + c)] == want);
    }
    CHECK(got.rgb[0] == 255);
  }
  // Grey and RGB with alpha, 8- and 16-bit: v alpha / max, rounded once.
  for (const int type : {PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB_ALPHA, PNG_COLOR_TYPE_RGB})
    for (const int depth : {8, 16}) {
      PngSpec a;
      a.type = type;
      a.depth = depth;
      a.width = w;
      a.height = h;
      const unsigned max = (1u << depth) - 1;
      const int ch = channels_of(type);
      for (int i = 0; i < n * ch; ++i)
        a.samples.push_back(static_cast<unsigned>(rng() % (max + 1)));
      if (ch % 2 == 0) a.samples[static_cast<std::size_t>(ch - 1)] = max;  // one opaque pixel
      const RgbImage got = decode_png(write_png(a), "a");
      INFO("type " << type << ", depth " << depth);
      std::size_t translucent = 0;
      for (int i = 0; i < n; ++i) {
        const unsigned* px = &a.samples[static_cast<std::size_t>(i * ch)];
        const unsigned alpha = ch % 2 == 0 ? px[ch - 1] : max;
        translucent += alpha != max;
        for (int c = 0; c < 3; ++c)
          CHECK(got.rgb[static_cast<std::size_t>(3 * i + c)] ==
                onto_black(px[ch < 3 ? 0 : c], alpha, max));
      }
      CHECK(got.translucent == translucent);
    }
  // 16-bit values that are 8-bit ones scaled (v x 257) read back exactly; so does an
  // opaque RGBA image and an interlaced one.
  const RgbImage im = random_image(w, h, 12);
  PngSpec deep;
  deep.depth = 16;
  deep.width = w;
  deep.height = h;
  for (const std::uint8_t v : im.rgb) deep.samples.push_back(v * 257u);
  CHECK(decode_png(write_png(deep), "d").rgb == im.rgb);
  PngSpec opaque = deep;
  opaque.type = PNG_COLOR_TYPE_RGB_ALPHA;
  opaque.samples.clear();
  for (std::size_t i = 0; i < im.rgb.size(); ++i) {
    opaque.samples.push_back(im.rgb[i] * 257u);
    if (i % 3 == 2) opaque.samples.push_back(65535);
  }
  const RgbImage back = decode_png(write_png(opaque), "o");
  CHECK(back.rgb == im.rgb);
  CHECK(back.translucent == 0);
  PngSpec laced;
  laced.width = w;
  laced.height = h;
  laced.interlaced = true;
  laced.samples.assign(im.rgb.begin(), im.rgb.end());
  CHECK(decode_png(write_png(laced), "i").rgb == im.rgb);
  // An RGB image's transparent colour (tRNS): those pixels black, the rest as written.
  laced.transparent = png_color_16{0, im.rgb[0], im.rgb[1], im.rgb[2], 0};
  const RgbImage keyed = decode_png(write_png(laced), "k");
  for (int i = 0; i < n; ++i) {
    const bool key = std::equal(im.rgb.begin() + 3 * i, im.rgb.begin() + 3 * i + 3, im.rgb.begin());
    for (int c = 0; c < 3; ++c)
      CHECK(keyed.rgb[static_cast<std::size_t>(3 * i + c)] ==
            (key ? 0 : im.rgb[static_cast<std::size_t>(3 * i + c)]));
  }
  CHECK(keyed.translucent >= 1);
}

TEST_CASE("resampling by area: uniform stays uniform, blocks average, factors repeat",
          "[render][image]") {
  // 16 x 16 of 2 x 2 blocks -> 8 x 8: each block's mean, exactly (blocks of one value).
  RgbImage blocks;
  blocks.width = blocks.height = 16;
  for (int r = 0; r < 16; ++r)
    for (int c = 0; c < 16; ++c)
      for (int k = 0; k < 3; ++k)
        blocks.rgb.push_back(static_cast<std::uint8_t>((r / 2) * 30 + (c / 2) * 3 + k));
  const RgbImage small = resample(blocks, 8, 8);
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 8; ++c) CHECK(small.at(c, r)[1] == r * 30 + c * 3 + 1);
  // 2 x 2 -> 6 x 4: each input pixel repeated 3 x 2.
  const RgbImage tiny = random_image(2, 2, 5);
  const RgbImage big = resample(tiny, 6, 4);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 6; ++c) CHECK(big.at(c, r) == tiny.at(c / 3, r / 2));
  // Not a whole factor (5 x 3 -> 2 x 2): a uniform image stays uniform, and the mean of
  // the output equals the input's within rounding.
  RgbImage grey;
  grey.width = 5;
  grey.height = 3;
  grey.rgb.assign(45, 77);
  for (std::uint8_t v : resample(grey, 2, 2).rgb) CHECK(v == 77);
  const RgbImage odd = random_image(5, 3, 11);
  const RgbImage half = resample(odd, 2, 2);
  for (int k = 0; k < 3; ++k) {
    double in = 0, out = 0;
    for (int i = 0; i < 15; ++i) in += odd.rgb[3 * i + k];
    for (int i = 0; i < 4; ++i) out += half.rgb[3 * i + k];
    CHECK(out / 4 == Approx(in / 15).margin(0.5));
  }
}

TEST_CASE("image pixel (c, r) drives pad r x columns + c, 0 to 255 as 0 to 1", "[render][image]") {
  RgbImage im;
  im.width = 8;
  im.height = 8;
  im.rgb.assign(3 * 64, 0);
  im.rgb[3 * (2 * 8 + 3) + 1] = 255;  // pure G (SAI) at column 3, row 2
  im.rgb[3 * (7 * 8 + 0) + 0] = 51;   // R (RA) at 0.2, column 0, row 7
  const PadIntensities p = pad_intensities(im, 8, 8, false);
  REQUIRE(p.value.size() == 64);
  for (std::size_t i = 0; i < 64; ++i) {
    const auto& v = p.value[i];
    if (i == 19) {
      CHECK(v == std::array<double, 3>{0, 1, 0});
    } else if (i == 56) {
      CHECK(v == std::array<double, 3>{0.2, 0, 0});
    } else {
      CHECK(v == std::array<double, 3>{0, 0, 0});
    }
  }
  try {
    pad_intensities(random_image(4, 3, 2), 8, 8, false);
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
    CHECK_THAT(e.what(), Catch::Matchers::StartsWith(
                             "image of 4 x 3 pixels for an array of 8 x 8 pads (columns x rows): "
                             "give --resample"));
  }
  CHECK(pad_intensities(random_image(4, 3, 2), 8, 8, true).value.size() == 64);
}

TEST_CASE("damaged PNGs of every kind are bad input or pixels, never a crash", "[render][image]") {
  // Bytes changed inside a chunk whose CRC is then made right again, so that libpng reads
  // on into the damage (a wrong CRC alone stops it at once).
  auto crc_fixed = [](std::vector<std::uint8_t> png) {
    std::size_t at = 8;
    while (at + 12 <= png.size()) {
      const std::size_t n = (std::size_t{png[at]} << 24) | (std::size_t{png[at + 1]} << 16) |
                            (std::size_t{png[at + 2]} << 8) | png[at + 3];
      if (n > png.size() - at - 12) break;
      std::uint32_t crc = 0xFFFFFFFFu;
      for (std::size_t i = at + 4; i < at + 8 + n; ++i) {
        crc ^= png[i];
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
      }
      crc ^= 0xFFFFFFFFu;
      for (int s = 0; s < 4; ++s)
        png[at + 8 + n + static_cast<std::size_t>(s)] = static_cast<std::uint8_t>(crc >> (24 - 8 * s));
      at += 12 + n;
    }
    return png;
  };
  std::mt19937 rng(12);
  std::vector<std::vector<std::uint8_t>> kinds;
  for (const auto& [type, depth] : {std::pair{PNG_COLOR_TYPE_PALETTE, 4}, {PNG_COLOR_TYPE_GRAY, 1},
                                    {PNG_COLOR_TYPE_GRAY_ALPHA, 16}, {PNG_COLOR_TYPE_RGB_ALPHA, 8}}) {
    PngSpec s;
    s.type = type;
    s.depth = depth;
    s.width = 9;
    s.height = 7;
    s.interlaced = depth == 8;
    const unsigned max = (1u << depth) - 1;
    for (int i = 0; i < 63 * channels_of(type); ++i)
      s.samples.push_back(static_cast<unsigned>(rng() % (max + 1)));
    for (unsigned k = 0; type == PNG_COLOR_TYPE_PALETTE && k <= max; ++k)
      s.palette.push_back({static_cast<png_byte>(k), 0, static_cast<png_byte>(255 - k)});
    kinds.push_back(write_png(s));
  }
  int decoded = 0, refused_n = 0;
  for (int run = 0; run < 2000; ++run) {
    std::vector<std::uint8_t> png = kinds[static_cast<std::size_t>(run) % kinds.size()];
    for (int flips = 1 + static_cast<int>(rng() % 3); flips > 0; --flips)
      png[8 + rng() % (png.size() - 8)] ^= static_cast<std::uint8_t>(1 + rng() % 255);
    if (run % 2) png = crc_fixed(png);
    try {
      const RgbImage im = decode_png(png, "x");
      REQUIRE(im.rgb.size() == 3 * static_cast<std::size_t>(im.width) * im.height);
      ++decoded;
    } catch (const Error& e) {
      REQUIRE(e.code() == ExitCode::bad_input);
      ++refused_n;
    }
  }
  CHECK(refused_n > 0);
  CHECK(decoded > 0);  // some damage is only to values: read as they now are
}
