// STL, ascii and binary. Binary is recognised by its size (84 + 50 n bytes for the n
// triangles its header announces), not by the word "solid", which many binary exporters put
// in their 80-byte header. Corners with exactly equal coordinates are welded into one
// vertex on reading (-0 and +0 count as equal), so the soup has the file's real topology;
// facet normals are recomputed by the writer and not read.
//
// Writing: faces with more than three corners are split into fans; binary stores float32
// (positions that are not floats are rounded, as the format demands); ascii writes the
// shortest decimal that reads back as the exact double.

#include <geom/io/formats.h>
#include <geom/io/text.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>

namespace geom::io_detail {
namespace {

/// Open-addressing map from exact coordinates to a vertex index.
class Welder {
 public:
  Welder(PolygonSoup& soup, std::size_t expected_corners) : soup_(soup) {
    std::size_t cap = 16;
    while (cap < 2 * expected_corners) cap *= 2;
    slots_.assign(cap, kEmpty);
    soup_.positions.reserve(expected_corners / 4 + 16);
  }

  std::uint32_t vertex(const Point& p) {
    const Point q = p + Point::Zero();  // turns -0 into +0 so both hash alike
    std::uint64_t h = 1469598103934665603ull;
    for (int k = 0; k < 3; ++k) {
      h ^= std::bit_cast<std::uint64_t>(q[k]);
      h *= 1099511628211ull;
      h ^= h >> 29;
    }
    std::size_t mask = slots_.size() - 1;
    std::size_t i = static_cast<std::size_t>(h) & mask;
    for (;;) {
      const std::uint32_t s = slots_[i];
      if (s == kEmpty) break;
      if (soup_.positions[s] == q) return s;
      i = (i + 1) & mask;
    }
    const auto v = static_cast<std::uint32_t>(soup_.positions.size());
    soup_.positions.push_back(q);
    slots_[i] = v;
    if (2 * soup_.positions.size() > slots_.size()) grow();
    return v;
  }

 private:
  void grow() {
    std::vector<std::uint32_t> old(slots_.size() * 2, kEmpty);
    old.swap(slots_);
    std::vector<std::uint32_t> all(soup_.positions.size());
    for (std::uint32_t v = 0; v < all.size(); ++v) all[v] = v;
    const std::size_t mask = slots_.size() - 1;
    for (std::uint32_t v : all) {
      const Point& q = soup_.positions[v];
      std::uint64_t h = 1469598103934665603ull;
      for (int k = 0; k < 3; ++k) {
        h ^= std::bit_cast<std::uint64_t>(q[k]);
        h *= 1099511628211ull;
        h ^= h >> 29;
      }
      std::size_t i = static_cast<std::size_t>(h) & mask;
      while (slots_[i] != kEmpty) i = (i + 1) & mask;
      slots_[i] = v;
    }
  }
  static constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();
  PolygonSoup& soup_;
  std::vector<std::uint32_t> slots_;
};

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != b[i]) return false;
  return true;
}

PolygonSoup read_binary(std::span<const std::byte> data, const std::string& name, std::uint32_t n) {
  ByteCursor in(data, name);
  PolygonSoup soup;
  Welder weld(soup, 3ull * n);
  soup.face_offsets.reserve(n + 1ull);
  soup.face_indices.reserve(3ull * n);
  soup.face_offsets.push_back(0);
  in.seek(84);
  for (std::uint32_t t = 0; t < n; ++t) {
    const unsigned char* p = in.ptr() + 12;
    for (int c = 0; c < 3; ++c) {
      Point x(load_le<float>(p + 12 * c), load_le<float>(p + 12 * c + 4), load_le<float>(p + 12 * c + 8));
      if (!x.allFinite()) in.fail_at(in.pos() + 12 + 12 * c, "vertex coordinate is NaN or infinite");
      soup.face_indices.push_back(weld.vertex(x));
    }
    soup.face_offsets.push_back(static_cast<std::uint32_t>(soup.face_indices.size()));
    in.skip(50);
  }
  if (n == 0) soup.face_offsets.clear();
  return soup;
}

PolygonSoup read_ascii(std::span<const std::byte> data, const std::string& name) {
  TextCursor in(data, name);
  PolygonSoup soup;
  Welder weld(soup, std::min<std::size_t>(data.size() / 64 + 16, std::size_t{1} << 24));
  soup.face_offsets.push_back(0);
  auto expect = [&](const char* kw) {
    in.skip_space(false);
    const std::string_view w = in.word();
    if (!iequals(w, kw))
      in.fail(std::string("expected '") + kw + "', found '" + TextCursor::printable(w.substr(0, 32)) + "'");
  };
  expect("solid");
  in.skip_line();  // the solid's name
  for (;;) {
    in.skip_space(false);
    if (in.at_end()) in.fail("file ends without 'endsolid'");
    const std::string_view w = in.word();
    if (iequals(w, "endsolid")) {
      in.skip_line();
      in.skip_space(false);
      if (in.at_end()) break;
      expect("solid");  // several solids in one file
      in.skip_line();
      continue;
    }
    if (!iequals(w, "facet"))
      in.fail("expected 'facet' or 'endsolid', found '" + TextCursor::printable(w.substr(0, 32)) + "'");
    expect("normal");
    for (int k = 0; k < 3; ++k) in.number("facet normal component");
    expect("outer");
    expect("loop");
    std::size_t corners = 0;
    for (;;) {
      in.skip_space(false);
      const std::string_view k = in.word();
      if (iequals(k, "endloop")) break;
      if (!iequals(k, "vertex"))
        in.fail("expected 'vertex' or 'endloop', found '" + TextCursor::printable(k.substr(0, 32)) + "'");
      Point x;
      for (int c = 0; c < 3; ++c) x[c] = in.number("vertex coordinate");
      if (!x.allFinite()) in.fail("vertex coordinate is NaN or infinite");
      soup.face_indices.push_back(weld.vertex(x));
      ++corners;
    }
    if (corners < 3) in.fail("facet with " + std::to_string(corners) + " vertices");
    expect("endfacet");
    if (soup.face_indices.size() > std::numeric_limits<std::uint32_t>::max()) in.fail("too many corners");
    soup.face_offsets.push_back(static_cast<std::uint32_t>(soup.face_indices.size()));
  }
  if (soup.face_offsets.size() == 1) soup.face_offsets.clear();
  return soup;
}

Normal facet_normal(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c) {
  const Eigen::Vector3f n = (b - a).cross(c - a);
  const float len = n.norm();
  return len > 0 && std::isfinite(len) ? Normal((n / len).cast<double>()) : Normal::Zero();
}

}  // namespace

PolygonSoup read_stl(std::span<const std::byte> data, const std::string& name) {
  if (data.size() >= 84) {
    std::uint32_t n;
    std::memcpy(&n, data.data() + 80, 4);
    if (data.size() == 84 + 50ull * n) return read_binary(data, name, n);
  }
  std::size_t i = 0;
  const auto* c = reinterpret_cast<const char*>(data.data());
  while (i < data.size() && std::isspace(static_cast<unsigned char>(c[i]))) ++i;
  if (data.size() - i >= 5 && iequals(std::string_view(c + i, 5), "solid")) {
    // A binary file whose header starts with "solid" but whose size is off is still
    // reported as binary when it is not text.
    bool text = true;
    for (std::size_t k = i; k < std::min<std::size_t>(data.size(), i + 512); ++k)
      if (c[k] == 0) text = false;
    if (text) return read_ascii(data, name);
  }
  if (data.size() < 84)
    throw ParseError(name, ParseError::Unit::kByte, data.size(),
                     "file too short for binary STL (84-byte header) and not ascii STL");
  std::uint32_t n;
  std::memcpy(&n, data.data() + 80, 4);
  throw ParseError(name, ParseError::Unit::kByte, 80,
                   "binary STL header announces " + std::to_string(n) + " triangles (" +
                       std::to_string(84 + 50ull * n) + " bytes) but the file has " + std::to_string(data.size()) +
                       " bytes");
}

void write_stl(const PolygonSoup& soup, const WriteOptions& options, std::string& out) {
  std::vector<std::array<std::uint32_t, 3>> tris;
  tris.reserve(soup.face_indices.size());
  for (std::size_t f = 0; f < soup.n_faces(); ++f) {
    const auto face = soup.face(f);
    for (std::size_t k = 2; k < face.size(); ++k) tris.push_back({face[0], face[k - 1], face[k]});
  }
  if (tris.size() > std::numeric_limits<std::uint32_t>::max())
    throw InvalidArgument("too many triangles for STL");
  if (options.binary) {
    std::string header = "binary STL written by geom";
    header.resize(80, ' ');
    out.reserve(84 + 50 * tris.size());
    out += header;
    store_le(out, static_cast<std::uint32_t>(tris.size()));
    for (const auto& t : tris) {
      Eigen::Vector3f p[3];
      for (int c = 0; c < 3; ++c) p[c] = soup.positions[t[c]].cast<float>();
      const Normal n = facet_normal(p[0], p[1], p[2]);
      for (int k = 0; k < 3; ++k) store_le(out, static_cast<float>(n[k]));
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) store_le(out, p[c][k]);
      store_le(out, std::uint16_t{0});
    }
    return;
  }
  out += "solid geom\n";
  for (const auto& t : tris) {
    const Normal n = facet_normal(soup.positions[t[0]].cast<float>(), soup.positions[t[1]].cast<float>(),
                                  soup.positions[t[2]].cast<float>());
    out += "facet normal";
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_float(out, static_cast<float>(n[k]));
    }
    out += "\n outer loop\n";
    for (int c = 0; c < 3; ++c) {
      out += "  vertex";
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        append_double(out, soup.positions[t[c]][k]);
      }
      out += '\n';
    }
    out += " endloop\nendfacet\n";
  }
  out += "endsolid geom\n";
}

}  // namespace geom::io_detail
