#pragma once
/// \file
/// The edge-collapse engine behind simplify() and ProgressiveMesh: flat triangle arrays,
/// per-vertex incident-triangle lists, Garland–Heckbert quadrics and a monotone priority
/// queue. Internal to geom/lod. The constructor (collapse_setup.cpp) builds them on all
/// cores, with the same result on any number. On a large mesh the collapses run on all cores
/// too, region by region (collapse_loop.cpp), again with the same result on any number.
///
/// Queue entries carry the sum of their endpoints' stamps (stamps only grow, so an equal
/// sum means neither changed). A collapse queues every edge of the survivor at its new
/// cost while that neighbourhood is in cache; the queue drops the old entries unevaluated
/// when it next passes over them.
///
/// The queue orders by cost / √(merged face weight) (see priority(); along a boundary that
/// weight is capped by the boundary planes' weight). A collapse only adds
/// quadrics, so costs grow, and in practice faster than that root: the minimum almost never
/// decreases (the exceptions, about one push in 400 on a noisy torus, and those from
/// round-off or the endpoint fallback, are queued at the current minimum). The queue is
/// therefore a radix heap over the key's float bits (Ahuja, Mehlhorn, Orlin, Tarjan 1990)
/// rather than a comparison heap: a push appends to one of 33 buckets and an entry only
/// ever moves to lower buckets, in sequential passes. A 4-ary heap of a million edges spent
/// most of its time on cache misses in sift-down.
///
/// Memory, not arithmetic, bounds the main loop: each collapse lands somewhere random on
/// the surface. So what a collapse reads of a vertex and its neighbours (quadric, position,
/// mark, triangle list, flags) sits in one two-line record (VertexData), triangle lists
/// hold live triangles only (a dead one leaves its three lists at once), and the big arrays
/// ask for huge pages. And since the queue knows the next few collapses, their data is
/// fetched ahead, link by link of the chain record → list → triangles → neighbours, so
/// the misses of several collapses overlap instead of stalling one after another.

#include <geom/core/surface_mesh.h>
#include <geom/lod/attribute_quadric.h>
#include <geom/lod/quadric.h>
#include <geom/lod/simplify.h>

#include <array>
#include <bit>
#include <cstdint>
#include <memory>
#include <vector>

namespace geom::detail {

inline constexpr std::uint32_t kNone = 0xffffffffu;

/// One performed collapse: vertex u merged into v, v moved to pos_v_after.
struct CollapseRecord {
  std::uint32_t u = kNone, v = kNone;
  Point pos_u, pos_v_before, pos_v_after;
  /// Corners (3 × triangle + slot) that held u and now hold v:
  /// changed[changed_begin .. changed_end).
  std::uint32_t changed_begin = 0, changed_end = 0;
  /// Triangles removed; dead[1] == kNone for a boundary edge.
  std::array<std::uint32_t, 2> dead{kNone, kNone};
};

class CollapseEngine {
 public:
  /// Pre: mesh is a valid SurfaceMesh. Throws: InvalidArgument on bad options.
  /// Meshes of at least parallel_min_triangles run their collapses region by region on all
  /// cores (never when recording).
  CollapseEngine(const SurfaceMesh& mesh, const SimplifyOptions& options, bool record,
                 std::size_t parallel_min_triangles = kParallelMinTriangles);
  // From 50k rather than 100k triangles since the singular quadrics got cheap (the serial
  // collapses were then the bulk of a mid-size mesh's time): the bunny, armadillo and
  // nefertiti (70-100k) simplify 16-29% faster on 2 cores, every error cell of bench_lod stays
  // a win, by as little as 0.991× (armadillo 1%, Hausdorff 0.914× serially; the region order
  // moves the single worst point by about as much as 1% jitter of the priorities does).
  // Below, fandisk (13k) lost 2 cells: a part of a thousand triangles is mostly seam.
  static constexpr std::size_t kParallelMinTriangles = 50000;

  /// Collapse until at most target triangles remain or nothing valid is left.
  SimplifyStop run(std::size_t target_triangles);

  std::size_t n_triangles_initial() const { return triangles_.size(); }
  std::size_t n_triangles() const { return alive_triangles_; }
  std::size_t n_collapses() const;
  double max_error() const;
  /// Regions collapsed in parallel (0: the collapses run on one core).
  std::size_t n_parts() const { return parts_; }

  /// Dense vertex i is mesh vertex vertex_of()[i] (isolated vertices are left out).
  const std::vector<Vertex>& vertex_of() const { return vertex_of_; }
  /// Input positions (model units) and triangles, as they were before any collapse.
  const std::vector<Point>& original_positions() const { return original_positions_; }
  const std::vector<std::array<std::uint32_t, 3>>& original_triangles() const {
    return original_triangles_;
  }
  const std::vector<CollapseRecord>& records() const { return records_; }
  const std::vector<std::uint32_t>& changed() const { return changed_; }

  /// Current state: a vertex's position (model units), triangles and which of them are
  /// alive, and whether a vertex still has live triangles.
  Point model(std::uint32_t v) const {
    return vd_[v].moved ? Point(center_ + scale_ * vd_[v].p) : model_[v];
  }
  const std::vector<std::array<std::uint32_t, 3>>& triangles() const { return triangles_; }
  bool triangle_alive(std::uint32_t t) const { return tri_alive_[t] != 0; }
  bool vertex_alive(std::uint32_t v) const { return vd_[v].ref_size != 0; }

  /// The current mesh; out_origin receives the input vertex of each output vertex. With
  /// options.refit_iterations != 0, out_survivor (if given, sized to the input's
  /// vertices_size()) receives for each input vertex the output vertex it was merged into.
  /// out_triangle (if given) receives the engine's triangle each output face is.
  SurfaceMesh extract(std::vector<Vertex>* out_origin, std::vector<Vertex>* out_survivor = nullptr,
                      std::vector<std::uint32_t>* out_triangle = nullptr) const;
  /// With options.refit_iterations != 0 (and not recording): a third of the area of each
  /// input vertex's triangles as the engine split them (model units², by input vertex index,
  /// sized input_vertices; 0 for a vertex no face uses), the refit's vertex sample weights.
  /// Empty otherwise.
  std::vector<double> input_vertex_areas(std::size_t input_vertices) const;

 private:
  // What the main loop reads of a vertex and of its neighbours, together in two cache lines
  // rather than spread over a dozen arrays.
  struct alignas(64) VertexData {
    Quadric q;
    Point p;  // normalised
    std::uint32_t mark = 0;
    // Live incident triangles: refs_[ref_begin .. ref_begin + ref_size); none once removed.
    std::uint32_t ref_begin = 0, ref_size = 0;
    std::uint8_t boundary = 0, locked = 0, retry = 0;
    // Placed at a new position by a collapse: its model position is then derived from p.
    std::uint8_t moved = 0;
    // Face plane weight (area) merged into the vertex, normalised units: the queue's
    // priority reads it for every neighbour, so it lives here rather than in its own array.
    double weight = 0;
  };
  static_assert(sizeof(VertexData) == 128, "VertexData is two cache lines");
  struct Candidate {
    float cost;
    std::uint32_t a, b, stamps;
  };
  // The first entries of the queue, listed by one block of vertices (the constructor).
  struct EdgeBlock {
    std::unique_ptr<Candidate[]> edges;
    std::size_t size = 0;
  };
  /// The next few entries wait, in order, in a small ring outside the buckets; pushes
  /// cheaper than the buckets' minimum are inserted there. Entries pushed below the last
  /// popped cost (possible only through round-off or the endpoint fallback of the
  /// placement) therefore come out next.
  class RadixQueue {
   public:
    /// Entries whose stamps no longer match these (one per vertex) are outdated.
    void watch(const std::uint32_t* stamps) { stamps_ = stamps; }
    void push(Candidate c);
    /// Start from the entries of these blocks, in order (queue empty), placed in chunks of
    /// one slab sized for them all.
    void assign(const std::vector<EdgeBlock>& blocks);
    /// Move the current entries out (those taken ahead first, then bucket by bucket) and
    /// leave the queue empty, its memory freed.
    EdgeBlock release();
    /// Remove a current entry of the smallest cost into out; false when none is left.
    bool pop(Candidate& out) {
      const Candidate* c = top();
      if (!c) return false;
      out = *c;
      drop_top();
      return true;
    }
    /// A current entry of the smallest cost, left in the queue; null when none is left.
    const Candidate* top();
    void drop_top() {
      head_ = (head_ + 1) % kRing;
      --n_ahead_;
    }
    /// The queue's order: non-negative floats order like their bit patterns; NaN goes last.
    [[gnu::always_inline]] static std::uint32_t key(float cost) {
      if (!(cost >= 0.0f)) return cost != cost ? 0x7f800000u : 0u;
      return std::bit_cast<std::uint32_t>(cost);
    }
    /// The entry that comes out k pops from now if nothing cheaper is pushed meanwhile
    /// (k < kAhead), or null: the engine fetches the memory of upcoming collapses early.
    const Candidate* peek(std::size_t k) const {
      return k < n_ahead_ ? &ahead_[(head_ + k) % kRing] : nullptr;
    }
    static constexpr std::size_t kAhead = 8;

   private:
    [[gnu::always_inline]] bool current(const Candidate& c) const {
      return c.stamps == stamps_[c.a] + stamps_[c.b];
    }
    /// Keep the next kAhead entries (or all that are left) in ahead_.
    void top_up();
    /// Make bucket 0 hold the current entries of the smallest cost, unless none is left.
    void settle();
    [[gnu::always_inline]] int bucket(std::uint32_t k) const;
    // A bucket holds its entries in order in fixed-size chunks, all full but the last, taken
    // from a pool that all buckets share; a bucket drained into the lower ones hands each
    // chunk back as soon as it is read, and the lower buckets refill it while it is still in
    // cache. As 33 vectors, each kept the capacity of its own peak: 141 MB on the 1M torus
    // for 24 MB of initial entries, fresh pages that the kernel had to clear (peak memory of
    // simplify() there: 383 MB then, 273 MB now).
    static constexpr std::size_t kChunk = 1024;
    struct Bucket {
      std::vector<Candidate*> chunks;  // none when empty
      Candidate *end = nullptr, *limit = nullptr;  // in the last chunk
      bool empty() const { return chunks.empty(); }
      std::size_t size() const {
        if (empty()) return 0;
        return (chunks.size() - 1) * kChunk + static_cast<std::size_t>(end - chunks.back());
      }
    };
    void append(Bucket& b, const Candidate& c) {
      if (b.end == b.limit) {
        b.chunks.push_back(take_chunk());
        b.end = b.chunks.back();
        b.limit = b.end + kChunk;
      }
      *b.end++ = c;
    }
    Candidate* take_chunk() {
      if (free_.empty()) grow_pool(kSlabChunks);
      Candidate* c = free_.back();
      free_.pop_back();
      return c;
    }
    void grow_pool(std::size_t chunks);
    static constexpr std::size_t kSlabChunks = 256;  // 4 MiB
    struct SlabDelete {
      void operator()(Candidate* p) const noexcept;
    };
    std::vector<std::unique_ptr<Candidate[], SlabDelete>> slabs_;
    std::vector<Candidate*> free_;  // last in, first out: the chunk read last is reused first
    std::array<Bucket, 33> buckets_;
    std::uint32_t last_ = 0;
    std::size_t size_ = 0;  // in buckets_
    const std::uint32_t* stamps_ = nullptr;
    // The cheapest entries, taken out of the buckets ahead of time: a ring from head_, by
    // increasing cost. Pushes cheaper than last_ are inserted here, in order.
    static constexpr std::size_t kRing = 4 * kAhead, kAheadMax = kRing - 1;
    Candidate& ahead(std::size_t k) { return ahead_[(head_ + k) % kRing]; }
    std::array<Candidate, kRing> ahead_{};
    std::size_t head_ = 0, n_ahead_ = 0;
  };
  struct Placement {
    double cost;
    Point p;        // normalised units
    int source;     // 0 optimum, 1 = a, 2 = b, 3 = midpoint
  };

  // A triangle of the fan around the merged vertex: its other corners in order, its normal.
  struct FanFace {
    std::uint32_t next, prev;
    Eigen::Vector3d n;
  };
  static constexpr int kFanMax = 64;
  /// What one collapse loop owns: its queue, scratch, mark tokens, room in refs_ and
  /// counters. One on the serial path; with parts, one per part plus one for the seam
  /// (collapse_loop.cpp), each touched by one thread at a time.
  struct alignas(64) Worker {
    RadixQueue queue;
    std::vector<std::uint32_t> neighbours;  // push_vertex_edges' result
    std::vector<Candidate> pending;         // push_vertex_edges' scratch
    std::vector<Candidate> uncosted;        // its edges not in costs
    std::vector<std::uint32_t> uncosted_at;  // their places in pending
    // The edges its re-queues (push_vertex_edges with reuse) costed lately, by ends and stamp
    // sum: direct-mapped, 2^kCostCacheBits entries, allocated on first use. A vertex with a
    // rejected edge queues all its edges again after every collapse beside it, and those
    // whose ends did not change cost what they cost before. On fandisk, a CAD model whose
    // flat regions reject collapses over and over, this took 6-7% off the collapse loop's
    // instructions at 50% and 10%; meshes that seldom reject do not look it up.
    struct CachedCost {
      std::uint32_t a = kNone, b = kNone, stamps = 0;
      float cost = 0;
    };
    std::vector<CachedCost> costs;
    std::vector<std::uint32_t> retry;       // drain()'s scratch
    // In a parallel step, what belongs to the seam: entries, and vertices whose edges are
    // to be queued again.
    std::vector<Candidate> staged;
    std::vector<std::uint32_t> staged_retry;
    std::array<FanFace, kFanMax> fan;  // try_collapse's scratch: the new fan
    // Its size (0: not recorded) and where v's triangles start in it.
    int fan_size = 0, fan_v = 0;
    // Marks are compared with the current token for equality only; each worker draws its
    // tokens from a range of its own (hundreds of millions with kParts workers, at about 20
    // a collapse), so another worker's marks never look current.
    std::uint32_t token = 0;
    // Its room for merged triangle lists: refs_[ref_end .. ref_limit).
    std::size_t ref_end = 0, ref_limit = 0;
    std::size_t collapses = 0, removed = 0;  // triangles removed
    double max_error = 0;
    bool error_rejected = false;
    bool in_step = false;  // collapsing its part concurrently with the other parts
    std::uint8_t part = 0;
  };
  /// How a drain() ended.
  enum class Drain { kDone, kLimit, kEmpty, kRoom, kCancelled };
  struct DrainLimits {
    std::uint32_t key;  // collapse entries up to this queue key
    std::size_t faces;  // remove at most about this many triangles
    bool exact;         // never more than faces (else the last collapse may pass it by one)
  };

  Placement place(std::uint32_t a, std::uint32_t b) const;
  /// place(a[k], b[k]).cost for k = 0, 1, bit for bit, in two SIMD lanes
  /// (collapse_costs.cpp).
  std::array<double, 2> place_cost_pair(const std::uint32_t* a, const std::uint32_t* b) const;
  /// Write a's edges to higher-numbered vertices (unless both ends are locked) to out, each
  /// once, in order of first appearance around a; return their number (at most
  /// 2 × a's triangles). Thread-safe.
  std::uint32_t higher_edges(std::uint32_t a, Candidate* out) const;
  /// Set the cost (the queue's priority) of c[0 .. n), two edges at a time.
  void set_costs(Candidate* c, std::size_t n) const;
  [[gnu::always_inline]] float priority(std::uint32_t a, std::uint32_t b, double cost) const;
  /// Queue v's edges at their current costs. reuse: take the costs of edges whose ends are
  /// unchanged since w last costed them from w.costs (v's own collapse changed all of its
  /// edges, so after it there is nothing to reuse).
  void push_vertex_edges(Worker& w, std::uint32_t v, bool reuse = false);
  void set_costs_reusing(Worker& w) const;
  static constexpr unsigned kCostCacheBits = 12;
  /// Queue c where it belongs: w's queue on the serial path, else its part's or the seam's.
  void push(Worker& w, const Candidate& c);
  void prefetch_upcoming(const Worker& w) const;
  // Below this many vertices (2 MiB of VertexData, a core's share of L2 here) the records stay
  // in cache and fetching ahead only costs instructions: fandisk (6.5k vertices) simplified
  // 10% faster without it, the bunny (35k) the same, the 1M torus 15-30% slower.
  static constexpr std::size_t kPrefetchMinVertices = 16384;
  // Forced inline: the collapse checks call it for every triangle around both ends.
  [[gnu::always_inline]] bool has_tri_with(std::uint32_t t, std::uint32_t x) const {
    const auto& tri = triangles_[t];
    return tri[0] == x || tri[1] == x || tri[2] == x;
  }
  void drop_ref(std::uint32_t w, std::uint32_t t);
  int try_collapse(Worker& w, std::uint32_t u, std::uint32_t v, const Placement& pl);
  double tip_cost(const Worker& w, std::uint32_t u, std::uint32_t v, const Placement& pl) const;
  double tip_height2(const Worker& w, int start, const Point& p, const Point& x, double t2) const;
  double midpoint_height2(std::uint32_t u, std::uint32_t v, const Point& p, const Worker& w,
                          double t2) const;
  double old_surface_distance2(std::uint32_t u, std::uint32_t v, std::uint32_t q, const Point& m,
                               double tm) const;
  /// Returns the number of triangles removed.
  int collapse(Worker& w, std::uint32_t u, std::uint32_t v, const Placement& pl);
  void ensure_refs(Worker& w, std::size_t extra);
  /// Rewrite the live triangle lists to the front of a fresh refs_ of at least `capacity`
  /// and share the rest out among the workers.
  void compact_refs(std::size_t capacity);
  /// Collapse from w's queue (or all queues) within the limits.
  Drain drain(Worker& w, const DrainLimits& limits);
  bool face_ok(std::uint32_t t, std::uint32_t moved, const Point& p, FanFace& out) const;
  void fan_face(std::uint32_t t, std::uint32_t moved, const Point& p, FanFace& out) const;
  bool fan_folds(Worker& w, int size);
  // cos 127°: CGAL rejects only near-complete folds (179°); this also stops sharp creases.
  static constexpr double kFoldCos = -0.6;
  // place()'s tie band, relative to the size of the merged quadric's terms about the edge:
  // about 50 ulps, a few times the round-off of evaluating its ten terms.
  static constexpr double kTieTolerance = 1e-14;
  // The pseudo-inverse tolerance's floor for inputs given at full double precision: well
  // above the eigen solver's own error (about 1e-15 of the largest eigenvalue) and the
  // round-off of summing a quadric's planes.
  static constexpr double kSolverRoundOff = 1e-13;
  // A boundary collapse's priority counts at most this many times the squared lengths of
  // the boundary edges merged into its ends as face weight (see priority()).
  static constexpr double kBoundaryArea = 2.0;
  // A collapse that leaves a removed position more than √kTipRatio × its RMS quadric error
  // above the new fan is requeued at cost kTipWeight · weight · height² (see tip_cost()).
  static constexpr double kTipRatio = 6.0, kTipWeight = 0.5;
  // A new fan edge whose midpoint is more than √(kMidRatio · kTipRatio) × the RMS quadric
  // error and kMidSlope × its length off the old surface is requeued likewise, its height
  // counted at 1 / kMidRatio (see midpoint_height2()). Tuned on the 8-mesh error matrix with
  // edges sampled densely: (0.035, 0.5) and (0.05, 0.35) had no loss that the matrix did
  // not have before; 0.05 with 0.5 or 0.7, and 0.07 or 0.1 with 0.5, each lost a case.
  static constexpr double kMidRatio = 0.5, kMidSlope = 0.035;
  double pseudo_inverse_tolerance(double max_abs, double total_area) const;
  std::vector<Point> normalised_positions() const;

  // Region-parallel collapses (collapse_loop.cpp).
  static constexpr std::size_t kParts = 8;
  static constexpr std::uint8_t kSeam = 0xff;
  /// Label the vertices with kParts regions of the positions pos and mark the seam.
  void partition(const std::vector<Point>& pos);
  /// Set up the workers and hand them the first entries (blocks of edges, in order).
  void start_workers(std::vector<EdgeBlock>& blocks, std::uint32_t first_token,
                     std::size_t refs_end);
  /// Share refs_[end .. refs_capacity_) out among the workers.
  void share_refs(std::size_t end);
  SimplifyStop run_parallel(std::size_t target);
  /// After a collapse outside the parallel steps, survivor v and any neighbour of another
  /// part become seam, so that no part reaches another's vertices.
  void extend_seam(std::uint32_t v);
  /// Move every queue's entries into the seam's, which the tail then drains alone.
  void merge_queues();
  /// The fraction of run()'s work done, for options.progress.
  double progress() const;
  std::size_t run_start_ = 0, run_target_ = 0;  // triangles when run() began, its target

  // Attribute hooks (collapse_attributes.cpp), called only when attributes_ is set.
  void init_attributes(const SurfaceMesh& mesh);
  int wedge_pairs(std::uint32_t a, std::uint32_t b, AttributeQuadrics::WedgePair* out) const;
  Placement place_with_attributes(std::uint32_t a, std::uint32_t b, Quadric q) const;
  bool attributes_allow(std::uint32_t u, std::uint32_t v, const Placement& pl) const;
  void collapse_attributes(std::uint32_t u, std::uint32_t v);
  void write_attributes(SurfaceMesh& out) const;

  SimplifyOptions options_;
  bool record_;

  std::vector<Vertex> vertex_of_;
  std::vector<Point> original_positions_;
  std::vector<std::array<std::uint32_t, 3>> original_triangles_;

  Point center_ = Point::Zero();
  double scale_ = 1.0;  // model = center + scale · normalised
  // place()'s pseudo-inverse tolerance, relative to the largest eigenvalue: the eigenvalue
  // ratio that the input's coordinate rounding alone can give (see pseudo_inverse_tolerance()).
  double pinv_tolerance_ = 1e-7;

  std::vector<VertexData> vd_;
  std::vector<Point> model_;     // model units; stale for moved vertices unless record_
  std::vector<std::uint32_t> stamp_;  // apart from vd_: the queue reads them densely
  // Per vertex, the summed squared lengths of the boundary edges whose constraint planes its
  // quadric holds (priority()); empty for a closed mesh. Apart from vd_, which is full: only
  // boundary vertices read it.
  std::vector<double> boundary_length2_;

  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<std::uint8_t> tri_alive_;
  std::size_t alive_triangles_ = 0;

  // Incident triangle lists (VertexData::ref_begin) in refs_[0 .. refs_capacity_); a collapse
  // writes v's merged list into its worker's room. Not cleared: only written parts are read.
  std::unique_ptr<std::uint32_t[]> refs_;
  std::size_t refs_capacity_ = 0;

  std::vector<Worker> workers_;
  std::size_t parts_ = 0;  // 0: one worker, serial
  bool merged_ = false;     // parts_ > 0, and the tail's one queue (the seam's) holds all
  // Per vertex: its part (fixed), and its part or kSeam (seam only grows).
  std::vector<std::uint8_t> label_, region_;

  // Per dense vertex, the vertex it was collapsed into (kNone while alive); kept only for the
  // refit, which projects the input through it instead of searching the whole output.
  std::vector<std::uint32_t> merged_into_;
  // Per dense vertex, a third of its triangles' area (model units²); kept only for the refit,
  // whose vertex samples it weighs: the setup's sweep has every triangle's area at hand.
  std::vector<double> vertex_area_;

  std::vector<CollapseRecord> records_;
  std::vector<std::uint32_t> changed_;

  std::unique_ptr<AttributeQuadrics> attributes_;  // null unless options.attributes.any()
};

/// simplify() with the size from which collapses run in parallel (tests set it low).
SimplifyResult simplify(const SurfaceMesh& mesh, const SimplifyOptions& options,
                        std::size_t parallel_min_triangles);

}  // namespace geom::detail
