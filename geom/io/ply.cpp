// PLY (ascii, binary_little_endian, binary_big_endian).
//
// Reading: the "vertex" element's x/y/z become positions, nx/ny/nz normals,
// red/green/blue colours (integer types scaled by the type's maximum, floats as they are),
// u/v, s/t, texture_u/texture_v or texture_s/texture_t texture coordinates, and any other
// scalar property a NamedScalars; the "face" element's vertex_indices (or vertex_index)
// list becomes faces and its other scalar properties NamedScalars. A "tristrips" element's
// vertex_indices (the Stanford scans' form: strips separated by -1) becomes triangles after
// the faces, odd triangles of a strip turned to keep the winding; its triangles with a
// repeated vertex are the stitches between strips, not faces, and are left out (with face
// scalars, strip triangles get 0). Other elements and list properties are skipped in all
// three encodings.
//
// Header lines may end in "\n", "\r\n" or a bare "\r" (old Mac exporters); the first line
// decides, so a binary body after "end_header\r" may begin with a 0x0A byte.
//
// The writer is in ply_write.cpp.

#include <geom/io/formats.h>
#include <geom/io/text.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>

namespace geom::io_detail {
namespace {

enum class Type : std::uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::size_t type_size(Type t) {
  switch (t) {
    case Type::kInt8: case Type::kUint8: return 1;
    case Type::kInt16: case Type::kUint16: return 2;
    case Type::kInt32: case Type::kUint32: case Type::kFloat32: return 4;
    case Type::kFloat64: return 8;
  }
  return 1;
}

bool is_integer_type(Type t) { return t != Type::kFloat32 && t != Type::kFloat64; }

double type_max(Type t) {
  switch (t) {
    case Type::kInt8: return 127;
    case Type::kUint8: return 255;
    case Type::kInt16: return 32767;
    case Type::kUint16: return 65535;
    case Type::kInt32: return 2147483647.0;
    case Type::kUint32: return 4294967295.0;
    default: return 1;
  }
}

std::optional<Type> parse_type(std::string_view s) {
  if (s == "char" || s == "int8") return Type::kInt8;
  if (s == "uchar" || s == "uint8") return Type::kUint8;
  if (s == "short" || s == "int16") return Type::kInt16;
  if (s == "ushort" || s == "uint16") return Type::kUint16;
  if (s == "int" || s == "int32") return Type::kInt32;
  if (s == "uint" || s == "uint32") return Type::kUint32;
  if (s == "float" || s == "float32") return Type::kFloat32;
  if (s == "double" || s == "float64") return Type::kFloat64;
  return std::nullopt;
}

// Where a vertex/face property's values go.
enum class Role : std::uint8_t {
  kSkip, kX, kY, kZ, kNx, kNy, kNz, kRed, kGreen, kBlue, kU, kV, kScalar, kIndices, kStrip
};

struct PlyProperty {
  std::string name;
  Type type = Type::kFloat32;
  bool is_list = false;
  Type count_type = Type::kUint8;
  Role role = Role::kSkip;
  std::size_t scalar = 0;  // index into vertex_scalars / face_scalars
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> props;
  std::uint64_t header_line = 0;
  bool fixed() const {
    for (const auto& p : props)
      if (p.is_list) return false;
    return true;
  }
  std::size_t min_bytes() const {
    std::size_t n = 0;
    for (const auto& p : props) n += p.is_list ? type_size(p.count_type) : type_size(p.type);
    return n;
  }
};

enum class Encoding { kAscii, kLittle, kBig };

Role vertex_role(const std::string& n) {
  if (n == "x") return Role::kX;
  if (n == "y") return Role::kY;
  if (n == "z") return Role::kZ;
  if (n == "nx") return Role::kNx;
  if (n == "ny") return Role::kNy;
  if (n == "nz") return Role::kNz;
  if (n == "red" || n == "r" || n == "diffuse_red") return Role::kRed;
  if (n == "green" || n == "g" || n == "diffuse_green") return Role::kGreen;
  if (n == "blue" || n == "b" || n == "diffuse_blue") return Role::kBlue;
  if (n == "u" || n == "s" || n == "texture_u" || n == "texture_s") return Role::kU;
  if (n == "v" || n == "t" || n == "texture_v" || n == "texture_t") return Role::kV;
  return Role::kScalar;
}

class PlyReader {
 public:
  PlyReader(std::span<const std::byte> data, const std::string& name) : data_(data), name_(name) {}

  PolygonSoup run() {
    // Lines ending in a bare '\r' are read from a copy with '\n' in their place, byte for
    // byte, so offsets and line numbers hold: the header's lines, then an ascii body's.
    const bool cr_lines = bare_cr_lines();
    if (cr_lines) crs_to_newlines(cr_header_size());
    header();
    if (cr_lines && encoding_ == Encoding::kAscii) crs_to_newlines(data_.size());
    if (encoding_ == Encoding::kAscii) {
      TextCursor in(data_, name_);
      in.set_pos(reinterpret_cast<const char*>(data_.data()) + body_);
      in.set_line(body_line_);
      for (std::size_t e = 0; e < elements_.size(); ++e) ascii_element(in, elements_[e], e);
    } else {
      ByteCursor in(data_, name_);
      in.seek(body_);
      for (std::size_t e = 0; e < elements_.size(); ++e) binary_element(in, elements_[e], e);
    }
    append_strip_triangles();
    if (soup_.face_offsets.size() <= 1) soup_.face_offsets.clear();
    return std::move(soup_);
  }

 private:
  /// True when the first line ends in '\r' alone.
  bool bare_cr_lines() const {
    const std::string_view s(reinterpret_cast<const char*>(data_.data()), data_.size());
    const std::size_t eol = s.find_first_of("\r\n");
    return eol != std::string_view::npos && s[eol] == '\r' &&
           (eol + 1 == s.size() || s[eol + 1] != '\n');
  }

  /// With '\r' line ends: the offset just past the "end_header" line's '\r' (the file's size
  /// when there is none), so that a binary body's bytes are never taken for line ends.
  std::size_t cr_header_size() const {
    const std::string_view s(reinterpret_cast<const char*>(data_.data()), data_.size());
    for (std::size_t at = 0, eol; (eol = s.find('\r', at)) != std::string_view::npos;
         at = eol + 1) {
      std::string_view line = s.substr(at, eol - at);
      while (!line.empty() && is_blank(line.front())) line.remove_prefix(1);
      if (line.starts_with("end_header") && (line.size() == 10 || is_blank(line[10])))
        return eol + 1;
    }
    return s.size();
  }

  /// Makes every '\r' before `end` a '\n', in a copy of the file taken on first use.
  void crs_to_newlines(std::size_t end) {
    if (lines_.empty()) {
      lines_.assign(reinterpret_cast<const char*>(data_.data()), data_.size());
      data_ = std::as_bytes(std::span<const char>(lines_.data(), lines_.size()));
    }
    std::replace(lines_.begin(), lines_.begin() + static_cast<std::ptrdiff_t>(end), '\r', '\n');
  }

  [[noreturn]] void header_fail(std::uint64_t line, const std::string& what) const {
    throw ParseError(name_, ParseError::Unit::kLine, line, what);
  }

  void header() {
    TextCursor in(data_, name_);
    std::string_view magic = in.word();
    if (magic != "ply") header_fail(1, "not a PLY file: expected 'ply' on the first line");
    in.skip_line();
    bool have_format = false;
    for (;;) {
      if (in.at_end()) header_fail(in.line(), "file ends inside the PLY header (no end_header)");
      const std::uint64_t line = in.line();
      std::string_view key = in.word();
      if (key == "format") {
        std::string_view f = in.word();
        if (f == "ascii") encoding_ = Encoding::kAscii;
        else if (f == "binary_little_endian") encoding_ = Encoding::kLittle;
        else if (f == "binary_big_endian") encoding_ = Encoding::kBig;
        else header_fail(line, "unknown PLY format '" + TextCursor::printable(f) + "'");
        have_format = true;
      } else if (key == "element") {
        Element e;
        e.name = std::string(in.word());
        e.header_line = line;
        std::int64_t count;
        const std::string_view c = in.word();
        const char* q = parse_int(c.data(), c.data() + c.size(), count);
        if (e.name.empty() || !q || q != c.data() + c.size() || count < 0)
          header_fail(line, "expected 'element <name> <count>'");
        e.count = static_cast<std::uint64_t>(count);
        elements_.push_back(std::move(e));
      } else if (key == "property") {
        if (elements_.empty()) header_fail(line, "property before any element");
        PlyProperty p;
        std::string_view t = in.word();
        if (t == "list") {
          p.is_list = true;
          auto ct = parse_type(in.word());
          auto it = parse_type(in.word());
          if (!ct || !it) header_fail(line, "unknown type in list property");
          if (!is_integer_type(*ct)) header_fail(line, "list count type must be an integer type");
          p.count_type = *ct;
          p.type = *it;
        } else {
          auto ty = parse_type(t);
          if (!ty) header_fail(line, "unknown property type '" + TextCursor::printable(t) + "'");
          p.type = *ty;
        }
        p.name = std::string(in.word());
        if (p.name.empty()) header_fail(line, "property without a name");
        elements_.back().props.push_back(std::move(p));
      } else if (key == "end_header") {
        in.skip_line();
        break;
      } else if (key != "comment" && key != "obj_info" && !key.empty()) {
        header_fail(line, "unexpected '" + TextCursor::printable(key) + "' in the PLY header");
      }
      in.skip_line();
    }
    if (!have_format) header_fail(in.line(), "PLY header has no format line");
    body_ = static_cast<std::size_t>(in.pos() - reinterpret_cast<const char*>(data_.data()));
    body_line_ = in.line();
    assign_roles();
  }

  void assign_roles() {
    for (auto& e : elements_) {
      if (e.name == "vertex") {
        if (vertex_element_) header_fail(e.header_line, "second vertex element");
        vertex_element_ = &e;
        bool has[16] = {};
        for (auto& p : e.props) {
          if (p.is_list) continue;
          p.role = vertex_role(p.name);
          if (p.role != Role::kScalar) {
            if (has[static_cast<int>(p.role)]) p.role = Role::kScalar;  // duplicate name
            has[static_cast<int>(p.role)] = true;
          }
          if (p.role == Role::kScalar) {
            p.scalar = soup_.vertex_scalars.size();
            soup_.vertex_scalars.push_back({p.name, {}});
          }
        }
        for (Role r : {Role::kX, Role::kY, Role::kZ})
          if (!has[static_cast<int>(r)])
            header_fail(e.header_line, "vertex element lacks one of the x, y, z properties");
        normals_ = has[static_cast<int>(Role::kNx)] && has[static_cast<int>(Role::kNy)] &&
                   has[static_cast<int>(Role::kNz)];
        colors_ = has[static_cast<int>(Role::kRed)] && has[static_cast<int>(Role::kGreen)] &&
                  has[static_cast<int>(Role::kBlue)];
        texcoords_ = has[static_cast<int>(Role::kU)] && has[static_cast<int>(Role::kV)];
        // Incomplete groups are carried as scalars rather than dropped.
        for (auto& p : e.props) {
          const bool orphan = ((p.role == Role::kNx || p.role == Role::kNy || p.role == Role::kNz) && !normals_) ||
                              ((p.role == Role::kRed || p.role == Role::kGreen || p.role == Role::kBlue) && !colors_) ||
                              ((p.role == Role::kU || p.role == Role::kV) && !texcoords_);
          if (orphan) {
            p.role = Role::kScalar;
            p.scalar = soup_.vertex_scalars.size();
            soup_.vertex_scalars.push_back({p.name, {}});
          }
        }
      } else if (e.name == "face") {
        if (face_element_) header_fail(e.header_line, "second face element");
        face_element_ = &e;
        for (auto& p : e.props) {
          if (p.is_list) {
            if ((p.name == "vertex_indices" || p.name == "vertex_index") && !has_indices_) {
              if (!is_integer_type(p.type)) header_fail(e.header_line, "face indices must be an integer type");
              p.role = Role::kIndices;
              has_indices_ = true;
            }
          } else {
            p.role = Role::kScalar;
            p.scalar = soup_.face_scalars.size();
            soup_.face_scalars.push_back({p.name, {}});
          }
        }
        if (!has_indices_) header_fail(e.header_line, "face element has no vertex_indices list");
      } else if (e.name == "tristrips") {
        if (strip_element_) header_fail(e.header_line, "second tristrips element");
        strip_element_ = &e;
        auto indices = std::find_if(e.props.begin(), e.props.end(), [](const PlyProperty& p) {
          return p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index");
        });
        if (indices == e.props.end())
          header_fail(e.header_line, "tristrips element has no vertex_indices list");
        if (!is_integer_type(indices->type))
          header_fail(e.header_line, "tristrips indices must be an integer type");
        indices->role = Role::kStrip;
      }
    }
    if (face_element_ && !vertex_element_) header_fail(face_element_->header_line, "face element without a vertex element");
    if (strip_element_ && !vertex_element_)
      header_fail(strip_element_->header_line, "tristrips element without a vertex element");
    n_vertices_ = vertex_element_ ? vertex_element_->count : 0;
  }

  void reserve_for(const Element& e) {
    // Counts were checked against the remaining bytes before this is called.
    const std::size_t n = static_cast<std::size_t>(e.count);
    if (&e == vertex_element_) {
      soup_.positions.reserve(n);
      if (normals_) soup_.vertex_normals.reserve(n);
      if (colors_) soup_.vertex_colors.reserve(n);
      if (texcoords_) soup_.vertex_texcoords.reserve(n);
      for (auto& s : soup_.vertex_scalars) s.values.reserve(n);
    } else if (&e == face_element_) {
      soup_.face_offsets.reserve(n + 1);
      soup_.face_indices.reserve(3 * n);
      for (auto& s : soup_.face_scalars) s.values.reserve(n);
    }
  }

  /// One record's scalar values routed to the soup.
  struct VertexRecord {
    Point p = Point::Zero();
    Normal n = Normal::Zero();
    Color c = Color::Zero();
    TexCoord t = TexCoord::Zero();
  };

  void route_vertex_value(VertexRecord& r, const PlyProperty& p, double v) {
    switch (p.role) {
      case Role::kX: r.p.x() = v; break;
      case Role::kY: r.p.y() = v; break;
      case Role::kZ: r.p.z() = v; break;
      case Role::kNx: r.n.x() = v; break;
      case Role::kNy: r.n.y() = v; break;
      case Role::kNz: r.n.z() = v; break;
      case Role::kRed: r.c.x() = is_integer_type(p.type) ? v / type_max(p.type) : v; break;
      case Role::kGreen: r.c.y() = is_integer_type(p.type) ? v / type_max(p.type) : v; break;
      case Role::kBlue: r.c.z() = is_integer_type(p.type) ? v / type_max(p.type) : v; break;
      case Role::kU: r.t.x() = v; break;
      case Role::kV: r.t.y() = v; break;
      case Role::kScalar: soup_.vertex_scalars[p.scalar].values.push_back(v); break;
      default: break;
    }
  }

  bool push_vertex(const VertexRecord& r) {
    if (!std::isfinite(r.p.x()) || !std::isfinite(r.p.y()) || !std::isfinite(r.p.z())) return false;
    soup_.positions.push_back(r.p);
    if (normals_) soup_.vertex_normals.push_back(r.n);
    if (colors_) soup_.vertex_colors.push_back(r.c);
    if (texcoords_) soup_.vertex_texcoords.push_back(r.t);
    return true;
  }

  // ---- binary -------------------------------------------------------------------------
  template <bool kBig>
  static double load(Type t, const unsigned char* p) {
    auto get = [p]<class T>(T) {
      return kBig ? load_be<T>(p) : load_le<T>(p);
    };
    switch (t) {
      case Type::kInt8: return static_cast<std::int8_t>(p[0]);
      case Type::kUint8: return p[0];
      case Type::kInt16: return get(std::int16_t{});
      case Type::kUint16: return get(std::uint16_t{});
      case Type::kInt32: return get(std::int32_t{});
      case Type::kUint32: return get(std::uint32_t{});
      case Type::kFloat32: return get(float{});
      case Type::kFloat64: return get(double{});
    }
    return 0;
  }
  double load_value(Type t, const unsigned char* p) const {
    return encoding_ == Encoding::kBig ? load<true>(t, p) : load<false>(t, p);
  }

  void binary_element(ByteCursor& in, const Element& e, std::size_t) {
    const std::size_t min = e.min_bytes();
    if (!count_fits(e.count, min, in.remaining()))
      in.fail("element '" + e.name + "' claims " + std::to_string(e.count) + " records of at least " +
              std::to_string(min) + " bytes, but only " + std::to_string(in.remaining()) + " bytes remain");
    reserve_for(e);
    const bool is_vertex = &e == vertex_element_;
    const bool is_face = &e == face_element_;
    if (!is_vertex && !is_face) {
      if (e.fixed()) {
        in.skip(static_cast<std::size_t>(e.count) * min);
        return;
      }
    }
    if (is_face && fast_faces(in, e)) return;
    if (is_vertex && soup_.positions.empty() && fast_vertices(in, e)) return;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      const std::size_t record_start = in.pos();
      VertexRecord r;
      for (const PlyProperty& p : e.props) {
        if (!p.is_list) {
          const std::size_t s = type_size(p.type);
          if (in.remaining() < s) in.need(s, ("property '" + p.name + "' of element '" + e.name + "'").c_str());
          if (p.role != Role::kSkip) {
            const double v = load_value(p.type, in.ptr());
            if (is_vertex) route_vertex_value(r, p, v);
            else if (is_face) soup_.face_scalars[p.scalar].values.push_back(v);
          }
          in.skip(s);
          continue;
        }
        const std::size_t cs = type_size(p.count_type);
        in.need(cs, "list count");
        const std::size_t count_at = in.pos();
        const double cv = load_value(p.count_type, in.ptr());
        in.skip(cs);
        if (cv < 0) in.fail_at(count_at, "negative list length in element '" + e.name + "'");
        const std::size_t n = static_cast<std::size_t>(cv);
        const std::size_t s = type_size(p.type);
        if (!count_fits(n, s, in.remaining()))
          in.fail_at(count_at, "list of " + std::to_string(n) + " values runs past the end of the file");
        if (p.role == Role::kIndices) {
          if (n == 0) in.fail_at(count_at, "face without vertices");
          for (std::size_t k = 0; k < n; ++k) {
            const double v = load_value(p.type, in.ptr() + k * s);
            if (v < 0 || v >= static_cast<double>(n_vertices_))
              in.fail_at(in.pos() + k * s, "vertex index " + std::to_string(static_cast<long long>(v)) +
                                               " out of range (" + std::to_string(n_vertices_) + " vertices)");
            soup_.face_indices.push_back(static_cast<std::uint32_t>(v));
          }
          add_face_offset(in.pos());
        } else if (p.role == Role::kStrip) {
          strip_length_ = 0;
          for (std::size_t k = 0; k < n; ++k) {
            const double v = load_value(p.type, in.ptr() + k * s);
            if (!add_strip_index(v)) in.fail_at(in.pos() + k * s, strip_index_error(v, i));
          }
        }
        in.skip(n * s);
      }
      if (is_vertex && !push_vertex(r)) in.fail_at(record_start, "vertex coordinate is NaN or infinite");
    }
  }

  /// The common layout (face = one "list uchar int|uint" property) without per-value
  /// dispatch, writing straight into the soup's arrays.
  bool fast_faces(ByteCursor& in, const Element& e) {
    if (e.props.size() != 1 || !soup_.face_indices.empty()) return false;
    const PlyProperty& p = e.props[0];
    if (p.role != Role::kIndices || p.count_type != Type::kUint8 ||
        (p.type != Type::kInt32 && p.type != Type::kUint32))
      return false;
    return encoding_ == Encoding::kBig ? fast_faces_impl<true>(in, e, p) : fast_faces_impl<false>(in, e, p);
  }

  template <bool kBig>
  bool fast_faces_impl(ByteCursor& in, const Element& e, const PlyProperty& p) {
    const std::uint64_t nv = n_vertices_;
    const std::size_t count = static_cast<std::size_t>(e.count);  // checked against the bytes left
    auto& off = soup_.face_offsets;
    auto& idx = soup_.face_indices;
    off.resize(count + 1);
    off[0] = 0;
    idx.resize(3 * count);  // triangles are the common case; grown when faces are larger
    const unsigned char* const begin = in.ptr() - in.pos();
    const unsigned char* q = in.ptr();
    const unsigned char* const end = begin + in.size();
    std::size_t used = 0;
    for (std::size_t i = 0; i < count; ++i) {
      if (q >= end) in.fail_at(static_cast<std::size_t>(q - begin), "file ends inside face " + std::to_string(i));
      const std::size_t n = *q++;
      if (n == 0) in.fail_at(static_cast<std::size_t>(q - 1 - begin), "face without vertices");
      if (static_cast<std::size_t>(end - q) < 4 * n)
        in.fail_at(static_cast<std::size_t>(q - begin), "file ends inside the indices of face " + std::to_string(i));
      if (used + n > idx.size()) idx.resize(std::max(2 * idx.size(), used + n));
      std::uint32_t* out = idx.data() + used;
      for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t raw = kBig ? load_be<std::uint32_t>(q + 4 * k) : load_le<std::uint32_t>(q + 4 * k);
        // As unsigned, a negative int32 is >= 2^31 > any valid count: one test covers both.
        if (raw >= nv) {
          const std::int64_t shown = p.type == Type::kInt32 ? std::int64_t{static_cast<std::int32_t>(raw)}
                                                            : std::int64_t{raw};
          in.fail_at(static_cast<std::size_t>(q + 4 * k - begin),
                     "vertex index " + std::to_string(shown) + " out of range (" + std::to_string(nv) + " vertices)");
        }
        out[k] = raw;
      }
      q += 4 * n;
      used += n;
      if (used > std::numeric_limits<std::uint32_t>::max())
        in.fail_at(static_cast<std::size_t>(q - begin), "too many face corners");
      off[i + 1] = static_cast<std::uint32_t>(used);
    }
    idx.resize(used);
    in.seek(static_cast<std::size_t>(q - begin));
    return true;
  }

  /// Fixed-size vertex records (no lists): every record is known to be in the file, so
  /// values are read at precomputed offsets without per-value bounds checks.
  bool fast_vertices(ByteCursor& in, const Element& e) {
    if (!e.fixed()) return false;
    return encoding_ == Encoding::kBig ? fast_vertices_impl<true>(in, e) : fast_vertices_impl<false>(in, e);
  }

  template <bool kBig>
  bool fast_vertices_impl(ByteCursor& in, const Element& e) {
    const std::size_t count = static_cast<std::size_t>(e.count);
    const std::size_t stride = e.min_bytes();
    std::vector<std::size_t> offset(e.props.size());
    for (std::size_t k = 0, o = 0; k < e.props.size(); ++k) {
      offset[k] = o;
      o += type_size(e.props[k].type);
    }
    const unsigned char* base = in.ptr();
    const std::size_t start = in.pos();
    soup_.positions.resize(count);
    // x, y, z as the first three float properties: the layout nearly every file has.
    const bool xyz_floats = e.props.size() >= 3 && e.props[0].role == Role::kX && e.props[1].role == Role::kY &&
                            e.props[2].role == Role::kZ && e.props[0].type == Type::kFloat32 &&
                            e.props[1].type == Type::kFloat32 && e.props[2].type == Type::kFloat32;
    const bool only_xyz = xyz_floats && e.props.size() == 3;
    for (std::size_t i = 0; i < count; ++i) {
      const unsigned char* rec = base + i * stride;
      if (xyz_floats) {
        Point& p = soup_.positions[i];
        p.x() = kBig ? load_be<float>(rec) : load_le<float>(rec);
        p.y() = kBig ? load_be<float>(rec + 4) : load_le<float>(rec + 4);
        p.z() = kBig ? load_be<float>(rec + 8) : load_le<float>(rec + 8);
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
          in.fail_at(start + i * stride, "vertex coordinate is NaN or infinite");
        if (only_xyz) continue;
      }
      VertexRecord r;
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        if (p.role == Role::kSkip) continue;
        route_vertex_value(r, p, load<kBig>(p.type, rec + offset[k]));
      }
      if (!r.p.allFinite()) in.fail_at(start + i * stride, "vertex coordinate is NaN or infinite");
      soup_.positions[i] = r.p;
      if (normals_) soup_.vertex_normals.push_back(r.n);
      if (colors_) soup_.vertex_colors.push_back(r.c);
      if (texcoords_) soup_.vertex_texcoords.push_back(r.t);
    }
    in.skip(count * stride);
    return true;
  }

  void add_face_offset(std::uint64_t where) {
    if (soup_.face_offsets.empty()) soup_.face_offsets.push_back(0);
    if (soup_.face_indices.size() > std::numeric_limits<std::uint32_t>::max())
      throw ParseError(name_, encoding_ == Encoding::kAscii ? ParseError::Unit::kLine : ParseError::Unit::kByte,
                       where, "too many face corners");
    soup_.face_offsets.push_back(static_cast<std::uint32_t>(soup_.face_indices.size()));
  }

  // ---- ascii --------------------------------------------------------------------------
  void ascii_element(TextCursor& in, const Element& e, std::size_t) {
    // Every value takes at least one character and one separator.
    const std::size_t remaining = static_cast<std::size_t>(in.end() - in.pos());
    const std::size_t min = std::max<std::size_t>(2 * e.props.size(), 2);
    if (!count_fits(e.count, min, remaining + 1))
      in.fail("element '" + e.name + "' claims " + std::to_string(e.count) + " records, more than the " +
              std::to_string(remaining) + " bytes left can hold");
    reserve_for(e);
    const bool is_vertex = &e == vertex_element_;
    const bool is_face = &e == face_element_;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      VertexRecord r;
      for (const PlyProperty& p : e.props) {
        if (!p.is_list) {
          const double v = ascii_value(in, p.type, p.name.c_str());
          if (is_vertex) route_vertex_value(r, p, v);
          else if (is_face && p.role == Role::kScalar) soup_.face_scalars[p.scalar].values.push_back(v);
          continue;
        }
        const double cv = ascii_value(in, p.count_type, "list count");
        if (cv < 0) in.fail("negative list length");
        const std::size_t n = static_cast<std::size_t>(cv);
        if (!count_fits(n, 2, static_cast<std::size_t>(in.end() - in.pos()) + 1))
          in.fail("list of " + std::to_string(n) + " values runs past the end of the file");
        if (p.role == Role::kIndices && n == 0) in.fail("face without vertices");
        if (p.role == Role::kStrip) strip_length_ = 0;
        for (std::size_t k = 0; k < n; ++k) {
          const double v = ascii_value(in, p.type, "list value");
          if (p.role == Role::kIndices) {
            if (v < 0 || v >= static_cast<double>(n_vertices_))
              in.fail("vertex index " + std::to_string(static_cast<long long>(v)) + " out of range (" +
                      std::to_string(n_vertices_) + " vertices)");
            soup_.face_indices.push_back(static_cast<std::uint32_t>(v));
          } else if (p.role == Role::kStrip && !add_strip_index(v)) {
            in.fail(strip_index_error(v, i));
          }
        }
        if (p.role == Role::kIndices) add_face_offset(in.line());
      }
      if (is_vertex && !push_vertex(r)) in.fail("vertex coordinate is NaN or infinite");
    }
  }

  // ---- tristrips -----------------------------------------------------------------------
  /// One value of a strip list (each record starts a new strip, as -1 does). Triangle j of
  /// a strip is (a, b, c) for even j and (b, a, c) for odd j, so all face the same way.
  /// Returns false for a value that is neither -1 nor a vertex index.
  bool add_strip_index(double v) {
    if (v == -1) {
      strip_length_ = 0;
      return true;
    }
    if (v < 0 || v >= static_cast<double>(n_vertices_)) return false;
    const auto c = static_cast<std::uint32_t>(v);
    if (strip_length_ >= 2) {
      const std::uint32_t a = strip_[0], b = strip_[1];
      if (a != b && b != c && a != c) {
        const bool odd = strip_length_ % 2 == 1;  // triangle j = strip_length_ - 2
        strip_triangles_.insert(strip_triangles_.end(), {odd ? b : a, odd ? a : b, c});
      }
    }
    strip_[0] = strip_[1];
    strip_[1] = c;
    ++strip_length_;
    return true;
  }

  std::string strip_index_error(double v, std::uint64_t record) const {
    return "element '" + strip_element_->name + "' record " + std::to_string(record) +
           ": vertex index " + std::to_string(static_cast<long long>(v)) + " out of range (" +
           std::to_string(n_vertices_) + " vertices; -1 ends a strip)";
  }

  /// Strip triangles go after the element "face"'s, wherever the elements are in the file.
  void append_strip_triangles() {
    if (strip_triangles_.empty()) return;
    if (soup_.face_indices.size() + strip_triangles_.size() >
        std::numeric_limits<std::uint32_t>::max())
      throw ParseError(name_, ParseError::Unit::kNone, 0, "too many face corners");
    if (soup_.face_offsets.empty()) soup_.face_offsets.push_back(0);
    for (std::size_t t = 0; t < strip_triangles_.size(); t += 3) {
      soup_.face_indices.insert(soup_.face_indices.end(), strip_triangles_.begin() + t,
                                strip_triangles_.begin() + t + 3);
      soup_.face_offsets.push_back(static_cast<std::uint32_t>(soup_.face_indices.size()));
    }
    for (auto& s : soup_.face_scalars) s.values.resize(soup_.n_faces(), 0.0);
  }

  double ascii_value(TextCursor& in, Type t, const char* what) {
    in.skip_space(false);
    if (in.at_end()) in.fail(std::string("file ends before ") + what);
    double v = in.number(what);
    if (is_integer_type(t)) {
      const bool is_signed = t == Type::kInt8 || t == Type::kInt16 || t == Type::kInt32;
      if (v != std::floor(v) || v < (is_signed ? -type_max(t) - 1 : 0.0) || v > type_max(t))
        in.fail(std::string(what) + " is not a valid integer of its declared type");
    } else if (t == Type::kFloat32 && std::fabs(v) < 0x1.ffffffp+127) {
      // Below 2^128 - 2^103 the value rounds to a finite float (FLT_MAX's shortest decimal
      // is slightly above FLT_MAX, so the bound is the rounding threshold, not FLT_MAX).
      // Declared float: the value is the float the text denotes.
      v = round_to_float(v);
    }
    return v;
  }

  std::span<const std::byte> data_;
  const std::string& name_;
  Encoding encoding_ = Encoding::kAscii;
  std::vector<Element> elements_;
  const Element* vertex_element_ = nullptr;
  const Element* face_element_ = nullptr;
  const Element* strip_element_ = nullptr;
  std::size_t body_ = 0;
  std::uint64_t body_line_ = 1;
  std::uint64_t n_vertices_ = 0;
  bool normals_ = false, colors_ = false, texcoords_ = false, has_indices_ = false;
  PolygonSoup soup_;
  std::string lines_;            // the file with '\r' line ends made '\n' (see run())
  std::uint32_t strip_[2] = {};  // the last two vertices of the current strip
  std::size_t strip_length_ = 0;
  std::vector<std::uint32_t> strip_triangles_;
};

}  // namespace

PolygonSoup read_ply(std::span<const std::byte> data, const std::string& name) {
  return PlyReader(data, name).run();
}

}  // namespace geom::io_detail
