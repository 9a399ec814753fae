#include <geom/render/image.h>

#include <png.h>

#include <algorithm>
#include <array>
#include <cstring>

namespace geom {

Image::Image(int width, int height, Rgb8 fill) : width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw InvalidArgument("image size must be 1..16384 per side, got " + std::to_string(width) +
                          "x" + std::to_string(height));
  pixels_.assign(static_cast<std::size_t>(width) * height, fill);
}

void Image::blit(const Image& src, int x0, int y0) {
  for (int y = std::max(0, -y0); y < src.height() && y + y0 < height_; ++y)
    for (int x = std::max(0, -x0); x < src.width() && x + x0 < width_; ++x)
      at(x + x0, y + y0) = src.at(x, y);
}

std::vector<std::uint8_t> encode_png(const Image& image) {
  if (image.empty()) throw InvalidArgument("cannot encode an empty image as PNG");
  png_image info;
  std::memset(&info, 0, sizeof(info));
  info.version = PNG_IMAGE_VERSION;
  info.width = static_cast<png_uint_32>(image.width());
  info.height = static_cast<png_uint_32>(image.height());
  info.format = PNG_FORMAT_RGB;
  const void* data = image.pixels().data();
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&info, nullptr, &size, 0, data, 0, nullptr))
    throw Error(std::string("PNG encoding failed: ") + info.message);
  std::vector<std::uint8_t> out(size);
  if (!png_image_write_to_memory(&info, out.data(), &size, 0, data, 0, nullptr))
    throw Error(std::string("PNG encoding failed: ") + info.message);
  out.resize(size);
  return out;
}

Image decode_png(std::span<const std::uint8_t> bytes, const std::string& name) {
  png_image info;
  std::memset(&info, 0, sizeof(info));
  info.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&info, bytes.data(), bytes.size()))
    throw ParseError(name, ParseError::Unit::kNone, 0, std::string("not a PNG: ") + info.message);
  info.format = PNG_FORMAT_RGB;
  if (info.width == 0 || info.height == 0 || info.width > 16384 || info.height > 16384) {
    png_image_free(&info);
    throw ParseError(name, ParseError::Unit::kNone, 0, "PNG size out of range");
  }
  Image image(static_cast<int>(info.width), static_cast<int>(info.height));
  std::vector<std::uint8_t> buffer(PNG_IMAGE_SIZE(info));
  if (!png_image_finish_read(&info, nullptr, buffer.data(), 0, nullptr))
    throw ParseError(name, ParseError::Unit::kNone, 0, std::string("bad PNG: ") + info.message);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const std::uint8_t* p = &buffer[(static_cast<std::size_t>(y) * image.width() + x) * 3];
      image.at(x, y) = {p[0], p[1], p[2]};
    }
  return image;
}

namespace {

// A 5×7 bitmap font drawn for geom: one byte per row, bit 4 is the leftmost pixel.
struct Glyph {
  char c;
  std::array<std::uint8_t, 7> rows;
};
constexpr Glyph kFont[] = {
    {' ', {0, 0, 0, 0, 0, 0, 0}},
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}},
    {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
    {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
    {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}},
    {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}},
    {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}},
    {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
    {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}},
    {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}},
    {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {'.', {0, 0, 0, 0, 0, 0x0C, 0x0C}},
    {',', {0, 0, 0, 0, 0x0C, 0x04, 0x08}},
    {':', {0, 0x0C, 0x0C, 0, 0x0C, 0x0C, 0}},
    {'-', {0, 0, 0, 0x1F, 0, 0, 0}},
    {'_', {0, 0, 0, 0, 0, 0, 0x1F}},
    {'=', {0, 0, 0x1F, 0, 0x1F, 0, 0}},
    {'+', {0, 0x04, 0x04, 0x1F, 0x04, 0x04, 0}},
    {'*', {0, 0x04, 0x15, 0x0E, 0x15, 0x04, 0}},
    {'/', {0x01, 0x02, 0x02, 0x04, 0x08, 0x08, 0x10}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
    {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
    {'#', {0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A}},
    {'|', {0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'?', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04}},
};

const Glyph& glyph(char c) {
  if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  for (const Glyph& g : kFont)
    if (g.c == c) return g;
  return kFont[std::size(kFont) - 1];
}

constexpr int kAdvance = 6;  // 5 pixels and a gap

}  // namespace

int text_width(const std::string& text, int scale) {
  return text.empty() ? 0 : (static_cast<int>(text.size()) * kAdvance - 1) * scale;
}

void draw_text(Image& image, int x, int y, const std::string& text, Rgb8 color, int scale) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const Glyph& g = glyph(text[i]);
    int gx = x + static_cast<int>(i) * kAdvance * scale;
    for (int row = 0; row < 7; ++row)
      for (int col = 0; col < 5; ++col) {
        if (!(g.rows[row] & (0x10 >> col))) continue;
        for (int sy = 0; sy < scale; ++sy)
          for (int sx = 0; sx < scale; ++sx) {
            int px = gx + col * scale + sx, py = y + row * scale + sy;
            if (px >= 0 && py >= 0 && px < image.width() && py < image.height())
              image.at(px, py) = color;
          }
      }
  }
}

Image montage(const std::vector<Image>& images, const std::vector<std::string>& labels,
              const MontageOptions& options) {
  if (images.size() != labels.size())
    throw InvalidArgument("montage: " + std::to_string(images.size()) + " images but " +
                          std::to_string(labels.size()) + " labels");
  if (images.empty()) throw InvalidArgument("montage: no images");
  const int n = static_cast<int>(images.size());
  const int columns = options.columns > 0 ? std::min(options.columns, n) : n;
  const int rows = (n + columns - 1) / columns;
  const int pad = options.padding, label_h = 7 * options.label_scale + pad;
  int cell_w = 0, cell_h = 0;
  for (int i = 0; i < n; ++i) {
    cell_w = std::max({cell_w, images[i].width(), text_width(labels[i], options.label_scale)});
    cell_h = std::max(cell_h, images[i].height());
  }
  Image out(columns * (cell_w + pad) + pad, rows * (cell_h + label_h + pad) + pad,
            options.background);
  for (int i = 0; i < n; ++i) {
    int cx = pad + (i % columns) * (cell_w + pad), cy = pad + (i / columns) * (cell_h + label_h + pad);
    out.blit(images[i], cx + (cell_w - images[i].width()) / 2, cy + (cell_h - images[i].height()) / 2);
    int tw = text_width(labels[i], options.label_scale);
    draw_text(out, cx + (cell_w - tw) / 2, cy + cell_h + pad / 2, labels[i], options.text,
              options.label_scale);
  }
  return out;
}

}  // namespace geom
