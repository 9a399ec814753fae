// PLY writer: binary little-endian (WriteOptions::binary) or ascii. Each group of values
// (positions, normals, texture coordinates, each scalar) is written as float when every value
// in it is exactly a float, else as double, so what was read comes back bit for bit; colours
// as uchar when every component is k/255, else float. Faces with more than 255 corners switch
// the list count to int. Per-corner attributes (OBJ's vt/vn) have no PLY form and are not
// written.

#include <geom/io/formats.h>
#include <geom/io/text.h>

#include <algorithm>
#include <cmath>
#include <span>

namespace geom::io_detail {
namespace {

bool float_exact(double v) { return is_float_exact(v); }

template <class Range>
bool all_float_exact(const Range& values) {
  for (const auto& x : values)
    if (!float_exact(x)) return false;
  return true;
}

bool color_byte_exact(double c) {
  if (!(c >= 0 && c <= 1)) return false;
  return std::round(c * 255.0) / 255.0 == c;
}

struct Column {
  std::string name;
  bool as_float;
  bool as_uchar = false;
  const double* base;  // value of element i: base[i * stride]
  std::size_t stride;
};

void put(std::string& out, const Column& c, std::size_t i, bool binary) {
  const double v = c.base[i * c.stride];
  if (c.as_uchar) {
    const auto b = static_cast<unsigned char>(std::lround(v * 255.0));
    if (binary) out += static_cast<char>(b);
    else append_int(out, b);
  } else if (c.as_float) {
    if (binary) store_le(out, static_cast<float>(v));
    else append_float(out, static_cast<float>(v));
  } else {
    if (binary) store_le(out, v);
    else append_double(out, v);
  }
}

}  // namespace

void write_ply(const PolygonSoup& soup, const WriteOptions& options, std::string& out) {
  const bool binary = options.binary;
  const std::size_t nv = soup.positions.size();
  const std::size_t nf = soup.n_faces();
  std::vector<Column> vcols, fcols;
  auto group = [&](const char* const* names, int dims, const double* base, std::size_t n_values, bool colors) {
    std::span<const double> all(base, n_values);
    const bool f = all_float_exact(all);
    bool u = false;
    if (colors) {
      u = true;
      for (double c : all)
        if (!color_byte_exact(c)) { u = false; break; }
    }
    // base is null for an empty soup; no offset may be applied to it then.
    for (int k = 0; k < dims; ++k)
      vcols.push_back({names[k], f, u, base ? base + k : nullptr, static_cast<std::size_t>(dims)});
  };
  static const char* const kPos[] = {"x", "y", "z"};
  static const char* const kNormal[] = {"nx", "ny", "nz"};
  static const char* const kColor[] = {"red", "green", "blue"};
  static const char* const kTex[] = {"u", "v"};
  group(kPos, 3, nv ? soup.positions[0].data() : nullptr, 3 * nv, false);
  if (options.attributes && nv) {
    if (!soup.vertex_normals.empty()) group(kNormal, 3, soup.vertex_normals[0].data(), 3 * nv, false);
    if (!soup.vertex_colors.empty()) group(kColor, 3, soup.vertex_colors[0].data(), 3 * nv, true);
    if (!soup.vertex_texcoords.empty()) group(kTex, 2, soup.vertex_texcoords[0].data(), 2 * nv, false);
    for (const auto& s : soup.vertex_scalars)
      vcols.push_back({s.name, all_float_exact(s.values), false, s.values.data(), 1});
  }
  if (options.attributes && nf)
    for (const auto& s : soup.face_scalars)
      fcols.push_back({s.name, all_float_exact(s.values), false, s.values.data(), 1});
  std::size_t max_corners = 0;
  for (std::size_t f = 0; f < nf; ++f)
    max_corners = std::max<std::size_t>(max_corners, soup.face_offsets[f + 1] - soup.face_offsets[f]);
  const bool wide_count = max_corners > 255;

  out += "ply\nformat ";
  out += binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
  out += "comment written by geom\nelement vertex ";
  append_int(out, static_cast<std::int64_t>(nv));
  out += '\n';
  auto type_name = [](const Column& c) { return c.as_uchar ? "uchar" : c.as_float ? "float" : "double"; };
  for (const auto& c : vcols) out += std::string("property ") + type_name(c) + " " + c.name + "\n";
  out += "element face ";
  append_int(out, static_cast<std::int64_t>(nf));
  out += wide_count ? "\nproperty list int int vertex_indices\n" : "\nproperty list uchar int vertex_indices\n";
  for (const auto& c : fcols) out += std::string("property ") + type_name(c) + " " + c.name + "\n";
  out += "end_header\n";

  std::size_t vbytes = 0;
  for (const auto& c : vcols) vbytes += c.as_uchar ? 1 : c.as_float ? 4 : 8;
  out.reserve(out.size() + (binary ? nv * vbytes + nf + soup.face_indices.size() * 4 : nv * 40 + nf * 24));
  for (std::size_t v = 0; v < nv; ++v) {
    for (std::size_t k = 0; k < vcols.size(); ++k) {
      if (!binary && k) out += ' ';
      put(out, vcols[k], v, binary);
    }
    if (!binary) out += '\n';
  }
  for (std::size_t f = 0; f < nf; ++f) {
    const std::uint32_t b = soup.face_offsets[f], e = soup.face_offsets[f + 1];
    if (binary) {
      if (wide_count) store_le(out, static_cast<std::int32_t>(e - b));
      else out += static_cast<char>(static_cast<unsigned char>(e - b));
      for (std::uint32_t c = b; c < e; ++c) store_le(out, static_cast<std::int32_t>(soup.face_indices[c]));
    } else {
      append_int(out, e - b);
      for (std::uint32_t c = b; c < e; ++c) {
        out += ' ';
        append_int(out, soup.face_indices[c]);
      }
    }
    for (const auto& c : fcols) {
      if (!binary) out += ' ';
      put(out, c, f, binary);
    }
    if (!binary) out += '\n';
  }
}

}  // namespace geom::io_detail
