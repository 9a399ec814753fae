#include <geom/isosurface/marching_cubes.h>

#include <geom/core/soup.h>
#include <geom/isosurface/mc_tables.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

namespace geom {

namespace {

// Crossings are kept this far from the edge ends so that vertices on different edges never
// coincide, even when a sample equals the level (see the tie rule in the header).
constexpr double kMinT = 1.0 / 1024.0;
// Triangle corners that name a vertex owned by the next chunk (its first layer, by rank).
constexpr std::uint32_t kForeign = 1u << 31;

struct ChunkOut {
  std::vector<Point> positions;
  std::vector<Normal> normals;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  MarchingCubesStats stats;
  bool boundary_above = false, boundary_below = false, has_nan = false;
};

/// The threshold t of type T with (v >= t) ⟺ (double(v) >= level) for every T value v.
template <class T>
T threshold_for(double level) {
  if constexpr (std::is_same_v<T, double>) {
    return level;
  } else {
    float t = static_cast<float>(level);
    if (static_cast<double>(t) < level) t = std::nextafter(t, std::numeric_limits<float>::infinity());
    return t;
  }
}

template <class T>
class Extractor {
 public:
  Extractor(const T* values, const GridView& grid, const MarchingCubesOptions& options)
      : v_(values),
        nx_(grid.dims.nx),
        ny_(grid.dims.ny),
        nz_(grid.dims.nz),
        words_((grid.dims.nx + 63) / 64),
        origin_(grid.geometry.origin),
        spacing_(grid.geometry.spacing),
        level_(options.level),
        threshold_(threshold_for<T>(options.level)),
        normals_(options.compute_normals),
        flip_(options.normals_toward == NormalDirection::kDecreasing),
        tables_(detail::mc_tables()) {}

  /// Cells of slabs [z0, z1): layers z0 … z1. The chunk owns the vertices on layer z0's
  /// x/y edges, on all z edges and on interior layers; layer z1's belong to the next chunk
  /// unless z1 is the last layer.
  void run(std::size_t z0, std::size_t z1, ChunkOut& out) const {
    const std::size_t plane = nx_ * ny_;
    std::vector<std::uint64_t> bits_a(words_ * ny_), bits_b(words_ * ny_);
    std::unique_ptr<std::uint32_t[]> xa(new std::uint32_t[plane]), ya(new std::uint32_t[plane]),
        xb(new std::uint32_t[plane]), yb(new std::uint32_t[plane]), zs(new std::uint32_t[plane]);
    std::uint64_t* bot = bits_a.data();
    std::uint64_t* top = bits_b.data();
    std::uint32_t *xbot = xa.get(), *ybot = ya.get(), *xtop = xb.get(), *ytop = yb.get();

    classify(z0, bot, out);
    layer_vertices(z0, bot, xbot, ybot, true, out);
    for (std::size_t z = z0; z < z1; ++z) {
      classify(z + 1, top, out);
      if (out.has_nan) return;
      z_vertices(z, bot, top, zs.get(), out);
      bool own_top = z + 1 < z1 || z + 1 == nz_ - 1;
      layer_vertices(z + 1, top, xtop, ytop, own_top, out);
      cells(z, bot, top, xbot, ybot, xtop, ytop, zs.get(), out);
      std::swap(bot, top);
      std::swap(xbot, xtop);
      std::swap(ybot, ytop);
    }
  }

 private:
  T value(std::size_t x, std::size_t y, std::size_t z) const { return v_[x + nx_ * (y + ny_ * z)]; }

  /// One bit per sample of layer z (value ≥ level), plus NaN and grid-boundary bookkeeping.
  void classify(std::size_t z, std::uint64_t* bits, ChunkOut& out) const {
    const T* layer = v_ + nx_ * ny_ * z;
    const T t = threshold_;
    bool nan = false;
    for (std::size_t y = 0; y < ny_; ++y) {
      const T* row = layer + y * nx_;
      std::uint64_t* w = bits + y * words_;
      for (std::size_t wi = 0; wi < words_; ++wi) {
        const std::size_t x0 = wi * 64;
        const std::size_t n = std::min<std::size_t>(64, nx_ - x0);
        std::uint64_t m = 0;
        bool word_nan = false;
        if (n == 64) {
          m = classify64(row + x0, t, word_nan);
        } else {
          for (std::size_t b = 0; b < n; ++b) {
            T s = row[x0 + b];
            m |= std::uint64_t(s >= t) << b;
            word_nan |= s != s;
          }
        }
        w[wi] = m;
        nan |= word_nan;
      }
      // Grid boundary samples: the whole first/last layer and row, the row ends elsewhere.
      const bool full = z == 0 || z == nz_ - 1 || y == 0 || y == ny_ - 1;
      for (std::size_t wi = 0; wi < words_; ++wi) {
        const std::size_t n = std::min<std::size_t>(64, nx_ - wi * 64);
        std::uint64_t valid = n == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1;
        if (!full) {
          valid &= (wi == 0 ? std::uint64_t(1) : 0) |
                   (wi == words_ - 1 ? std::uint64_t(1) << (n - 1) : 0);
        }
        out.boundary_above |= (w[wi] & valid) != 0;
        out.boundary_below |= (~w[wi] & valid) != 0;
      }
    }
    out.has_nan |= nan;
  }

  /// Bits (v >= t) of 64 samples; SSE2 on x86-64 (its baseline), scalar elsewhere.
  static std::uint64_t classify64(const T* p, T t, bool& nan) {
#if defined(__SSE2__)
    std::uint64_t m = 0;
    if constexpr (std::is_same_v<T, float>) {
      const __m128 tv = _mm_set1_ps(t);
      __m128 unordered = _mm_setzero_ps();
      for (int b = 0; b < 64; b += 4) {
        __m128 v = _mm_loadu_ps(p + b);
        m |= std::uint64_t(_mm_movemask_ps(_mm_cmpge_ps(v, tv))) << b;
        unordered = _mm_or_ps(unordered, _mm_cmpunord_ps(v, v));
      }
      nan |= _mm_movemask_ps(unordered) != 0;
    } else {
      const __m128d tv = _mm_set1_pd(t);
      __m128d unordered = _mm_setzero_pd();
      for (int b = 0; b < 64; b += 2) {
        __m128d v = _mm_loadu_pd(p + b);
        m |= std::uint64_t(_mm_movemask_pd(_mm_cmpge_pd(v, tv))) << b;
        unordered = _mm_or_pd(unordered, _mm_cmpunord_pd(v, v));
      }
      nan |= _mm_movemask_pd(unordered) != 0;
    }
    return m;
#else
    std::uint64_t m = 0;
    for (int b = 0; b < 64; ++b) {
      m |= std::uint64_t(p[b] >= t) << b;
      nan |= p[b] != p[b];
    }
    return m;
#endif
  }

  double t_of(double a, double b) const {
    double t = (level_ - a) / (b - a);
    return t > kMinT ? (t < 1.0 - kMinT ? t : 1.0 - kMinT) : kMinT;  // NaN (±inf ends) → kMinT
  }

  Eigen::Vector3d gradient(std::size_t x, std::size_t y, std::size_t z) const {
    const std::size_t n[3] = {nx_, ny_, nz_};
    const std::size_t c[3] = {x, y, z};
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      if (n[k] < 2) continue;
      // Central differences inside, one-sided at the grid boundary.
      std::size_t lo[3] = {x, y, z}, hi[3] = {x, y, z};
      lo[k] = c[k] > 0 ? c[k] - 1 : 0;
      hi[k] = c[k] + 1 < n[k] ? c[k] + 1 : c[k];
      double h = spacing_[k] * double(hi[k] - lo[k]);
      g[k] = (double(value(hi[0], hi[1], hi[2])) - double(value(lo[0], lo[1], lo[2]))) / h;
    }
    return g;
  }

  /// Crossing on the edge from sample (x, y, z) one step along axis.
  Point edge_point(std::size_t x, std::size_t y, std::size_t z, int axis, double* t_out = nullptr) const {
    std::size_t x1 = x + (axis == 0), y1 = y + (axis == 1), z1 = z + (axis == 2);
    double t = t_of(double(value(x, y, z)), double(value(x1, y1, z1)));
    if (t_out) *t_out = t;
    Eigen::Vector3d g{double(x), double(y), double(z)};
    g[axis] += t;
    return origin_ + g.cwiseProduct(spacing_);
  }

  Normal edge_normal(std::size_t x, std::size_t y, std::size_t z, int axis, double t) const {
    std::size_t x1 = x + (axis == 0), y1 = y + (axis == 1), z1 = z + (axis == 2);
    Eigen::Vector3d g = (1.0 - t) * gradient(x, y, z) + t * gradient(x1, y1, z1);
    double len = g.norm();
    if (!(len > 0) || !std::isfinite(len)) return Normal::Zero();
    return (flip_ ? -g : g) / len;
  }

  std::uint32_t new_vertex(std::size_t x, std::size_t y, std::size_t z, int axis, ChunkOut& out) const {
    double t;
    out.positions.push_back(edge_point(x, y, z, axis, &t));
    if (normals_) out.normals.push_back(edge_normal(x, y, z, axis, t));
    ++out.stats.edge_vertices;
    return static_cast<std::uint32_t>(out.positions.size() - 1);
  }

  /// Vertices on layer z's crossed x and y edges, row by row (x edges, then y edges). A
  /// foreign layer is enumerated in the same order so ranks match the owner's indices.
  void layer_vertices(std::size_t z, const std::uint64_t* bits, std::uint32_t* xs,
                      std::uint32_t* ys, bool own, ChunkOut& out) const {
    std::uint32_t rank = 0;
    for (std::size_t y = 0; y < ny_; ++y) {
      const std::uint64_t* row = bits + y * words_;
      for (std::size_t wi = 0; wi < words_; ++wi) {
        std::uint64_t next = wi + 1 < words_ ? row[wi + 1] : 0;
        std::uint64_t c = (row[wi] ^ ((row[wi] >> 1) | (next << 63))) & edge_mask(wi, nx_ - 1);
        while (c) {
          std::size_t x = wi * 64 + std::countr_zero(c);
          c &= c - 1;
          xs[y * nx_ + x] = own ? new_vertex(x, y, z, 0, out) : (kForeign | rank++);
        }
      }
      if (y + 1 == ny_) break;
      const std::uint64_t* row2 = row + words_;
      for (std::size_t wi = 0; wi < words_; ++wi) {
        std::uint64_t c = row[wi] ^ row2[wi];
        while (c) {
          std::size_t x = wi * 64 + std::countr_zero(c);
          c &= c - 1;
          ys[y * nx_ + x] = own ? new_vertex(x, y, z, 1, out) : (kForeign | rank++);
        }
      }
    }
  }

  void z_vertices(std::size_t z, const std::uint64_t* bot, const std::uint64_t* top,
                  std::uint32_t* zs, ChunkOut& out) const {
    for (std::size_t y = 0; y < ny_; ++y)
      for (std::size_t wi = 0; wi < words_; ++wi) {
        std::uint64_t c = bot[y * words_ + wi] ^ top[y * words_ + wi];
        while (c) {
          std::size_t x = wi * 64 + std::countr_zero(c);
          c &= c - 1;
          zs[y * nx_ + x] = new_vertex(x, y, z, 2, out);
        }
      }
  }

  /// Bits of word wi that index positions < limit.
  static std::uint64_t edge_mask(std::size_t wi, std::size_t limit) {
    std::size_t x0 = wi * 64;
    if (limit <= x0) return 0;
    std::size_t n = limit - x0;
    return n >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1;
  }

  static unsigned bit2(const std::uint64_t* row, std::size_t x) {
    unsigned b0 = unsigned(row[x >> 6] >> (x & 63)) & 1u;
    unsigned b1 = unsigned(row[(x + 1) >> 6] >> ((x + 1) & 63)) & 1u;
    return b0 | (b1 << 1);
  }

  void cells(std::size_t z, const std::uint64_t* bot, const std::uint64_t* top,
             const std::uint32_t* xbot, const std::uint32_t* ybot, const std::uint32_t* xtop,
             const std::uint32_t* ytop, const std::uint32_t* zs, ChunkOut& out) const {
    const auto& cases = tables_.cases;
    for (std::size_t y = 0; y + 1 < ny_; ++y) {
      const std::uint64_t* r00 = bot + y * words_;
      const std::uint64_t* r10 = r00 + words_;
      const std::uint64_t* r01 = top + y * words_;
      const std::uint64_t* r11 = r01 + words_;
      for (std::size_t wi = 0; wi < words_; ++wi) {
        std::uint64_t any = r00[wi] | r10[wi] | r01[wi] | r11[wi];
        std::uint64_t all = r00[wi] & r10[wi] & r01[wi] & r11[wi];
        std::uint64_t any_n = 0, all_n = 0;
        if (wi + 1 < words_) {
          any_n = r00[wi + 1] | r10[wi + 1] | r01[wi + 1] | r11[wi + 1];
          all_n = r00[wi + 1] & r10[wi + 1] & r01[wi + 1] & r11[wi + 1];
        }
        std::uint64_t any2 = any | (any >> 1) | (any_n << 63);
        std::uint64_t all2 = all & ((all >> 1) | (all_n << 63));
        std::uint64_t active = any2 & ~all2 & edge_mask(wi, nx_ - 1);
        while (active) {
          std::size_t x = wi * 64 + std::countr_zero(active);
          active &= active - 1;
          unsigned ci = bit2(r00, x) | bit2(r10, x) << 2 | bit2(r01, x) << 4 | bit2(r11, x) << 6;
          cell(x, y, z, cases[ci], xbot, ybot, xtop, ytop, zs, out);
        }
      }
    }
  }

  void cell(std::size_t x, std::size_t y, std::size_t z, const detail::McCase& mc,
            const std::uint32_t* xbot, const std::uint32_t* ybot, const std::uint32_t* xtop,
            const std::uint32_t* ytop, const std::uint32_t* zs, ChunkOut& out) const {
    ++out.stats.active_cells;
    std::uint32_t entry_index = mc.first_entry;
    double f[8];
    auto load = [&] {
      for (int c = 0; c < 8; ++c)
        f[c] = double(value(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2))) - level_;
    };
    if (mc.n_ambiguous) {
      load();
      for (int j = 0; j < mc.n_ambiguous; ++j) {
        const detail::McAmbiguousFace& af = mc.ambiguous[j];
        // Products of the same two samples are bitwise equal in either cube, so both
        // sides of the face take the same decision.
        if (f[af.above0] * f[af.above1] >= f[af.below0] * f[af.below1]) entry_index += 1u << j;
      }
      out.stats.ambiguous_faces += mc.n_ambiguous;
    }
    const detail::McEntry* chosen = &tables_.entries[entry_index];
    if (chosen->n_tunnels) {
      if (!mc.n_ambiguous) load();
      for (int j = 0; j < chosen->n_tunnels; ++j) {
        const detail::McTunnel& tn = chosen->tunnels[j];
        if (detail::interior_connected(f, tn.corner0, tn.corner1, tn.above)) {
          chosen = &tables_.entries[tn.entry];
          ++out.stats.tunnels;
          break;
        }
      }
    }
    const detail::McEntry& entry = *chosen;
    std::uint32_t vid[16];
    const std::size_t row = y * nx_ + x;
    std::uint32_t mask = mc.edge_mask;
    while (mask) {
      int e = std::countr_zero(mask);
      mask &= mask - 1;
      if (e < 4) {
        vid[e] = ((e >> 1) ? xtop : xbot)[row + (e & 1) * nx_];
      } else if (e < 8) {
        int k = e - 4;
        vid[e] = ((k >> 1) ? ytop : ybot)[row + (k & 1)];
      } else {
        int k = e - 8;
        vid[e] = zs[row + (k & 1) + (k >> 1) * nx_];
      }
    }
    for (int j = 0; j < entry.n_centroids; ++j) {
      Point p = Point::Zero();
      Normal n = Normal::Zero();
      int count = 0;
      std::uint32_t m = entry.centroid_mask[j];
      while (m) {
        int e = std::countr_zero(m);
        m &= m - 1;
        int c0 = detail::kEdgeCorners[e][0];
        int axis = e / 4;
        std::size_t ex = x + (c0 & 1), ey = y + ((c0 >> 1) & 1), ez = z + (c0 >> 2);
        double t;
        p += edge_point(ex, ey, ez, axis, &t);
        if (normals_) n += edge_normal(ex, ey, ez, axis, t);
        ++count;
      }
      p /= count;
      if ((entry.centroid_inward >> j) & 1)
        p = 0.5 * (p + origin_ + Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5).cwiseProduct(spacing_));
      out.positions.push_back(p);
      if (normals_) {
        double len = n.norm();
        out.normals.push_back(len > 0 ? Normal(n / len) : Normal::Zero());
      }
      ++out.stats.centroid_vertices;
      vid[12 + j] = static_cast<std::uint32_t>(out.positions.size() - 1);
    }
    const std::uint8_t* refs = tables_.refs.data() + entry.first_ref;
    for (int k = 0; k < entry.n_triangles; ++k, refs += 3) {
      if (flip_)
        out.triangles.push_back({vid[refs[0]], vid[refs[2]], vid[refs[1]]});
      else
        out.triangles.push_back({vid[refs[0]], vid[refs[1]], vid[refs[2]]});
    }
  }

  const T* v_;
  std::size_t nx_, ny_, nz_, words_;
  Eigen::Vector3d origin_, spacing_;
  double level_;
  T threshold_;
  bool normals_, flip_;
  const detail::McTables& tables_;
};

template <class T>
[[noreturn]] void throw_first_nan(const T* v, const GridDims& d) {
  for (std::size_t z = 0; z < d.nz; ++z)
    for (std::size_t y = 0; y < d.ny; ++y)
      for (std::size_t x = 0; x < d.nx; ++x)
        if (std::isnan(v[d.index(x, y, z)]))
          throw InvalidArgument("grid sample (x=" + std::to_string(x) + ", y=" + std::to_string(y) +
                                ", z=" + std::to_string(z) + ") is NaN; expected finite values");
  throw InvalidArgument("grid holds a NaN sample");
}

template <class T>
IsoSurface extract(const T* values, const GridView& grid, const MarchingCubesOptions& options) {
  IsoSurface result;
  const GridDims& d = grid.dims;
  result.stats.cells = d.nx > 1 && d.ny > 1 && d.nz > 1 ? (d.nx - 1) * (d.ny - 1) * (d.nz - 1) : 0;
  if (d.size() == 0) return result;
  Extractor<T> ex(values, grid, options);
  const std::size_t slabs = d.nz - 1;

  std::size_t n_chunks = 1;
  if (options.parallel && slabs > 1) {
    std::size_t threads = static_cast<std::size_t>(tbb::this_task_arena::max_concurrency());
    if (threads > 1) n_chunks = std::min(slabs, 4 * threads);
  }
  std::vector<ChunkOut> chunks(std::max<std::size_t>(n_chunks, 1));
  auto chunk_begin = [&](std::size_t c) { return slabs * c / n_chunks; };
  if (slabs == 0 || d.nx < 2 || d.ny < 2) {
    // No cells, but NaN must still be reported.
    for (std::size_t i = 0; i < d.size(); ++i)
      if (std::isnan(values[i])) throw_first_nan(values, d);
    return result;
  }
  if (n_chunks == 1) {
    ex.run(0, slabs, chunks[0]);
  } else {
    tbb::parallel_for(std::size_t(0), n_chunks, [&](std::size_t c) {
      ex.run(chunk_begin(c), chunk_begin(c + 1), chunks[c]);
    });
  }
  bool boundary_above = false, boundary_below = false;
  for (const ChunkOut& c : chunks) {
    if (c.has_nan) throw_first_nan(values, d);
    boundary_above |= c.boundary_above;
    boundary_below |= c.boundary_below;
  }

  std::vector<std::size_t> vertex_offset(n_chunks + 1, 0), tri_offset(n_chunks + 1, 0);
  for (std::size_t c = 0; c < n_chunks; ++c) {
    vertex_offset[c + 1] = vertex_offset[c] + chunks[c].positions.size();
    tri_offset[c + 1] = tri_offset[c] + chunks[c].triangles.size();
  }
  if (vertex_offset[n_chunks] >= kForeign)
    throw InvalidArgument("iso-surface has " + std::to_string(vertex_offset[n_chunks]) +
                          " vertices, more than 32-bit indices allow");
  if (n_chunks == 1) {
    // One chunk owns every layer, so it has no foreign references: no renumbering.
    result.positions = std::move(chunks[0].positions);
    result.normals = std::move(chunks[0].normals);
    result.triangles = std::move(chunks[0].triangles);
  } else {
    result.positions.resize(vertex_offset[n_chunks]);
    result.triangles.resize(tri_offset[n_chunks]);
    if (options.compute_normals) result.normals.resize(vertex_offset[n_chunks]);
  }
  auto merge = [&](std::size_t c) {
    const ChunkOut& ch = chunks[c];
    std::copy(ch.positions.begin(), ch.positions.end(), result.positions.begin() + vertex_offset[c]);
    if (options.compute_normals)
      std::copy(ch.normals.begin(), ch.normals.end(), result.normals.begin() + vertex_offset[c]);
    const std::uint32_t own = static_cast<std::uint32_t>(vertex_offset[c]);
    const std::uint32_t next = static_cast<std::uint32_t>(vertex_offset[std::min(c + 1, n_chunks)]);
    auto* dst = result.triangles.data() + tri_offset[c];
    for (const auto& t : ch.triangles) {
      for (int k = 0; k < 3; ++k)
        (*dst)[k] = (t[k] & kForeign) ? next + (t[k] & ~kForeign) : own + t[k];
      ++dst;
    }
  };
  if (n_chunks > 1) tbb::parallel_for(std::size_t(0), n_chunks, merge);

  MarchingCubesStats& s = result.stats;
  for (const ChunkOut& c : chunks) {
    s.edge_vertices += c.stats.edge_vertices;
    s.centroid_vertices += c.stats.centroid_vertices;
    s.active_cells += c.stats.active_cells;
    s.ambiguous_faces += c.stats.ambiguous_faces;
    s.tunnels += c.stats.tunnels;
  }
  s.vertices = result.positions.size();
  s.triangles = result.triangles.size();
  s.closed = !(boundary_above && boundary_below);
  return result;
}

}  // namespace

IsoSurface marching_cubes_arrays(const GridView& grid, const MarchingCubesOptions& options) {
  grid.check();
  if (!std::isfinite(options.level))
    throw InvalidArgument("iso level must be finite, found " + std::to_string(options.level));
  if (grid.values.index() == 0)
    return extract(std::get<0>(grid.values).data(), grid, options);
  return extract(std::get<1>(grid.values).data(), grid, options);
}

MarchingCubesResult marching_cubes(const GridView& grid, const MarchingCubesOptions& options) {
  IsoSurface s = marching_cubes_arrays(grid, options);
  MarchingCubesResult result;
  result.mesh = mesh_from_triangles(s.positions, s.triangles);
  if (options.compute_normals) {
    auto normals = result.mesh.add_property<Vertex, Normal>(prop::kVertexNormal);
    for (std::size_t i = 0; i < s.normals.size(); ++i)
      normals[Vertex(static_cast<std::uint32_t>(i))] = s.normals[i];
  }
  result.stats = s.stats;
  return result;
}

}  // namespace geom
