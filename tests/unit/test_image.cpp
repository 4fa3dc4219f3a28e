// Tactile images (lib/render/image.hpp): PNG through libpng, exactly, and nothing that is
// not 8-bit RGB; resampling by area; the image-to-pad mapping of issue 23.
#include <catch2/catch.hpp>

#include <cstring>
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

// A PNG of another format, through libpng's simplified writer.
std::vector<std::uint8_t> png_of_format(png_uint_32 format, int w, int h) {
  png_image p;
  std::memset(&p, 0, sizeof p);
  p.version = PNG_IMAGE_VERSION;
  p.width = static_cast<png_uint_32>(w);
  p.height = static_cast<png_uint_32>(h);
  p.format = format;
  std::vector<std::uint8_t> pixels(PNG_IMAGE_SIZE(p), 100);
  std::vector<std::uint8_t> colormap;
  if (format & PNG_FORMAT_FLAG_COLORMAP) {
    p.colormap_entries = 256;
    colormap.assign(PNG_IMAGE_COLORMAP_SIZE(p), 7);
  }
  const void* cmap = colormap.empty() ? nullptr : colormap.data();
  png_alloc_size_t size = 0;
  REQUIRE(png_image_write_get_memory_size(p, size, 0, pixels.data(), 0, cmap));
  std::vector<std::uint8_t> out(size);
  REQUIRE(png_image_write_to_memory(&p, out.data(), &size, 0, pixels.data(), 0, cmap));
  out.resize(size);
  png_image_free(&p);
  return out;
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

TEST_CASE("a PNG that is not 8-bit RGB, or does not decode, is bad input", "[render][image]") {
  refused(png_of_format(PNG_FORMAT_GRAY, 4, 4), "greyscale, expected an 8-bit RGB PNG");
  refused(png_of_format(PNG_FORMAT_RGBA, 4, 4), "RGB with alpha");
  refused(png_of_format(PNG_FORMAT_LINEAR_RGB, 4, 4), "16-bit RGB");
  refused(png_of_format(PNG_FORMAT_RGB_COLORMAP, 4, 4), "a palette image");
  refused({}, "not a PNG file");
  refused({'P', '6', ' ', '4', ' ', '4', ' ', '2', '5', '5'}, "not a PNG file");  // a PPM
  auto good = encode_png(random_image(64, 64, 9));
  auto truncated = good;
  truncated.resize(truncated.size() / 2);
  refused(truncated, "does not decode");
  auto damaged = good;
  damaged[20] ^= 0x5A;  // inside IHDR: its CRC fails
  refused(damaged, "does not decode");
  refused(encode_png(random_image(kMaxImageSide + 1, 1, 3)), "larger than 4096 x 4096");
  // A gamma other than sRGB's would have libpng convert the values: refused.  sRGB's own
  // (1/2.2) is read exactly as written.
  const RgbImage im = random_image(16, 16, 4);
  refused(with_gamma(encode_png(im), 100000), "gAMA chunk gives a gamma of 100000/100000");
  CHECK(decode_png(with_gamma(encode_png(im), 45455), "x").rgb == im.rgb);
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
