#include <geom/io/grid.h>

#include <geom/core/errors.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cctype>
#include <cstring>
#include <fstream>
#include <limits>

namespace geom {

namespace {

struct Dtype {
  char kind = 'f';   ///< f, i, u, b
  int size = 4;      ///< bytes
  bool big = false;  ///< big-endian
  std::string text;
};

/// Parse NumPy's type string; nullopt-like: size 0 when unsupported.
bool parse_dtype(std::string s, Dtype& out) {
  out.text = s;
  out.big = false;
  if (!s.empty() && (s[0] == '<' || s[0] == '>' || s[0] == '|' || s[0] == '=')) {
    out.big = s[0] == '>';
    s = s.substr(1);
  }
  if (s.size() != 2) return false;
  out.kind = s[0];
  out.size = s[1] - '0';
  switch (out.kind) {
    case 'f': return out.size == 2 || out.size == 4 || out.size == 8;
    case 'i':
    case 'u': return out.size == 1 || out.size == 2 || out.size == 4 || out.size == 8;
    case 'b': return out.size == 1;
    default: return false;
  }
}

bool wants_double(const Dtype& d) {
  return (d.kind == 'f' && d.size == 8) || ((d.kind == 'i' || d.kind == 'u') && d.size >= 4);
}

float half_to_float(std::uint16_t h) {
  const int sign = h >> 15, exp = (h >> 10) & 0x1f, mant = h & 0x3ff;
  float v;
  if (exp == 0)
    v = std::ldexp(float(mant), -24);
  else if (exp == 31)
    v = mant ? std::numeric_limits<float>::quiet_NaN() : std::numeric_limits<float>::infinity();
  else
    v = std::ldexp(float(mant | 0x400), exp - 25);
  return sign ? -v : v;
}

double decode(const unsigned char* p, const Dtype& d) {
  unsigned char b[8];
  std::memcpy(b, p, d.size);
  if (d.big) std::reverse(b, b + d.size);
  auto load = [&](auto tag) {
    decltype(tag) v;
    std::memcpy(&v, b, sizeof v);
    return v;
  };
  switch (d.kind) {
    case 'b': return b[0] != 0;
    case 'f':
      if (d.size == 2) return half_to_float(load(std::uint16_t{}));
      if (d.size == 4) return load(float{});
      return load(double{});
    case 'i':
      if (d.size == 1) return load(std::int8_t{});
      if (d.size == 2) return load(std::int16_t{});
      if (d.size == 4) return load(std::int32_t{});
      return double(load(std::int64_t{}));
    default:
      if (d.size == 1) return load(std::uint8_t{});
      if (d.size == 2) return load(std::uint16_t{});
      if (d.size == 4) return load(std::uint32_t{});
      return double(load(std::uint64_t{}));
  }
}

/// Decode samples stored in file order (dims slow → fast) into x-fastest order, where
/// dest_stride[a] is the destination step of file axis a.
void decode_into(GridData& g, const unsigned char* src, const Dtype& d,
                 std::array<std::size_t, 3> file_dims, std::array<std::size_t, 3> dest_stride) {
  const std::size_t n = g.nx * g.ny * g.nz;
  const bool identity = dest_stride[2] == 1 && dest_stride[1] == file_dims[2] &&
                        dest_stride[0] == file_dims[1] * file_dims[2];
  g.is_double = wants_double(d);
  if (g.is_double)
    g.doubles.resize(n);
  else
    g.floats.resize(n);
  const bool native = !d.big && d.kind == 'f' && (d.size == 4 || d.size == 8);
  if (n == 0) return;  // a zero in the shape: nothing to copy (and memcpy of no bytes to a null)
  if (identity && native) {
    std::memcpy(g.is_double ? static_cast<void*>(g.doubles.data()) : static_cast<void*>(g.floats.data()), src,
                n * d.size);
    return;
  }
  std::size_t i = 0;
  for (std::size_t a = 0; a < file_dims[0]; ++a)
    for (std::size_t b = 0; b < file_dims[1]; ++b)
      for (std::size_t c = 0; c < file_dims[2]; ++c, ++i) {
        std::size_t dst = a * dest_stride[0] + b * dest_stride[1] + c * dest_stride[2];
        double v = decode(src + i * d.size, d);
        if (g.is_double)
          g.doubles[dst] = v;
        else
          g.floats[dst] = static_cast<float>(v);
      }
}

std::vector<std::byte> read_file(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error("cannot open " + path.string() + " for reading");
  f.seekg(0, std::ios::end);
  std::streamoff size = f.tellg();
  f.seekg(0);
  std::vector<std::byte> data(static_cast<std::size_t>(size));
  f.read(reinterpret_cast<char*>(data.data()), size);
  if (!f) throw Error("cannot read " + path.string());
  return data;
}

/// The value text after 'key': in a NumPy header dict, or empty when absent.
std::string header_value(const std::string& h, const std::string& key) {
  std::size_t k = h.find("'" + key + "'");
  if (k == std::string::npos) return {};
  std::size_t colon = h.find(':', k);
  if (colon == std::string::npos) return {};
  std::size_t start = colon + 1;
  while (start < h.size() && h[start] == ' ') ++start;
  if (start >= h.size()) return {};
  if (h[start] == '(') {
    std::size_t end = h.find(')', start);
    return end == std::string::npos ? std::string() : h.substr(start, end - start + 1);
  }
  if (h[start] == '\'') {
    std::size_t end = h.find('\'', start + 1);
    return end == std::string::npos ? std::string() : h.substr(start + 1, end - start - 1);
  }
  std::size_t end = h.find_first_of(",}", start);
  return h.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

}  // namespace

GridData read_npy(std::span<const std::byte> data, const std::string& name) {
  auto fail = [&](std::uint64_t at, const std::string& what) -> ParseError {
    return ParseError(name, ParseError::Unit::kByte, at, what);
  };
  const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
  if (data.size() < 10 || std::memcmp(bytes, "\x93NUMPY", 6) != 0)
    throw fail(0, "expected the .npy magic \\x93NUMPY");
  const int major = bytes[6];
  std::size_t header_len, header_start;
  if (major == 1) {
    header_len = bytes[8] | std::size_t(bytes[9]) << 8;
    header_start = 10;
  } else if (major == 2 || major == 3) {
    if (data.size() < 12) throw fail(8, "truncated .npy header length");
    header_len = bytes[8] | std::size_t(bytes[9]) << 8 | std::size_t(bytes[10]) << 16 |
                 std::size_t(bytes[11]) << 24;
    header_start = 12;
  } else {
    throw fail(6, "unsupported .npy version " + std::to_string(major) + " (expected 1, 2 or 3)");
  }
  if (header_len > data.size() - header_start)
    throw fail(8, "header length " + std::to_string(header_len) + " exceeds the file");
  const std::string header(reinterpret_cast<const char*>(bytes + header_start), header_len);

  Dtype dtype;
  std::string descr = header_value(header, "descr");
  if (descr.empty()) throw fail(header_start, "header has no 'descr'");
  if (!parse_dtype(descr, dtype))
    throw fail(header_start, "unsupported dtype '" + descr + "' (expected float, int, uint or bool)");
  std::string order = header_value(header, "fortran_order");
  if (order.find("True") == std::string::npos && order.find("False") == std::string::npos)
    throw fail(header_start, "header has no valid 'fortran_order'");
  const bool fortran = order.find("True") != std::string::npos;
  std::string shape_text = header_value(header, "shape");
  if (shape_text.size() < 2 || shape_text.front() != '(')
    throw fail(header_start, "header has no valid 'shape'");
  std::vector<std::size_t> shape;
  {
    std::string inner = shape_text.substr(1, shape_text.size() - 2);
    std::size_t pos = 0;
    while (pos < inner.size()) {
      while (pos < inner.size() && (inner[pos] == ' ' || inner[pos] == ',')) ++pos;
      if (pos >= inner.size()) break;
      std::size_t end = pos;
      while (end < inner.size() && std::isdigit(static_cast<unsigned char>(inner[end]))) ++end;
      if (end == pos || end - pos > 15) throw fail(header_start, "bad shape " + shape_text);
      shape.push_back(std::stoull(inner.substr(pos, end - pos)));
      pos = end;
      while (pos < inner.size() && (inner[pos] == 'L' || inner[pos] == ' ')) ++pos;
      if (pos < inner.size() && inner[pos] != ',') throw fail(header_start, "bad shape " + shape_text);
    }
  }
  if (shape.empty() || shape.size() > 3)
    throw fail(header_start, "expected a 1-, 2- or 3-D array, shape is " + shape_text);
  while (shape.size() < 3) shape.insert(shape.begin(), 1);

  const std::size_t data_start = header_start + header_len;
  const std::size_t available = (data.size() - data_start) / std::size_t(dtype.size);
  // The product first (an axis of 0 makes it 0 however large the others), then the bytes.
  std::size_t count = 1;
  bool overflow = false;
  for (std::size_t s : shape) overflow |= __builtin_mul_overflow(count, s, &count);
  if (count != 0 && (overflow || count > available))
    throw fail(data_start, "shape " + shape_text + " needs more samples than the " +
                               std::to_string(available) + " the file holds");
  GridData g;
  g.dtype = descr;
  g.nz = shape[0];
  g.ny = shape[1];
  g.nx = shape[2];
  if (fortran)  // file order: axis 2 slowest … axis 0 fastest
    decode_into(g, bytes + data_start, dtype, {shape[2], shape[1], shape[0]},
                {1, shape[2], shape[1] * shape[2]});
  else
    decode_into(g, bytes + data_start, dtype, {shape[0], shape[1], shape[2]},
                {shape[1] * shape[2], shape[2], 1});
  return g;
}

GridData read_npy(const std::filesystem::path& path) {
  std::vector<std::byte> data = read_file(path);
  return read_npy(data, path.string());
}

namespace {

template <class T>
void write_npy_impl(const std::filesystem::path& path, std::size_t nx, std::size_t ny,
                    std::size_t nz, std::span<const T> values, const char* descr) {
  if (values.size() != nx * ny * nz)
    throw InvalidArgument("write_npy: " + std::to_string(nx) + "×" + std::to_string(ny) + "×" +
                          std::to_string(nz) + " needs " + std::to_string(nx * ny * nz) +
                          " values, got " + std::to_string(values.size()));
  std::string header = std::string("{'descr': '") + descr + "', 'fortran_order': False, 'shape': (" +
                       std::to_string(nz) + ", " + std::to_string(ny) + ", " + std::to_string(nx) +
                       "), }";
  // Pad so the data starts on a 64-byte boundary, ending the header with '\n'.
  std::size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header.push_back('\n');
  std::ofstream f(path, std::ios::binary);
  if (!f) throw Error("cannot open " + path.string() + " for writing");
  const unsigned char len[2] = {static_cast<unsigned char>(header.size() & 0xff),
                                static_cast<unsigned char>(header.size() >> 8)};
  f.write("\x93NUMPY\x01\x00", 8);
  f.write(reinterpret_cast<const char*>(len), 2);
  f.write(header.data(), static_cast<std::streamsize>(header.size()));
  f.write(reinterpret_cast<const char*>(values.data()),
          static_cast<std::streamsize>(values.size() * sizeof(T)));
  if (!f) throw Error("cannot write " + path.string());
}

}  // namespace

void write_npy(const std::filesystem::path& path, std::size_t nx, std::size_t ny, std::size_t nz,
               std::span<const float> values) {
  write_npy_impl(path, nx, ny, nz, values, "<f4");
}

void write_npy(const std::filesystem::path& path, std::size_t nx, std::size_t ny, std::size_t nz,
               std::span<const double> values) {
  write_npy_impl(path, nx, ny, nz, values, "<f8");
}

GridData read_raw(const std::filesystem::path& path, const RawGridOptions& o) {
  Dtype dtype;
  if (!parse_dtype(o.dtype, dtype))
    throw InvalidArgument("unsupported raw dtype '" + o.dtype + "' (expected e.g. f4, <f8, u1, >i2)");
  if (o.nx == 0 || o.ny == 0 || o.nz == 0)
    throw InvalidArgument("raw grid dimensions must be positive");
  std::vector<std::byte> data = read_file(path);
  const std::size_t available =
      data.size() > o.offset ? (data.size() - o.offset) / std::size_t(dtype.size) : 0;
  if (o.nx > available || o.ny > available || o.nz > available || o.nx * o.ny > available ||
      o.nx * o.ny * o.nz > available)
    throw ParseError(path.string(), ParseError::Unit::kByte, data.size(),
                     "file holds " + std::to_string(available) + " samples after offset " +
                         std::to_string(o.offset) + ", grid needs " +
                         std::to_string(o.nx) + "×" + std::to_string(o.ny) + "×" +
                         std::to_string(o.nz));
  GridData g;
  g.nx = o.nx;
  g.ny = o.ny;
  g.nz = o.nz;
  g.dtype = o.dtype;
  const auto* src = reinterpret_cast<const unsigned char*>(data.data()) + o.offset;
  if (o.z_fastest)
    decode_into(g, src, dtype, {o.nx, o.ny, o.nz}, {1, o.nx, o.nx * o.ny});
  else
    decode_into(g, src, dtype, {o.nz, o.ny, o.nx}, {o.nx * o.ny, o.nx, 1});
  return g;
}

}  // namespace geom
