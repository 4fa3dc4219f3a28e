#include "render/image.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <png.h>

#include "core/error.hpp"
#include "io/json.hpp"

namespace tp {

std::array<std::uint8_t, 3> RgbImage::at(int column, int row) const {
  const std::size_t k = 3 * (static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
                             static_cast<std::size_t>(column));
  return {rgb[k], rgb[k + 1], rgb[k + 2]};
}

namespace {

// libpng's simplified API (png_image_*): no setjmp here, its errors come back as a 0 and a
// message; the image is freed on every path.
struct PngImage {
  png_image image;
  PngImage() {
    std::memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
  }
  ~PngImage() { png_image_free(&image); }
  PngImage(const PngImage&) = delete;
  PngImage& operator=(const PngImage&) = delete;
};

// What an image that is not 8-bit RGB is instead.
std::string not_rgb(png_uint_32 format) {
  if (format & PNG_FORMAT_FLAG_COLORMAP) return "a palette image";
  if (!(format & PNG_FORMAT_FLAG_COLOR)) return "greyscale";
  if (format & PNG_FORMAT_FLAG_ALPHA) return "RGB with alpha (transparency)";
  if (format & PNG_FORMAT_FLAG_LINEAR) return "16-bit RGB";
  return "";
}

// The file's gamma from its gAMA chunk (x 100000), or 0 without one: the chunks before
// the image data, walked by their lengths.
std::uint32_t file_gamma(const std::vector<std::uint8_t>& b) {
  auto be32 = [&](std::size_t at) {
    return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) |
           (std::uint32_t{b[at + 2]} << 8) | std::uint32_t{b[at + 3]};
  };
  std::size_t at = 8;
  while (at + 12 <= b.size()) {
    const std::uint32_t length = be32(at);
    const char* type = reinterpret_cast<const char*>(b.data() + at + 4);
    if (std::memcmp(type, "IDAT", 4) == 0 || std::memcmp(type, "IEND", 4) == 0) break;
    if (std::memcmp(type, "sRGB", 4) == 0) return 0;  // sRGB: what is read already
    if (std::memcmp(type, "gAMA", 4) == 0 && length == 4 && at + 12 <= b.size())
      return be32(at + 8);
    if (length > b.size() - at - 12) break;  // damaged: libpng says so below
    at += 12 + length;
  }
  return 0;
}

}  // namespace

RgbImage decode_png(const std::vector<std::uint8_t>& bytes, const std::string& what) {
  if (bytes.size() < 8 || png_sig_cmp(bytes.data(), 0, 8) != 0)
    bad_input(what + ": not a PNG file");
  PngImage p;
  if (!png_image_begin_read_from_memory(&p.image, bytes.data(), bytes.size()))
    bad_input(what + ": the PNG does not decode (" + p.image.message + ")");
  const std::string other = not_rgb(p.image.format);
  if (!other.empty()) bad_input(what + ": " + other + ", expected an 8-bit RGB PNG");
  // libpng's simplified reader converts a file whose gamma is not sRGB's (1/2.2, within
  // its 5 % threshold) to sRGB: intensities would not be read as written.
  const std::uint32_t gamma = file_gamma(bytes);
  if (gamma != 0 && (gamma < 43182 || gamma > 47728))
    bad_input(what + ": its gAMA chunk gives a gamma of " + std::to_string(gamma) +
              "/100000, not sRGB's 45455 (1/2.2): its values would be converted; save it "
              "without gAMA, or as sRGB");
  if (p.image.width > static_cast<png_uint_32>(kMaxImageSide) ||
      p.image.height > static_cast<png_uint_32>(kMaxImageSide))
    bad_input(what + ": " + std::to_string(p.image.width) + " x " + std::to_string(p.image.height) +
              " pixels, larger than " + std::to_string(kMaxImageSide) + " x " +
              std::to_string(kMaxImageSide));
  p.image.format = PNG_FORMAT_RGB;
  RgbImage out;
  out.width = static_cast<int>(p.image.width);
  out.height = static_cast<int>(p.image.height);
  out.rgb.assign(PNG_IMAGE_SIZE(p.image), 0);
  if (!png_image_finish_read(&p.image, nullptr, out.rgb.data(), 0, nullptr))
    bad_input(what + ": the PNG does not decode (" + p.image.message + ")");
  return out;
}

RgbImage read_png(const std::string& path) {
  const std::string text = read_input(path, "image", "a PNG file");
  const std::string name = path == "-" ? "image (stdin)" : "image '" + path + "'";
  return decode_png(std::vector<std::uint8_t>(text.begin(), text.end()), name);
}

std::vector<std::uint8_t> encode_png(const RgbImage& image) {
  PngImage p;
  p.image.width = static_cast<png_uint_32>(image.width);
  p.image.height = static_cast<png_uint_32>(image.height);
  p.image.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  if (!png_image_write_get_memory_size(p.image, size, 0, image.rgb.data(), 0, nullptr))
    failure(std::string("cannot encode a PNG: ") + p.image.message);
  std::vector<std::uint8_t> out(size);
  if (!png_image_write_to_memory(&p.image, out.data(), &size, 0, image.rgb.data(), 0, nullptr))
    failure(std::string("cannot encode a PNG: ") + p.image.message);
  out.resize(size);
  return out;
}

RgbImage resample(const RgbImage& in, int columns, int rows) {
  if (in.width < 1 || in.height < 1 ||
      in.rgb.size() != 3 * static_cast<std::size_t>(in.width) * static_cast<std::size_t>(in.height))
    bad_input("resample: an empty or inconsistent image");
  if (columns < 1 || rows < 1 || columns > kMaxImageSide || rows > kMaxImageSide)
    bad_input("resample: " + std::to_string(columns) + " x " + std::to_string(rows) +
              " outside 1 to " + std::to_string(kMaxImageSide) + " a side");
  RgbImage out;
  out.width = columns;
  out.height = rows;
  out.rgb.assign(3 * static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows), 0);
  // Output pixel (c, r) covers [c W / C, (c + 1) W / C) x [r H / R, (r + 1) H / R) of the
  // input; in units of 1 / (C R) of an input pixel everything is an integer.
  const long W = in.width, H = in.height, C = columns, R = rows;
  for (long r = 0; r < R; ++r)
    for (long c = 0; c < C; ++c) {
      const long x0 = c * W, x1 = (c + 1) * W;  // in units of 1 / C
      const long y0 = r * H, y1 = (r + 1) * H;  // in units of 1 / R
      double sum[3] = {0, 0, 0};
      for (long y = y0 / R; y * R < y1; ++y) {
        const long wy = std::min(y1, (y + 1) * R) - std::max(y0, y * R);
        for (long x = x0 / C; x * C < x1; ++x) {
          const long wx = std::min(x1, (x + 1) * C) - std::max(x0, x * C);
          const auto v = in.at(static_cast<int>(x), static_cast<int>(y));
          for (int k = 0; k < 3; ++k) sum[k] += static_cast<double>(wx * wy) * v[k];
        }
      }
      const double area = static_cast<double>(W * H);  // the covered area, same units
      for (int k = 0; k < 3; ++k)
        out.rgb[3 * static_cast<std::size_t>(r * C + c) + static_cast<std::size_t>(k)] =
            static_cast<std::uint8_t>(std::lround(sum[k] / area));
    }
  return out;
}

PadIntensities pad_intensities(const RgbImage& image, int columns, int rows, bool resample_it) {
  if (columns < 1 || rows < 1) bad_input("the array has no pads");
  const bool same = image.width == columns && image.height == rows;
  if (!same && !resample_it)
    bad_input("image of " + std::to_string(image.width) + " x " + std::to_string(image.height) +
              " pixels for an array of " + std::to_string(columns) + " x " + std::to_string(rows) +
              " pads (columns x rows): give --resample, or an image of "
              "that size");
  const RgbImage img = same ? image : resample(image, columns, rows);
  PadIntensities p;
  p.columns = columns;
  p.rows = rows;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      const auto v = img.at(c, r);
      p.value.push_back({v[0] / 255.0, v[1] / 255.0, v[2] / 255.0});
    }
  return p;
}

}  // namespace tp
