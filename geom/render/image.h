#pragma once
/// \file
/// An 8-bit RGB image, PNG encoding, text labels and side-by-side montages.

#include <geom/core/errors.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace geom {

struct Rgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb8&) const = default;
};

/// Row-major RGB image, top row first.
class Image {
 public:
  Image() = default;
  /// Throws: InvalidArgument for non-positive or absurd sizes (> 16384 per side).
  Image(int width, int height, Rgb8 fill = {});
  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return width_ == 0 || height_ == 0; }
  Rgb8& at(int x, int y) { return pixels_[static_cast<std::size_t>(y) * width_ + x]; }
  const Rgb8& at(int x, int y) const { return pixels_[static_cast<std::size_t>(y) * width_ + x]; }
  std::span<const Rgb8> pixels() const { return pixels_; }
  /// Copy `src` with its top-left corner at (x, y), clipped to this image.
  void blit(const Image& src, int x, int y);

 private:
  int width_ = 0, height_ = 0;
  std::vector<Rgb8> pixels_;
};

/// PNG bytes of the image (8-bit RGB). Throws: Error when libpng fails.
std::vector<std::uint8_t> encode_png(const Image& image);
/// Decode PNG bytes to RGB (alpha dropped, 16-bit reduced). Throws: ParseError when the
/// bytes are not a PNG.
Image decode_png(std::span<const std::uint8_t> bytes, const std::string& name = "<memory>");

/// Draw text with the built-in 5×7 font at (x, y) (top-left), each font pixel scale×scale.
/// Letters are drawn upper-case; characters without a glyph draw as '?'.
void draw_text(Image& image, int x, int y, const std::string& text, Rgb8 color, int scale = 1);
/// Width in pixels that draw_text would use.
int text_width(const std::string& text, int scale = 1);

struct MontageOptions {
  int columns = 0;  ///< 0: all in one row
  int padding = 12;
  int label_scale = 2;
  Rgb8 background{255, 255, 255};
  Rgb8 text{20, 20, 20};
};

/// Lay images out in a grid, each with its label underneath (labels may be empty).
/// Throws: InvalidArgument when labels and images differ in number.
Image montage(const std::vector<Image>& images, const std::vector<std::string>& labels,
              const MontageOptions& options = {});

}  // namespace geom
