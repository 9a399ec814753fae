// The progressive-mesh stream (geom/lod/FORMAT.md): little-endian, base mesh first, then
// vertex splits; every read is checked against the bytes that remain.
#include <geom/lod/progressive_mesh.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <string>

namespace geom {

namespace {

constexpr std::uint8_t kMagic[8] = {0x89, 'G', 'P', 'M', 0x0D, 0x0A, 0x1A, 0x0A};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 28;
constexpr std::size_t kMinSplitBytes = 4 + 48 + 1 + 12 + 4;

class Writer {
 public:
  void bytes(const std::uint8_t* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) out.push_back(std::byte{p[i]});
  }
  void u8(std::uint8_t v) { out.push_back(std::byte{v}); }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(std::byte(static_cast<std::uint8_t>(v >> (8 * i))));
  }
  void f64(double d) {
    const auto v = std::bit_cast<std::uint64_t>(d);
    for (int i = 0; i < 8; ++i) out.push_back(std::byte(static_cast<std::uint8_t>(v >> (8 * i))));
  }
  void point(const Point& p) { f64(p.x()), f64(p.y()), f64(p.z()); }
  std::vector<std::byte> out;
};

class Reader {
 public:
  explicit Reader(std::span<const std::byte> d) : data_(d) {}
  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return data_.size() - pos_; }
  bool truncated() const { return truncated_; }
  void need(std::size_t n, const char* what) {
    if (remaining() < n) {
      truncated_ = true;
      throw DecodeError(pos_, std::string("truncated progressive mesh: ") + what + " needs " +
                                  std::to_string(n) + " bytes, " + std::to_string(remaining()) +
                                  " remain");
    }
  }
  std::uint8_t u8(const char* what) {
    need(1, what);
    return static_cast<std::uint8_t>(data_[pos_++]);
  }
  std::uint32_t u32(const char* what) {
    need(4, what);
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t(static_cast<std::uint8_t>(data_[pos_ + i])) << (8 * i);
    pos_ += 4;
    return v;
  }
  double f64(const char* what) {
    need(8, what);
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= std::uint64_t(static_cast<std::uint8_t>(data_[pos_ + i])) << (8 * i);
    pos_ += 8;
    const double d = std::bit_cast<double>(v);
    if (!std::isfinite(d)) throw DecodeError(pos_ - 8, std::string("non-finite coordinate in ") + what);
    return d;
  }
  Point point(const char* what) {
    const double x = f64(what), y = f64(what), z = f64(what);
    return {x, y, z};
  }

 private:
  std::span<const std::byte> data_;
  std::size_t pos_ = 0;
  bool truncated_ = false;
};

}  // namespace

std::vector<std::byte> ProgressiveMesh::encode() const {
  // The base level's positions and faces, from a copy brought down to the base.
  ProgressiveMesh base = *this;
  base.coarsen_to(base_vertices_);
  Writer w;
  w.out.reserve(kHeaderBytes + base_vertices_ * 24 + base_faces_ * 12 +
                splits_.size() * (kMinSplitBytes + 12 + 16) + corners_.size() * 4);
  w.bytes(kMagic, 8);
  w.u32(kVersion);
  w.u32(0);
  w.u32(static_cast<std::uint32_t>(base_vertices_));
  w.u32(static_cast<std::uint32_t>(base_faces_));
  w.u32(static_cast<std::uint32_t>(splits_.size()));
  for (std::size_t v = 0; v < base_vertices_; ++v) w.point(base.positions_[v]);
  for (std::size_t f = 0; f < base_faces_; ++f)
    for (std::uint32_t c : base.faces_[f]) w.u32(c);
  std::size_t faces = base_faces_;
  for (const VertexSplit& s : splits_) {
    w.u32(s.vertex);
    w.point(s.vertex_position);
    w.point(s.new_position);
    w.u8(s.n_faces);
    // Faces beyond the current level hold their corners as of their split, which only the
    // coarsened copy guarantees for every face.
    for (std::size_t f = faces; f < faces + s.n_faces; ++f)
      for (std::uint32_t c : base.faces_[f]) w.u32(c);
    faces += s.n_faces;
    w.u32(s.corner_end - s.corner_begin);
    for (std::uint32_t j = s.corner_begin; j < s.corner_end; ++j) w.u32(corners_[j]);
  }
  return std::move(w.out);
}

ProgressiveMesh ProgressiveMesh::decode(std::span<const std::byte> data, bool allow_partial) {
  Reader r(data);
  r.need(kHeaderBytes, "header");
  for (std::uint8_t m : kMagic)
    if (r.u8("magic") != m) throw DecodeError(r.offset() - 1, "not a progressive mesh stream (bad magic)");
  const std::uint32_t version = r.u32("version");
  if (version != kVersion)
    throw DecodeError(r.offset() - 4, "unsupported progressive mesh version " + std::to_string(version) +
                                          ", expected " + std::to_string(kVersion));
  const std::uint32_t flags = r.u32("flags");
  if (flags != 0) throw DecodeError(r.offset() - 4, "unknown flags " + std::to_string(flags) + ", expected 0");
  const std::uint32_t nv = r.u32("base vertex count");
  const std::uint32_t nf = r.u32("base face count");
  const std::uint32_t ns = r.u32("split count");
  const std::size_t base_bytes = std::size_t{nv} * 24 + std::size_t{nf} * 12;
  r.need(base_bytes, "base mesh");
  if (!allow_partial && std::size_t{ns} > (r.remaining() - base_bytes) / kMinSplitBytes)
    throw DecodeError(r.offset() - 4, "split count " + std::to_string(ns) +
                                          " exceeds what the remaining bytes can hold");
  const std::size_t splits_bound =
      std::min<std::size_t>(ns, (r.remaining() - base_bytes) / kMinSplitBytes);

  ProgressiveMesh pm;
  pm.base_vertices_ = nv;
  pm.base_faces_ = nf;
  pm.positions_.reserve(nv + splits_bound);
  pm.faces_.reserve(nf + 2 * splits_bound);
  for (std::uint32_t v = 0; v < nv; ++v) pm.positions_.push_back(r.point("base position"));
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::size_t at = r.offset();
    const std::array<std::uint32_t, 3> c{r.u32("base face"), r.u32("base face"), r.u32("base face")};
    if (c[0] >= nv || c[1] >= nv || c[2] >= nv || c[0] == c[1] || c[1] == c[2] || c[0] == c[2])
      throw DecodeError(at, "base face " + std::to_string(f) + " has an out-of-range or repeated corner");
    pm.faces_.push_back(c);
  }
  pm.n_vertices_ = nv;
  pm.n_faces_ = nf;
  pm.splits_.reserve(splits_bound);
  for (std::uint32_t i = 0; i < ns; ++i) {
    const std::size_t start = r.offset();
    try {
      VertexSplit s;
      const auto added = static_cast<std::uint32_t>(pm.n_vertices_);
      s.vertex = r.u32("split vertex");
      if (s.vertex >= added)
        throw DecodeError(start, "split " + std::to_string(i) + ": vertex " + std::to_string(s.vertex) +
                                     " does not exist yet (" + std::to_string(added) + " vertices)");
      s.vertex_position = r.point("split position");
      s.new_position = r.point("split position");
      s.coarse_position = pm.positions_[s.vertex];
      s.n_faces = r.u8("split face count");
      if (s.n_faces != 1 && s.n_faces != 2)
        throw DecodeError(r.offset() - 1, "split " + std::to_string(i) + ": face count " +
                                              std::to_string(s.n_faces) + ", expected 1 or 2");
      std::array<std::array<std::uint32_t, 3>, 2> nfaces{};
      for (int f = 0; f < s.n_faces; ++f) {
        const std::size_t at = r.offset();
        auto& c = nfaces[f];
        c = {r.u32("split face"), r.u32("split face"), r.u32("split face")};
        const bool has_v = c[0] == s.vertex || c[1] == s.vertex || c[2] == s.vertex;
        const bool has_new = c[0] == added || c[1] == added || c[2] == added;
        if (c[0] > added || c[1] > added || c[2] > added || c[0] == c[1] || c[1] == c[2] ||
            c[0] == c[2] || !has_v || !has_new)
          throw DecodeError(at, "split " + std::to_string(i) +
                                    ": a new face must join the split vertex, the new vertex and an "
                                    "existing vertex");
      }
      const std::uint32_t m = r.u32("corner count");
      r.need(std::size_t{m} * 4, "corner list");
      s.corner_begin = static_cast<std::uint32_t>(pm.corners_.size());
      for (std::uint32_t j = 0; j < m; ++j) {
        const std::size_t at = r.offset();
        const std::uint32_t c = r.u32("corner");
        if (c / 3 >= pm.n_faces_ || pm.faces_[c / 3][c % 3] != s.vertex)
          throw DecodeError(at, "split " + std::to_string(i) + ": corner " + std::to_string(c) +
                                    " is not a corner of vertex " + std::to_string(s.vertex));
        pm.corners_.push_back(c);
      }
      s.corner_end = static_cast<std::uint32_t>(pm.corners_.size());
      // Commit: the split is whole.
      for (int f = 0; f < s.n_faces; ++f) pm.faces_.push_back(nfaces[f]);
      pm.positions_.push_back(s.new_position);
      pm.splits_.push_back(s);
      pm.face_prefix_.push_back(pm.n_faces_ + s.n_faces);
      pm.split(pm.splits_.size() - 1);
    } catch (const DecodeError&) {
      // A cut inside the last record is what a streaming reader sees; anything else is
      // corruption.
      if (!allow_partial || !r.truncated()) throw;
      pm.corners_.resize(pm.splits_.empty() ? 0 : pm.splits_.back().corner_end);
      break;
    }
  }
  if (!allow_partial && r.remaining() != 0)
    throw DecodeError(r.offset(), std::to_string(r.remaining()) + " trailing bytes after the last split");
  pm.vertex_origin_.resize(pm.positions_.size());
  for (std::size_t v = 0; v < pm.vertex_origin_.size(); ++v) pm.vertex_origin_[v] = Vertex(static_cast<std::uint32_t>(v));
  pm.face_origin_.resize(pm.faces_.size());
  for (std::size_t f = 0; f < pm.face_origin_.size(); ++f) pm.face_origin_[f] = static_cast<std::uint32_t>(f);
  return pm;
}

}  // namespace geom
