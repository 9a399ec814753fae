// Wavefront OBJ: v / vt / vn / f records, OpenSubdiv "t" tags, the names of faces' objects,
// groups and materials ("o", "g", "usemtl") and the material files ("mtllib"); everything
// else (smoothing groups, lines, free-form geometry) is skipped.
//
// Attributes: vt and vn become per-corner arrays (corner_texcoords, corner_normals), in
// which a corner without a vt/vn reference gets (0, 0) / (0, 0, 0). When every corner has
// one and all corners of each vertex name the same vt (vn) record, the reader also fills
// vertex_texcoords (vertex_normals), which is what most algorithms want. "v x y z r g b"
// (the common colour extension) fills vertex_colors; vertices without colour get black.
//
// Indices in "f" may point forwards (validated once the file is read); relative (negative)
// indices are resolved against the records read so far, as the format defines.

#include <geom/io/formats.h>
#include <geom/io/obj_names.h>
#include <geom/io/text.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

namespace geom::io_detail {
namespace {

constexpr std::int64_t kNone = -1;

/// Largest referenced index of one kind and the line that referenced it, checked at the end.
struct IndexUse {
  std::int64_t max = -1;
  std::uint64_t line = 0;
  void note(std::int64_t i, std::uint64_t at) {
    if (i > max) {
      max = i;
      line = at;
    }
  }
};

bool blank_or_eol(const char* p, const char* end) {
  return p >= end || is_blank(*p) || *p == '\n';
}

/// Skip the rest of a logical line (a trailing backslash joins the next physical line).
void skip_logical_line(TextCursor& in) {
  for (;;) {
    const char* start = in.pos();
    in.skip_line();
    const char* q = in.pos();
    if (q == start || q[-1] != '\n') return;
    std::ptrdiff_t i = (q - start) - 2;
    while (i >= 0 && start[i] == '\r') --i;
    if (i >= 0 && start[i] == '\\') continue;
    return;
  }
}

class ObjReader {
 public:
  /// `first_line` numbers the first line of `data`; a `chunk` is one piece of a file read in
  /// parallel: relative indices that reach before it are resolved by merge().
  ObjReader(std::span<const std::byte> data, const std::string& name, std::uint64_t first_line = 1,
            bool chunk = false)
      : in_(data, name), chunk_(chunk) {
    in_.set_line(first_line);
  }

  PolygonSoup run() {
    parse();
    return finish();
  }

  void parse() {
    soup_.face_offsets.push_back(0);
    if (in_.line() == 1 && in_.end() - in_.pos() >= 3 && std::memcmp(in_.pos(), "\xEF\xBB\xBF", 3) == 0)
      in_.set_pos(in_.pos() + 3);
    while (!in_.at_end()) {
      in_.skip_blanks();
      const char* p = in_.pos();
      const char* end = in_.end();
      if (p >= end) break;
      const char c = *p;
      if (c == '\n') {
        in_.skip_line();
        continue;
      }
      if (c == 'v' && p + 1 < end) {
        const char d = p[1];
        if (is_blank(d)) {
          in_.set_pos(p + 1);
          vertex();
        } else if (d == 't' && blank_or_eol(p + 2, end)) {
          in_.set_pos(p + 2);
          texcoord();
        } else if (d == 'n' && blank_or_eol(p + 2, end)) {
          in_.set_pos(p + 2);
          normal();
        } else {
          skip_logical_line(in_);
          continue;
        }
      } else if (c == 'f' && blank_or_eol(p + 1, end)) {
        in_.set_pos(p + 1);
        face();
      } else if (c == 't' && p + 1 < end && is_blank(p[1])) {
        in_.set_pos(p + 1);
        tag();
      } else if (names_statement(p, end)) {
      } else {
        // Unknown keywords are skipped as the format asks; a line that does not start with
        // a keyword or a comment is not OBJ at all (binary data, a wrong file).
        const bool keyword = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '#' || c == '\\';
        if (!keyword) in_.bad_token("an OBJ keyword");
        skip_logical_line(in_);
        continue;
      }
      end_of_record();
    }
  }

  /// Append the later pieces of a file to this one (the first), in file order.
  void merge(std::vector<ObjReader>& parts) {
    std::vector<Fixup> fixups = std::move(fixups_);
    for (std::size_t k = 1; k < parts.size(); ++k) {
      ObjReader& b = parts[k];
      const std::size_t pv = soup_.positions.size(), pvt = vt_.size(), pvn = vn_.size();
      const std::size_t pc = soup_.face_indices.size();
      const std::size_t bv = b.soup_.positions.size(), bc = b.soup_.face_indices.size();
      if (!soup_.vertex_colors.empty() || !b.soup_.vertex_colors.empty()) {
        soup_.vertex_colors.resize(pv, Color::Zero());
        b.soup_.vertex_colors.resize(bv, Color::Zero());
        soup_.vertex_colors.insert(soup_.vertex_colors.end(), b.soup_.vertex_colors.begin(), b.soup_.vertex_colors.end());
      }
      soup_.positions.insert(soup_.positions.end(), b.soup_.positions.begin(), b.soup_.positions.end());
      vt_.insert(vt_.end(), b.vt_.begin(), b.vt_.end());
      vn_.insert(vn_.end(), b.vn_.begin(), b.vn_.end());
      for (std::size_t f = 1; f < b.soup_.face_offsets.size(); ++f) {
        const std::size_t o = pc + b.soup_.face_offsets[f];
        if (o > std::numeric_limits<std::uint32_t>::max()) in_.fail("too many face corners");
        soup_.face_offsets.push_back(static_cast<std::uint32_t>(o));
      }
      soup_.face_indices.insert(soup_.face_indices.end(), b.soup_.face_indices.begin(), b.soup_.face_indices.end());
      for (auto [mine, theirs] : {std::pair{&corner_vt_, &b.corner_vt_}, std::pair{&corner_vn_, &b.corner_vn_}}) {
        if (mine->empty() && theirs->empty()) continue;
        mine->resize(pc, kNone);
        theirs->resize(bc, kNone);
        mine->insert(mine->end(), theirs->begin(), theirs->end());
      }
      const std::size_t prefix[3] = {pv, pvt, pvn};
      for (std::size_t c : b.relative_[0]) soup_.face_indices[pc + c] += static_cast<std::uint32_t>(pv);
      for (int kind = 1; kind < 3; ++kind)
        for (std::size_t c : b.relative_[kind])
          (kind == 1 ? corner_vt_ : corner_vn_)[pc + c] += static_cast<std::int64_t>(prefix[kind]);
      for (Fixup f : b.fixups_) {
        f.corner += pc;
        f.local += static_cast<std::int64_t>(prefix[f.kind]);
        fixups.push_back(f);
      }
      for (auto [mine, theirs] : {std::pair{&v_use_, &b.v_use_}, std::pair{&vt_use_, &b.vt_use_},
                                  std::pair{&vn_use_, &b.vn_use_}, std::pair{&tag_use_, &b.tag_use_}})
        if (theirs->max > mine->max) *mine = *theirs;
      soup_.creases.insert(soup_.creases.end(), b.soup_.creases.begin(), b.soup_.creases.end());
      soup_.corners.insert(soup_.corners.end(), b.soup_.corners.begin(), b.soup_.corners.end());
      if (b.soup_.boundary_interpolation) soup_.boundary_interpolation = b.soup_.boundary_interpolation;
      objects_.append(b.objects_);
      groups_.append(b.groups_);
      materials_.append(b.materials_);
      for (const std::string& lib : b.soup_.material_libraries) add_library(lib);
    }
    static const char* const kKind[] = {"vertex", "texture", "normal"};
    for (const Fixup& f : fixups) {
      if (f.local < 0)
        in_.fail_at(f.line, std::string("relative ") + kKind[f.kind] + " index " + std::to_string(f.index) +
                                " reaches before the first " + kKind[f.kind]);
      if (f.kind == 0) soup_.face_indices[f.corner] = static_cast<std::uint32_t>(f.local);
      else (f.kind == 1 ? corner_vt_ : corner_vn_)[f.corner] = f.local;
    }
  }

 private:
  /// "o", "g" and "usemtl" name the following faces; "mtllib" names a material file.
  bool names_statement(const char* p, const char* end) {
    struct Keyword {
      std::string_view word;
      FaceNameTrack* track;
    };
    for (auto [word, track] : {Keyword{"o", &objects_}, Keyword{"g", &groups_}, Keyword{"usemtl", &materials_},
                               Keyword{"mtllib", nullptr}}) {
      if (static_cast<std::size_t>(end - p) < word.size() || std::memcmp(p, word.data(), word.size()) != 0 ||
          !blank_or_eol(p + word.size(), end))
        continue;
      in_.set_pos(p + word.size());
      std::string rest;  // the words up to the line's end, joined by single spaces
      for (in_.skip_blanks(); !in_.at_eol(); in_.skip_blanks()) (rest += rest.empty() ? "" : " ") += in_.word();
      if (track) track->set(rest);
      else if (!rest.empty()) add_library(rest);
      return true;
    }
    return false;
  }

  void add_library(const std::string& lib) {
    auto& libs = soup_.material_libraries;
    if (std::find(libs.begin(), libs.end(), lib) == libs.end()) libs.push_back(lib);
  }

  void end_of_record() {
    in_.skip_blanks();
    if (!in_.at_eol()) in_.bad_token("end of line");
    skip_logical_line(in_);
  }

  double coordinate(const char* what) {
    double v = in_.number(what);
    if (!std::isfinite(v)) in_.fail(std::string(what) + " is not finite");
    return v;
  }

  void vertex() {
    Point p;
    p.x() = coordinate("vertex x coordinate");
    p.y() = coordinate("vertex y coordinate");
    p.z() = coordinate("vertex z coordinate");
    soup_.positions.push_back(p);
    double extra[4];
    int n = 0;
    while (n < 4 && in_.try_number(extra[n], "number")) ++n;
    if (n >= 3) {
      if (soup_.vertex_colors.size() + 1 < soup_.positions.size())
        soup_.vertex_colors.resize(soup_.positions.size() - 1, Color::Zero());
      soup_.vertex_colors.emplace_back(extra[0], extra[1], extra[2]);
    } else if (!soup_.vertex_colors.empty()) {
      soup_.vertex_colors.push_back(Color::Zero());
    }
    if (n == 2) in_.fail("vertex has 5 numbers; expected x y z [w] or x y z r g b");
  }

  void texcoord() {
    TexCoord t;
    t.x() = in_.number("texture u");
    double v = 0, w;
    in_.try_number(v, "texture v");
    t.y() = v;
    in_.try_number(w, "texture w");
    vt_.push_back(t);
  }

  void normal() {
    Normal n;
    n.x() = in_.number("normal x");
    n.y() = in_.number("normal y");
    n.z() = in_.number("normal z");
    vn_.push_back(n);
  }

  /// An OBJ index (1-based or negative relative) resolved to 0-based, or a failure.
  std::int64_t resolve(std::int64_t i, std::size_t count, const char* kind, IndexUse& use) {
    if (i > 0) {
      use.note(i - 1, in_.line());
      return i - 1;
    }
    if (i == 0) in_.fail(std::string(kind) + " index 0 (OBJ indices start at 1)");
    const std::int64_t r = static_cast<std::int64_t>(count) + i;
    if (r < 0 && chunk_) {
      // Reaches into an earlier piece of the file: resolved when the pieces are merged.
      const std::uint8_t kind = &use == &v_use_ ? 0 : &use == &vt_use_ ? 1 : 2;
      fixups_.push_back({kind, soup_.face_indices.size(), r, i, in_.line()});
      return 0;
    }
    if (chunk_) {
      // Relative to this piece's first record: the merge adds the earlier pieces' counts.
      const int k = &use == &v_use_ ? 0 : &use == &vt_use_ ? 1 : 2;
      relative_[k].push_back(soup_.face_indices.size());
    }
    if (r < 0)
      in_.fail(std::string("relative ") + kind + " index " + std::to_string(i) + " reaches before the first " +
               kind + " (" + std::to_string(count) + " so far)");
    return r;
  }

  std::int64_t index_at(const char*& p, const char* end, const char* what) {
    std::int64_t v;
    const char* q = parse_int(p, end, v);
    if (!q) {
      in_.set_pos(p);
      in_.bad_token(what);
    }
    p = q;
    return v;
  }

  void face() {
    std::size_t corners = 0;
    for (;;) {
      in_.skip_blanks();
      if (in_.at_eol()) break;
      const char* p = in_.pos();
      const char* end = in_.end();
      const std::int64_t v = resolve(index_at(p, end, "vertex index"), soup_.positions.size(), "vertex", v_use_);
      std::int64_t t = kNone, n = kNone;
      // Exporters write "1/", "1//" and "1/2/" for corners without a vt or vn: an empty
      // slot is no reference.
      auto slot_empty = [&] { return blank_or_eol(p, end) || *p == '/' || *p == '#'; };
      if (p < end && *p == '/') {
        ++p;
        if (!slot_empty())
          t = resolve(index_at(p, end, "texture index"), vt_.size(), "texture", vt_use_);
        if (p < end && *p == '/') {
          ++p;
          if (!slot_empty())
            n = resolve(index_at(p, end, "normal index"), vn_.size(), "normal", vn_use_);
        }
      }
      if (p < end && !is_blank(*p) && *p != '\n' && *p != '#') {
        in_.set_pos(p);
        in_.bad_token("face corner 'v', 'v/vt', 'v//vn' or 'v/vt/vn'");
      }
      in_.set_pos(p);
      if (v > std::numeric_limits<std::uint32_t>::max() - 1) in_.fail("vertex index too large");
      soup_.face_indices.push_back(static_cast<std::uint32_t>(v));
      if (t != kNone || !corner_vt_.empty()) {
        if (corner_vt_.empty()) corner_vt_.assign(soup_.face_indices.size() - 1, kNone);
        corner_vt_.push_back(t);
      }
      if (n != kNone || !corner_vn_.empty()) {
        if (corner_vn_.empty()) corner_vn_.assign(soup_.face_indices.size() - 1, kNone);
        corner_vn_.push_back(n);
      }
      ++corners;
    }
    if (corners == 0) in_.fail("face without vertices");
    objects_.face();
    groups_.face();
    materials_.face();
    if (soup_.face_indices.size() > std::numeric_limits<std::uint32_t>::max())
      in_.fail("too many face corners");
    soup_.face_offsets.push_back(static_cast<std::uint32_t>(soup_.face_indices.size()));
  }

  /// OpenSubdiv tags: "t <name> <ints>/<floats>/<strings> <ints...> <floats...> <strings...>".
  void tag() {
    const std::string_view name = in_.word();
    const std::string_view counts = in_.word();
    std::int64_t ni = 0, nf = 0, ns = 0;
    {
      const char* p = counts.data();
      const char* end = p + counts.size();
      const char* q = parse_int(p, end, ni);
      if (q && q < end && *q == '/') q = parse_int(q + 1, end, nf);
      else q = nullptr;
      if (q && q < end && *q == '/') q = parse_int(q + 1, end, ns);
      else q = nullptr;
      if (!q || q != end || ni < 0 || nf < 0 || ns < 0 || ni > 1000000 || nf > 1000000)
        in_.fail("tag '" + std::string(name) + "': expected counts 'ints/floats/strings', found '" +
                 TextCursor::printable(counts) + "'");
    }
    std::vector<std::int64_t> ints;
    std::vector<double> floats;
    for (std::int64_t i = 0; i < ni; ++i) ints.push_back(in_.integer("tag integer"));
    for (std::int64_t i = 0; i < nf; ++i) floats.push_back(in_.number("tag value"));
    for (std::int64_t i = 0; i < ns; ++i)
      if (in_.word().empty()) in_.fail("tag '" + std::string(name) + "' has fewer strings than declared");
    auto vertex_of = [&](std::int64_t v) -> std::uint32_t {
      if (v < 0 || v > std::numeric_limits<std::uint32_t>::max() - 1)
        in_.fail("tag '" + std::string(name) + "' names vertex " + std::to_string(v));
      tag_use_.note(v, in_.line());
      return static_cast<std::uint32_t>(v);
    };
    if (name == "crease") {
      if (ni < 2 || (nf != 1 && nf != ni - 1))
        in_.fail("crease tag needs 2+ vertices and 1 or one-per-edge sharpness values");
      for (std::int64_t i = 0; i + 1 < ni; ++i)
        soup_.creases.push_back({vertex_of(ints[i]), vertex_of(ints[i + 1]), floats[nf == 1 ? 0 : i]});
    } else if (name == "corner") {
      if (ni < 1 || (nf != 1 && nf != ni))
        in_.fail("corner tag needs 1+ vertices and 1 or one-per-vertex sharpness values");
      for (std::int64_t i = 0; i < ni; ++i)
        soup_.corners.push_back({vertex_of(ints[i]), floats[nf == 1 ? 0 : i]});
    } else if (name == "interpolateboundary") {
      if (ni != 1) in_.fail("interpolateboundary tag needs exactly one integer");
      soup_.boundary_interpolation = static_cast<int>(std::clamp<std::int64_t>(ints[0], -1000, 1000));
    }
    // Other tags (hole, creasemethod, smoothtriangles, facevarying…) have no place in a soup.
  }

  template <class T>
  void corner_values(const std::vector<std::int64_t>& refs, const std::vector<T>& values,
                     std::vector<T>& corners, std::vector<T>& per_vertex) {
    if (refs.empty()) return;
    corners.resize(refs.size());
    bool complete = true;
    for (std::size_t i = 0; i < refs.size(); ++i) {
      if (refs[i] == kNone) {
        corners[i] = T::Zero();
        complete = false;
      } else {
        corners[i] = values[static_cast<std::size_t>(refs[i])];
      }
    }
    if (!complete) return;
    // Per-vertex values too when every vertex's corners agree on one record.
    std::vector<std::int64_t> of_vertex(soup_.positions.size(), kNone);
    for (std::size_t i = 0; i < refs.size(); ++i) {
      std::int64_t& r = of_vertex[soup_.face_indices[i]];
      if (r == kNone) r = refs[i];
      else if (r != refs[i]) return;
    }
    per_vertex.assign(soup_.positions.size(), T::Zero());
    for (std::size_t v = 0; v < of_vertex.size(); ++v)
      if (of_vertex[v] != kNone) per_vertex[v] = values[static_cast<std::size_t>(of_vertex[v])];
  }

public:
  PolygonSoup finish() {
    const std::size_t nv = soup_.positions.size();
    if (v_use_.max >= static_cast<std::int64_t>(nv))
      in_.fail_at(v_use_.line, "vertex index " + std::to_string(v_use_.max + 1) + " out of range (file has " +
                                  std::to_string(nv) + " vertices)");
    if (vt_use_.max >= static_cast<std::int64_t>(vt_.size()))
      in_.fail_at(vt_use_.line, "texture index " + std::to_string(vt_use_.max + 1) + " out of range (file has " +
                                   std::to_string(vt_.size()) + " texture coordinates)");
    if (vn_use_.max >= static_cast<std::int64_t>(vn_.size()))
      in_.fail_at(vn_use_.line, "normal index " + std::to_string(vn_use_.max + 1) + " out of range (file has " +
                                   std::to_string(vn_.size()) + " normals)");
    if (tag_use_.max >= static_cast<std::int64_t>(nv))
      in_.fail_at(tag_use_.line, "tag names vertex " + std::to_string(tag_use_.max) + " but the file has " +
                                    std::to_string(nv) + " vertices");
    if (!soup_.vertex_colors.empty()) soup_.vertex_colors.resize(nv, Color::Zero());
    if (soup_.face_offsets.size() == 1) soup_.face_offsets.clear();
    corner_values(corner_vt_, vt_, soup_.corner_texcoords, soup_.vertex_texcoords);
    corner_values(corner_vn_, vn_, soup_.corner_normals, soup_.vertex_normals);
    soup_.face_objects = std::move(objects_).finish();
    soup_.face_groups = std::move(groups_).finish();
    soup_.face_materials = std::move(materials_).finish();
    return std::move(soup_);
  }

private:
  /// A relative index into an earlier piece: `local` is relative to this piece's first record.
  struct Fixup {
    std::uint8_t kind;  // 0 vertex, 1 texture, 2 normal
    std::size_t corner;
    std::int64_t local;
    std::int64_t index;  // as written, for the message
    std::uint64_t line;
  };

  TextCursor in_;
  bool chunk_ = false;
  std::vector<Fixup> fixups_;
  std::vector<std::size_t> relative_[3];  // corners holding a piece-relative index ≥ 0
  PolygonSoup soup_;
  std::vector<TexCoord> vt_;
  std::vector<Normal> vn_;
  std::vector<std::int64_t> corner_vt_, corner_vn_;
  IndexUse v_use_, vt_use_, vn_use_, tag_use_;
  FaceNameTrack objects_, groups_, materials_;
};

void append_vec(std::string& out, const char* key, const double* v, int n) {
  out += key;
  for (int i = 0; i < n; ++i) {
    out += ' ';
    append_double(out, v[i]);
  }
  out += '\n';
}

/// Unique values of a corner attribute (exact bits) and each corner's 1-based record.
template <class T>
std::vector<std::uint32_t> dedup(const std::vector<T>& values, std::vector<T>& unique) {
  std::vector<std::uint32_t> order(values.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  auto less = [&](std::uint32_t a, std::uint32_t b) {
    return std::memcmp(values[a].data(), values[b].data(), sizeof(T)) < 0;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::uint32_t> record(values.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (k == 0 || less(order[k - 1], order[k])) unique.push_back(values[order[k]]);
    record[order[k]] = static_cast<std::uint32_t>(unique.size());
  }
  return record;
}

}  // namespace

PolygonSoup read_obj(std::span<const std::byte> data, const std::string& name) {
  // Large files are cut at line ends into pieces parsed in parallel and merged in order;
  // small ones (and single-core machines) take the plain path.
  constexpr std::size_t kMinPiece = std::size_t{4} << 20;
  const std::size_t threads = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  const std::size_t pieces = std::min<std::size_t>({threads * 2, data.size() / kMinPiece, 64});
  if (pieces < 2) return ObjReader(data, name).run();
  const char* const begin = reinterpret_cast<const char*>(data.data());
  const char* const end = begin + data.size();
  std::vector<const char*> cut{begin};
  for (std::size_t k = 1; k < pieces; ++k) {
    const char* p = std::max(cut.back(), begin + data.size() * k / pieces);
    // After a newline that does not end a continued ("\\") line.
    for (;;) {
      const void* nl = p < end ? std::memchr(p, '\n', static_cast<std::size_t>(end - p)) : nullptr;
      if (!nl) {
        p = end;
        break;
      }
      const char* q = static_cast<const char*>(nl);
      const char* r = q;
      while (r > begin && r[-1] == '\r') --r;
      p = q + 1;
      if (!(r > begin && r[-1] == '\\')) break;
    }
    if (p >= end) break;
    if (p > cut.back()) cut.push_back(p);
  }
  cut.push_back(end);
  const std::size_t n = cut.size() - 1;
  std::vector<std::uint64_t> first_line(n + 1, 1);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
    first_line[k + 1] = static_cast<std::uint64_t>(std::count(cut[k], cut[k + 1], '\n'));
  });
  for (std::size_t k = 1; k <= n; ++k) first_line[k] += first_line[k - 1];
  std::vector<ObjReader> parts;
  parts.reserve(n);
  for (std::size_t k = 0; k < n; ++k)
    parts.emplace_back(std::span<const std::byte>(reinterpret_cast<const std::byte*>(cut[k]),
                                                  static_cast<std::size_t>(cut[k + 1] - cut[k])),
                       name, first_line[k], true);
  std::vector<std::optional<ParseError>> errors(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
    try {
      parts[k].parse();
    } catch (const ParseError& e) {
      errors[k] = e;
    }
  });
  for (const auto& e : errors)
    if (e) throw *e;  // the earliest piece's error, as a sequential read would report
  parts[0].merge(parts);
  return parts[0].finish();
}

void write_obj(const PolygonSoup& soup, const WriteOptions& options, std::string& out) {
  const std::size_t nv = soup.positions.size();
  out.reserve(nv * 40 + soup.face_indices.size() * 12 + 64);
  out += "# written by geom\n";
  for (const std::string& lib : soup.material_libraries) (out += "mtllib ") += lib + '\n';
  const bool colors = options.attributes && !soup.vertex_colors.empty();
  for (std::size_t v = 0; v < nv; ++v) {
    const Point& p = soup.positions[v];
    out += 'v';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_double(out, p[k]);
    }
    if (colors)
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        append_double(out, soup.vertex_colors[v][k]);
      }
    out += '\n';
  }
  // Corner attributes win over vertex ones: they carry seams that vertex values cannot.
  std::vector<std::uint32_t> vt_of, vn_of;
  bool vt_vertex = false, vn_vertex = false;
  if (options.attributes) {
    if (!soup.corner_texcoords.empty()) {
      std::vector<TexCoord> unique;
      vt_of = dedup(soup.corner_texcoords, unique);
      for (const auto& t : unique) append_vec(out, "vt", t.data(), 2);
    } else if (!soup.vertex_texcoords.empty()) {
      vt_vertex = true;
      for (const auto& t : soup.vertex_texcoords) append_vec(out, "vt", t.data(), 2);
    }
    if (!soup.corner_normals.empty()) {
      std::vector<Normal> unique;
      vn_of = dedup(soup.corner_normals, unique);
      for (const auto& n : unique) append_vec(out, "vn", n.data(), 3);
    } else if (!soup.vertex_normals.empty()) {
      vn_vertex = true;
      for (const auto& n : soup.vertex_normals) append_vec(out, "vn", n.data(), 3);
    }
  }
  const bool has_vt = vt_vertex || !vt_of.empty();
  const bool has_vn = vn_vertex || !vn_of.empty();
  for (std::size_t f = 0; f < soup.n_faces(); ++f) {
    write_face_name(soup.face_objects, "o", f, out);
    write_face_name(soup.face_groups, "g", f, out);
    write_face_name(soup.face_materials, "usemtl", f, out);
    out += 'f';
    for (std::uint32_t c = soup.face_offsets[f]; c < soup.face_offsets[f + 1]; ++c) {
      const std::uint32_t v = soup.face_indices[c];
      out += ' ';
      append_int(out, std::int64_t{v} + 1);
      if (has_vt || has_vn) {
        out += '/';
        if (has_vt) append_int(out, vt_vertex ? std::int64_t{v} + 1 : std::int64_t{vt_of[c]});
        if (has_vn) {
          out += '/';
          append_int(out, vn_vertex ? std::int64_t{v} + 1 : std::int64_t{vn_of[c]});
        }
      }
    }
    out += '\n';
  }
  if (soup.boundary_interpolation) {
    out += "t interpolateboundary 1/0/0 ";
    append_int(out, *soup.boundary_interpolation);
    out += '\n';
  }
  for (const auto& e : soup.creases) {
    out += "t crease 2/1/0 ";
    append_int(out, e.a);
    out += ' ';
    append_int(out, e.b);
    out += ' ';
    append_double(out, e.sharpness);
    out += '\n';
  }
  for (const auto& c : soup.corners) {
    out += "t corner 1/1/0 ";
    append_int(out, c.v);
    out += ' ';
    append_double(out, c.sharpness);
    out += '\n';
  }
}

}  // namespace geom::io_detail
