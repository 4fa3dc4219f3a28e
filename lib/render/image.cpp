#include "render/image.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <png.h>

#include "core/error.hpp"
#include "core/json.hpp"

namespace tp {

std::array<std::uint8_t, 3> RgbImage::at(int column, int row) const {
  const std::size_t k = 3 * (static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
                             static_cast<std::size_t>(column));
  return {rgb[k], rgb[k + 1], rgb[k + 2]};
}

namespace {

// libpng's simplified API (png_image_*), for writing: no setjmp here, its errors come
// back as a 0 and a message; the image is freed on every path.
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

// Reading goes through libpng's own API, which changes no value unless asked (the
// simplified reader would convert 16-bit and gamma-tagged files).  Its errors longjmp back
// to the setjmp in read_header or read_rows; those two hold no C++ object of their own, so
// nothing is skipped, and the structs are freed by PngReader's destructor on every path.
struct PngReader {
  png_structp png = nullptr;
  png_infop info = nullptr;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0, at = 0;
  char message[200] = "";
  ~PngReader() { png_destroy_read_struct(&png, &info, nullptr); }
};

[[noreturn]] void on_png_error(png_structp png, png_const_charp text) {
  auto* r = static_cast<PngReader*>(png_get_error_ptr(png));
  std::snprintf(r->message, sizeof r->message, "%s", text);
  png_longjmp(png, 1);
}
void on_png_warning(png_structp, png_const_charp) {}  // ancillary trouble: not ours to say

void on_png_read(png_structp png, png_bytep out, std::size_t n) {
  auto* r = static_cast<PngReader*>(png_get_io_ptr(png));
  if (n > r->size - r->at) png_error(png, "truncated: the file ends early");
  std::memcpy(out, r->data + r->at, n);
  r->at += n;
}

// The file's header, and the transforms to 8- or 16-bit RGB, or RGBA where the file has
// alpha or a transparent colour (tRNS): palettes and greys expanded, nothing else changed.
struct PngShape {
  png_uint_32 width = 0, height = 0;
  int channels = 0, depth = 0;  // after the transforms: 3 or 4, 8 or 16
  std::size_t row_bytes = 0;
};
bool read_header(PngReader& r, PngShape& s) {
  if (setjmp(png_jmpbuf(r.png))) return false;
  png_set_read_fn(r.png, &r, on_png_read);
  png_read_info(r.png, r.info);
  s.width = png_get_image_width(r.png, r.info);
  s.height = png_get_image_height(r.png, r.info);
  if (s.width > static_cast<png_uint_32>(kMaxImageSide) ||
      s.height > static_cast<png_uint_32>(kMaxImageSide))
    return true;  // refused by the caller, before anything is allocated
  const int type = png_get_color_type(r.png, r.info);
  if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(r.png);
  if (type == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(r.png, r.info) < 8)
    png_set_expand_gray_1_2_4_to_8(r.png);
  if (png_get_valid(r.png, r.info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(r.png);
  if (!(type & PNG_COLOR_MASK_COLOR)) png_set_gray_to_rgb(r.png);
  png_set_interlace_handling(r.png);
  png_read_update_info(r.png, r.info);
  s.channels = png_get_channels(r.png, r.info);
  s.depth = png_get_bit_depth(r.png, r.info);
  s.row_bytes = png_get_rowbytes(r.png, r.info);
  return true;
}
bool read_rows(PngReader& r, png_bytepp rows) {
  if (setjmp(png_jmpbuf(r.png))) return false;
  png_read_image(r.png, rows);
  png_read_end(r.png, nullptr);  // the rest: a file cut after its pixels is refused too
  return true;
}

// The 8- or 16-bit RGB(A) rows as 8-bit RGB: alpha composited onto black (v a / max), each
// value rounded once to the nearest of 0 to 255.  Returns how many pixels were not opaque.
std::size_t to_rgb8(const std::vector<std::uint8_t>& raw, const PngShape& s, RgbImage& out) {
  const std::uint64_t max = s.depth == 16 ? 65535 : 255;
  const std::uint64_t whole = s.channels == 4 ? max * max : max;  // v a, or v, at full scale
  auto value = [&](const std::uint8_t* p, int k) -> std::uint64_t {
    return s.depth == 16 ? (std::uint64_t{p[2 * k]} << 8) | p[2 * k + 1] : p[k];
  };
  std::size_t translucent = 0;
  for (png_uint_32 y = 0; y < s.height; ++y)
    for (png_uint_32 x = 0; x < s.width; ++x) {
      const std::uint8_t* p =
          raw.data() + y * s.row_bytes +
          static_cast<std::size_t>(x) * static_cast<std::size_t>(s.channels) * (s.depth / 8);
      const std::uint64_t alpha = s.channels == 4 ? value(p, 3) : 1;
      translucent += s.channels == 4 && alpha != max;
      for (int k = 0; k < 3; ++k)
        out.rgb[3 * (static_cast<std::size_t>(y) * s.width + x) + static_cast<std::size_t>(k)] =
            static_cast<std::uint8_t>((value(p, k) * alpha * 255 + whole / 2) / whole);
    }
  return translucent;
}

}  // namespace

RgbImage decode_png(const std::vector<std::uint8_t>& bytes, const std::string& what) {
  if (bytes.size() < 8 || png_sig_cmp(bytes.data(), 0, 8) != 0)
    bad_input(what + ": not a PNG file");
  PngReader r;
  r.data = bytes.data();
  r.size = bytes.size();
  r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r, on_png_error, on_png_warning);
  if (r.png) r.info = png_create_info_struct(r.png);
  if (!r.png || !r.info) failure("cannot start libpng's reader (out of memory)");
  PngShape s;
  if (!read_header(r, s)) bad_input(what + ": the PNG does not decode (" + r.message + ")");
  if (s.width > static_cast<png_uint_32>(kMaxImageSide) ||
      s.height > static_cast<png_uint_32>(kMaxImageSide))
    bad_input(what + ": " + std::to_string(s.width) + " x " + std::to_string(s.height) +
              " pixels, larger than " + std::to_string(kMaxImageSide) + " x " +
              std::to_string(kMaxImageSide));
  std::vector<std::uint8_t> raw(s.row_bytes * s.height);
  std::vector<png_bytep> rows(s.height);
  for (png_uint_32 y = 0; y < s.height; ++y) rows[y] = raw.data() + y * s.row_bytes;
  if (!read_rows(r, rows.data())) bad_input(what + ": the PNG does not decode (" + r.message + ")");
  RgbImage out;
  out.width = static_cast<int>(s.width);
  out.height = static_cast<int>(s.height);
  out.rgb.assign(3 * static_cast<std::size_t>(s.width) * s.height, 0);
  out.translucent = to_rgb8(raw, s, out);
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
