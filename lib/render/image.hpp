#pragma once
// Tactile images (issue 23): an 8-bit RGB picture whose channels are the primaries' intensities
// (R = RA, G = SAI, B = PC; 0 to 255 = 0 to 1 of the person's range), read from any PNG
// through libpng (Debian's libpng-dev), and mapped onto a 2-D array's pads: image pixel (column c,
// row r, row 0 at the top) drives the pixel of pad index r x columns + c
// (docs/rendering.md).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tp {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // row-major from the top, 3 bytes a pixel
  // Pixels the file gave as not opaque (alpha, or a transparent colour), composited onto
  // black: said on stderr by the programs that read them.
  std::size_t translucent = 0;
  std::array<std::uint8_t, 3> at(int column, int row) const;
};

// The largest image read, in each dimension (a bound on what a file can make us allocate).
inline constexpr int kMaxImageSide = 4096;

// Decodes any PNG to 8-bit RGB, every value as written (no gamma conversion, whatever a
// gAMA, sRGB or iCCP chunk says): a palette's colours, grey as R = G = B, 16-bit values
// rounded to the nearest of 0 to 255 (v x 255 / 65535), alpha (or a tRNS colour)
// composited onto black (v x alpha / max, so transparent is 0), each rounded once.  Bytes
// that do not decode, truncated ones included, and an image larger than kMaxImageSide a
// side are bad input naming `what` and the problem.
RgbImage decode_png(const std::vector<std::uint8_t>& bytes, const std::string& what);
RgbImage read_png(const std::string& path);  // "-": stdin
// An 8-bit RGB PNG of the image (for tests and figures).
std::vector<std::uint8_t> encode_png(const RgbImage& image);

// Area-weighted resampling to columns x rows: each output pixel is the mean of the input
// over the rectangle it covers (a box filter), so a uniform image stays uniform, a
// downsampling by whole blocks averages each block exactly, and an upsampling by whole
// factors repeats each pixel.  Rounded to the nearest value.
RgbImage resample(const RgbImage& image, int columns, int rows);

// Per pad (index r x columns + c): the RA, SAI and PC intensities, 0 to 1.
struct PadIntensities {
  int columns = 0, rows = 0;
  std::vector<std::array<double, 3>> value;
};
// The image on a columns x rows array: its size must be the array's, unless resample
// (bad input otherwise, naming both sizes).
PadIntensities pad_intensities(const RgbImage& image, int columns, int rows, bool resample);

}  // namespace tp
