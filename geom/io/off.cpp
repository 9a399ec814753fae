// OFF and its variants: [ST][C][N]OFF headers (texture coordinates, colours, normals per
// vertex), ascii and "OFF BINARY". Per-face colours are read past and ignored.
//
// Binary OFF is big-endian by the geomview spec, but pmp writes it little-endian; the reader
// tries each byte order (and faces with and without the trailing colour count) and keeps the
// one that accounts for the file exactly. Colours given as integers are scaled by 1/255.

#include <geom/io/formats.h>
#include <geom/io/text.h>

#include <cmath>
#include <limits>

namespace geom::io_detail {
namespace {

struct Header {
  bool st = false, c = false, n = false, binary = false;
};

/// Parse "[ST][C][N]OFF" (optionally followed by "BINARY"); false when it is not an OFF key.
bool parse_key(std::string_view w, Header& h) {
  if (w.starts_with("ST")) {
    h.st = true;
    w.remove_prefix(2);
  }
  if (w.starts_with("C")) {
    h.c = true;
    w.remove_prefix(1);
  }
  if (w.starts_with("N")) {
    h.n = true;
    w.remove_prefix(1);
  }
  return w == "OFF";
}

bool is_integer_token(const char* b, const char* e) {
  if (b < e && (*b == '-' || *b == '+')) ++b;
  if (b == e) return false;
  for (; b < e; ++b)
    if (*b < '0' || *b > '9') return false;
  return true;
}

std::uint64_t checked_count(TextCursor& in, const char* what, std::size_t min_bytes_each) {
  in.skip_space(true);
  const std::int64_t n = in.integer(what);
  if (n < 0) in.fail(std::string("negative ") + what);
  const auto left = static_cast<std::uint64_t>(in.end() - in.pos());
  if (!count_fits(static_cast<std::uint64_t>(n), min_bytes_each, left + 1))
    in.fail(std::string(what) + " " + std::to_string(n) + " cannot fit in the " + std::to_string(left) +
            " bytes that remain");
  return static_cast<std::uint64_t>(n);
}

/// Skip blank lines and comment lines; position at the first token of the next record.
void next_record(TextCursor& in) { in.skip_space(true); }

PolygonSoup read_ascii(TextCursor& in, const Header& h) {
  const std::uint64_t nv = checked_count(in, "vertex count", 6);
  const std::uint64_t nf = checked_count(in, "face count", 2);
  in.skip_blanks();
  if (!in.at_eol()) in.integer("edge count");
  PolygonSoup soup;
  soup.positions.reserve(nv);
  if (h.n) soup.vertex_normals.reserve(nv);
  if (h.c) soup.vertex_colors.reserve(nv);
  if (h.st) soup.vertex_texcoords.reserve(nv);
  std::vector<double> rest;
  for (std::uint64_t i = 0; i < nv; ++i) {
    next_record(in);
    if (in.at_end()) in.fail("file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
    Point p;
    for (int k = 0; k < 3; ++k) {
      p[k] = in.number("vertex coordinate");
      if (!std::isfinite(p[k])) in.fail("vertex coordinate is NaN or infinite");
    }
    soup.positions.push_back(p);
    if (h.n) {
      Normal n;
      for (int k = 0; k < 3; ++k) n[k] = in.number("normal");
      soup.vertex_normals.push_back(n);
    }
    // Remaining numbers on the line: colour (3 or 4) then texture coordinates (2).
    rest.clear();
    bool integer_colors = true;
    double v;
    for (;;) {
      in.skip_blanks();
      if (in.at_eol()) break;
      const char* b = in.pos();
      v = in.number("vertex value");
      if (rest.size() < 4 && !is_integer_token(b, in.pos())) integer_colors = false;
      rest.push_back(v);
      if (rest.size() > 16) in.fail("too many values on a vertex line");
    }
    std::size_t used = 0;
    if (h.c) {
      const std::size_t colour_values = rest.size() - (h.st ? 2 : 0);
      if (rest.size() < (h.st ? 5u : 3u) || (colour_values != 3 && colour_values != 4))
        in.fail("COFF vertex needs 3 or 4 colour values after the coordinates");
      const double scale = integer_colors ? 1.0 / 255.0 : 1.0;
      soup.vertex_colors.emplace_back(rest[0] * scale, rest[1] * scale, rest[2] * scale);
      used = colour_values;
    }
    if (h.st) {
      if (rest.size() < used + 2) in.fail("STOFF vertex needs 2 texture coordinates");
      soup.vertex_texcoords.emplace_back(rest[used], rest[used + 1]);
      used += 2;
    }
    if (used != rest.size() && !h.c) in.fail("unexpected extra values on a vertex line");
  }
  soup.face_offsets.reserve(nf + 1);
  soup.face_offsets.push_back(0);
  for (std::uint64_t i = 0; i < nf; ++i) {
    next_record(in);
    if (in.at_end()) in.fail("file ends after " + std::to_string(i) + " of " + std::to_string(nf) + " faces");
    const std::int64_t n = in.integer("face size");
    if (n <= 0) in.fail("face size " + std::to_string(n) + "; expected at least 1");
    if (!count_fits(static_cast<std::uint64_t>(n), 2, static_cast<std::uint64_t>(in.end() - in.pos()) + 1))
      in.fail("face size " + std::to_string(n) + " runs past the end of the file");
    for (std::int64_t k = 0; k < n; ++k) {
      const std::int64_t v = in.integer("vertex index");
      if (v < 0 || static_cast<std::uint64_t>(v) >= nv)
        in.fail("vertex index " + std::to_string(v) + " out of range (" + std::to_string(nv) + " vertices)");
      soup.face_indices.push_back(static_cast<std::uint32_t>(v));
    }
    if (soup.face_indices.size() > std::numeric_limits<std::uint32_t>::max()) in.fail("too many face corners");
    soup.face_offsets.push_back(static_cast<std::uint32_t>(soup.face_indices.size()));
    in.skip_line();  // a face colour may follow
  }
  if (nf == 0) soup.face_offsets.clear();
  return soup;
}

/// One attempt at the binary layout; nullopt when this byte order / face layout does not
/// account for the file (the error of the most plausible attempt is reported by the caller).
struct BinaryAttempt {
  bool big;
  bool colour_count;  // spec: each face ends with a colour count and that many floats
};

template <class T>
T get(const unsigned char* p, bool big) {
  return big ? load_be<T>(p) : load_le<T>(p);
}

PolygonSoup read_binary(ByteCursor& in, const Header& h, const BinaryAttempt& a) {
  in.need(12, "the OFF BINARY counts");
  const std::int32_t nv = get<std::int32_t>(in.ptr(), a.big);
  const std::int32_t nf = get<std::int32_t>(in.ptr() + 4, a.big);
  if (nv < 0 || nf < 0) in.fail("negative vertex or face count");
  in.skip(12);
  const std::size_t floats = 3 + (h.n ? 3 : 0) + (h.c ? 4 : 0) + (h.st ? 2 : 0);
  const std::size_t vstride = 4 * floats;
  if (!count_fits(static_cast<std::uint64_t>(nv), vstride, in.remaining()))
    in.fail("vertex count " + std::to_string(nv) + " does not fit in the " + std::to_string(in.remaining()) +
            " bytes left");
  if (!count_fits(static_cast<std::uint64_t>(nf), 8, in.remaining() - static_cast<std::size_t>(nv) * vstride))
    in.fail("face count " + std::to_string(nf) + " does not fit in the bytes left");
  PolygonSoup soup;
  soup.positions.reserve(static_cast<std::size_t>(nv));
  for (std::int32_t i = 0; i < nv; ++i) {
    const unsigned char* p = in.ptr();
    Point x(get<float>(p, a.big), get<float>(p + 4, a.big), get<float>(p + 8, a.big));
    if (!x.allFinite()) in.fail("vertex coordinate is NaN or infinite");
    soup.positions.push_back(x);
    std::size_t k = 3;
    if (h.n) {
      soup.vertex_normals.emplace_back(get<float>(p + 12, a.big), get<float>(p + 16, a.big), get<float>(p + 20, a.big));
      k += 3;
    }
    if (h.c) {
      soup.vertex_colors.emplace_back(get<float>(p + 4 * k, a.big), get<float>(p + 4 * k + 4, a.big),
                                      get<float>(p + 4 * k + 8, a.big));
      k += 4;
    }
    if (h.st) soup.vertex_texcoords.emplace_back(get<float>(p + 4 * k, a.big), get<float>(p + 4 * k + 4, a.big));
    in.skip(vstride);
  }
  soup.face_offsets.reserve(static_cast<std::size_t>(nf) + 1);
  soup.face_offsets.push_back(0);
  for (std::int32_t i = 0; i < nf; ++i) {
    in.need(4, "a face size");
    const std::size_t at = in.pos();
    const std::int32_t n = get<std::int32_t>(in.ptr(), a.big);
    if (n <= 0 || !count_fits(static_cast<std::uint64_t>(n), 4, in.remaining() - 4))
      in.fail("face size " + std::to_string(n) + " is invalid or runs past the end of the file");
    in.skip(4);
    for (std::int32_t k = 0; k < n; ++k) {
      const std::int32_t v = get<std::int32_t>(in.ptr(), a.big);
      if (v < 0 || v >= nv)
        in.fail("vertex index " + std::to_string(v) + " out of range (" + std::to_string(nv) + " vertices)");
      soup.face_indices.push_back(static_cast<std::uint32_t>(v));
      in.skip(4);
    }
    if (a.colour_count) {
      in.need(4, "a face colour count");
      const std::int32_t nc = get<std::int32_t>(in.ptr(), a.big);
      if (nc < 0 || nc > 4) in.fail_at(at, "face colour count " + std::to_string(nc) + " (expected 0 to 4)");
      in.skip(4);
      in.need(4 * static_cast<std::size_t>(nc), "a face colour");
      in.skip(4 * static_cast<std::size_t>(nc));
    }
    soup.face_offsets.push_back(static_cast<std::uint32_t>(soup.face_indices.size()));
  }
  if (nf == 0) soup.face_offsets.clear();
  if (in.remaining() != 0) in.fail(std::to_string(in.remaining()) + " unexplained bytes after the last face");
  return soup;
}

}  // namespace

PolygonSoup read_off(std::span<const std::byte> data, const std::string& name) {
  TextCursor in(data, name);
  in.skip_space(true);
  Header h;
  const std::string_view key = in.word();
  if (!parse_key(key, h)) {
    if (key.size() >= 3 && (key.ends_with("OFF") || key.starts_with("4") || key.find("nOFF") != key.npos))
      in.fail("unsupported OFF variant '" + TextCursor::printable(key) + "' (only [ST][C][N]OFF)");
    in.fail("not an OFF file: expected an OFF header, found '" + TextCursor::printable(key.substr(0, 32)) + "'");
  }
  in.skip_blanks();
  if (!in.at_eol()) {
    const char* save = in.pos();
    if (in.word() == "BINARY") h.binary = true;
    else in.set_pos(save);
  }
  if (!h.binary) return read_ascii(in, h);
  in.skip_line();
  const auto body = static_cast<std::size_t>(in.pos() - reinterpret_cast<const char*>(data.data()));
  // Try the spec's big-endian layout first, then pmp's little-endian one, each with and
  // without per-face colour counts.
  std::optional<ParseError> best;
  for (BinaryAttempt a : {BinaryAttempt{true, true}, BinaryAttempt{false, false}, BinaryAttempt{false, true},
                          BinaryAttempt{true, false}}) {
    ByteCursor bin(data, name);
    bin.seek(body);
    try {
      return read_binary(bin, h, a);
    } catch (const ParseError& e) {
      // The attempt that got furthest is the most plausible reading of a broken file.
      if (!best || e.where() > best->where()) best = e;
    }
  }
  throw *best;
}

void write_off(const PolygonSoup& soup, const WriteOptions& options, std::string& out) {
  const bool normals = options.attributes && !soup.vertex_normals.empty();
  const bool colors = options.attributes && !soup.vertex_colors.empty();
  const bool tex = options.attributes && !soup.vertex_texcoords.empty();
  out += tex ? "ST" : "";
  out += colors ? "C" : "";
  out += normals ? "N" : "";
  out += "OFF\n";
  append_int(out, static_cast<std::int64_t>(soup.positions.size()));
  out += ' ';
  append_int(out, static_cast<std::int64_t>(soup.n_faces()));
  out += " 0\n";
  out.reserve(out.size() + soup.positions.size() * 40 + soup.face_indices.size() * 8);
  auto put_colour = [&out](double c) {
    // Always with a '.' or exponent so the reader does not take it for a 0-255 integer.
    const std::size_t start = out.size();
    append_double(out, c);
    if (out.find_first_of(".en", start) == std::string::npos) out += ".0";
  };
  for (std::size_t v = 0; v < soup.positions.size(); ++v) {
    for (int k = 0; k < 3; ++k) {
      if (k) out += ' ';
      append_double(out, soup.positions[v][k]);
    }
    if (normals)
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        append_double(out, soup.vertex_normals[v][k]);
      }
    if (colors)
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        put_colour(soup.vertex_colors[v][k]);
      }
    if (tex)
      for (int k = 0; k < 2; ++k) {
        out += ' ';
        append_double(out, soup.vertex_texcoords[v][k]);
      }
    out += '\n';
  }
  for (std::size_t f = 0; f < soup.n_faces(); ++f) {
    append_int(out, soup.face_offsets[f + 1] - soup.face_offsets[f]);
    for (std::uint32_t c = soup.face_offsets[f]; c < soup.face_offsets[f + 1]; ++c) {
      out += ' ';
      append_int(out, soup.face_indices[c]);
    }
    out += '\n';
  }
}

}  // namespace geom::io_detail
