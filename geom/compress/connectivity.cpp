#include <geom/compress/connectivity.h>

#include <geom/core/huge_pages.h>

#include <algorithm>
#include <string>

namespace geom::codec::detail {

using geom::detail::reserve_huge;

namespace {

// R2 / L2: two steps along the open boundary — the vertex beyond a neighbour whose fan
// lacks a single triangle; frequent on irregular meshes, so they get their own symbols.
enum Symbol : unsigned {
  kNew = 0, kRight = 1, kLeft = 2, kBoundary = 3, kOther = 4, kRight2 = 5, kLeft2 = 6
};
constexpr unsigned kSymbols = 7;
constexpr unsigned kFanClasses = 7;
constexpr unsigned kGateContexts = kFanClasses * kFanClasses * 4;

/// The models both sides keep. The gate symbol's context is how many decoded triangles
/// already surround each gate vertex (a nearly full fan is likely to close: R at the
/// target, L at the source — the valence idea of Touma–Gotsman) and which of the two
/// boundary neighbours exist, since a missing neighbour rules a symbol out.
struct Models {
  std::vector<SmallModel<kSymbols>> gate = std::vector<SmallModel<kSymbols>>(kGateContexts);
  AdaptiveModel seed_new{2};
  AdaptiveModel diagonal[2] = {AdaptiveModel(2), AdaptiveModel(2)};
  GammaModel other;
  AdaptiveModel other_on_boundary{2};
  GammaModel walk;
  GammaModel seed_other;
};

/// The open boundary of the decoded region. A gate is a directed edge of a decoded triangle
/// whose other side is not decoded yet; gates are threaded on per-vertex lists (outgoing
/// and incoming, newest first) so the boundary neighbours and the zip partner are found in
/// O(1)/O(valence). Closing a gate only marks it (`to` = kNone, in the record the lists read
/// anyway) and advances list heads past closed gates (lazy deletion): every head is open,
/// and the lists stay singly linked and small.
struct Gate {
  std::uint32_t from, to, corner;
  std::uint32_t next_out, next_in;
};

// A gate is opened by attaching a corner's edge, at most once per corner (any stream; a
// closed mesh opens about 3T/2). One more record is the sentinel that stands for "no gate".
// Untouched pages of the block cost nothing.
std::size_t max_gates_for(std::size_t n_triangles) { return 3 * n_triangles; }
std::size_t gate_bytes(std::size_t n_triangles) {
  return (max_gates_for(n_triangles) + 1) * sizeof(Gate);
}

/// The gates waiting to be popped, in the scratch block after the gate records. Each gate is
/// pushed at most once, when it opens, so max_gates_for(T) entries never overflow: a push
/// needs no capacity check.
class GateStack {
 public:
  explicit GateStack(std::uint32_t* base) : base_(base), top_(base) {}
  bool empty() const { return top_ == base_; }
  void push(std::uint32_t g) { *top_++ = g; }
  std::uint32_t pop() { return *--top_; }
  /// The entry on top; pre: not empty.
  std::uint32_t top() const { return top_[-1]; }

 private:
  std::uint32_t* base_;
  std::uint32_t* top_;
};

class Region {
 public:
  /// vertex_hint: the vertices expected (a guess: if more arrive, the records double).
  Region(std::size_t n_triangles, std::size_t vertex_hint, Scratch& scratch)
      : sentinel_(static_cast<std::uint32_t>(max_gates_for(n_triangles))) {
    scratch.reserve(connectivity_scratch_bytes(n_triangles));
    gates_ = scratch.array<Gate>(0, sentinel_ + std::size_t{1});
    stack_ = scratch.array<std::uint32_t>(gate_bytes(n_triangles), sentinel_);
    gates_[sentinel_] = {kNone, kNone, kNone, kNone, kNone};
    // Closed meshes have about T/2 vertices; a mesh with boundaries more, which would cost
    // a doubling (twice the records cleared, and copied) unless the caller knows better.
    const std::size_t records = std::min(std::max(vertex_hint, n_triangles / 2), 3 * n_triangles) + 3;
    vertices_.resize(records);
    corners_.resize(records, 0);
  }
  std::uint32_t add_vertex() { return add_vertex_if(true); }
  /// The id the next vertex gets; it is added only when `take` (no branch on it: the
  /// record at that id is already blank).
  std::uint32_t add_vertex_if(bool take) {
    const std::uint32_t id = n_vertices_;
    n_vertices_ += take;
    if (n_vertices_ == vertices_.size()) [[unlikely]] {
      vertices_.resize(2 * vertices_.size());
      corners_.resize(vertices_.size(), 0);
    }
    return id;
  }
  std::uint32_t n_vertices() const { return n_vertices_; }
  /// Decoded triangles around v, saturated at kFanClasses − 1.
  unsigned fan(std::uint32_t v) const { return fan_class(corners_[v]); }
  static unsigned fan_class(std::uint32_t corners) {
    return std::min<std::uint32_t>(corners, kFanClasses - 1);
  }
  /// Returns v's new corner count.
  std::uint32_t add_corner(std::uint32_t v) { return ++corners_[v]; }
  /// Hands over each vertex's corners (the degree pass's wedge lists are sized by them;
  /// counting here saves it a scattered pass over every corner): moved, not copied. The
  /// region keeps no counts after this.
  void take_corner_counts(geom::detail::UninitialisedVector<std::uint32_t>& out) {
    out = std::move(corners_);
    out.resize(n_vertices_);
  }
  const Gate& gate(std::uint32_t g) const { return gates_[g]; }
  std::uint32_t* stack_block() const { return stack_; }
  bool is_open(std::uint32_t g) const { return gates_[g].to != kNone; }
  void prefetch(std::uint32_t g) const { __builtin_prefetch(gates_ + g); }

  /// The open gate from a to b, or kNone.
  std::uint32_t find(std::uint32_t a, std::uint32_t b) const {
    for (std::uint32_t g = vertices_[a].out; g != kNone; g = gates_[g].next_out)
      if (gates_[g].to == b) return g;  // closed gates have none
    return kNone;
  }
  /// The newest open gate out of / into v, or kNone. Lists run newest first, so when its far
  /// end is w, it is the gate find() returns for v→w (or w→v).
  std::uint32_t first_out(std::uint32_t v) const { return vertices_[v].out; }
  std::uint32_t first_in(std::uint32_t v) const { return vertices_[v].in; }
  /// The boundary vertex after v (head of v's outgoing gates), or kNone.
  std::uint32_t after(std::uint32_t v) const { return vertices_[v].after; }
  /// The boundary vertex before v (tail of v's first incoming gate), or kNone.
  std::uint32_t before(std::uint32_t v) const { return vertices_[v].before; }
  /// after / before, kNone for v = kNone too (the blank record past the last vertex).
  std::uint32_t after_or_none(std::uint32_t v) const { return after(std::min(v, n_vertices_)); }
  std::uint32_t before_or_none(std::uint32_t v) const {
    return before(std::min(v, n_vertices_));
  }
  std::uint32_t open(std::uint32_t from, std::uint32_t to, std::uint32_t corner) {
    const std::uint32_t id = n_gates_++;
    Vertex& a = vertices_[from];
    Vertex& b = vertices_[to];
    gates_[id] = {from, to, corner, a.out, b.in};
    a.out = id;
    a.after = to;
    b.in = id;
    b.before = from;
    return id;
  }
  /// Pre: gate id is open (every caller holds a popped gate checked open, a list head or a
  /// find() result).
  // Forced inline: GCC kept it out of line, and with the calls the connectivity decoder
  // took about 2% longer (alternated timings).
  [[gnu::always_inline]] void close(std::uint32_t id) {
    Gate& g = gates_[id];
    const std::uint32_t to = g.to;
    g.to = kNone;
    Vertex& a = vertices_[g.from];
    while (a.out != kNone && !is_open(a.out)) a.out = gates_[a.out].next_out;
    a.after = gates_[real(a.out)].to;
    Vertex& b = vertices_[to];
    while (b.in != kNone && !is_open(b.in)) b.in = gates_[b.in].next_in;
    b.before = gates_[real(b.in)].from;
  }

 private:
  // The lookups of a gate's two ends read one record each, not three arrays, and the
  // boundary neighbours are kept beside the list heads (updated as the heads move), so
  // finding them is not a second, dependent load of an old gate.
  // 16 bytes: no record straddles two cache lines.
  struct Vertex {
    std::uint32_t out = kNone, in = kNone;  // list heads: newest open gate
    std::uint32_t after = kNone, before = kNone;  // their far ends
  };
  // kNone (no gate) becomes the sentinel, whose ends are kNone: no branch.
  std::uint32_t real(std::uint32_t g) const { return std::min(g, sentinel_); }

  Gate* gates_;  // in the scratch block, which holds exactly max_gates_for(T) + 1
  std::uint32_t* stack_;  // after them, max_gates_for(T) entries
  std::uint32_t sentinel_;
  std::uint32_t n_gates_ = 0;
  std::uint32_t n_vertices_ = 0;
  std::vector<Vertex> vertices_;  // blank past n_vertices_, at least one
  // Per record of vertices_, the decoded triangles around its vertex (< 3T, no overflow):
  // apart from the records, so that it becomes CornerTable::corners_of without a copy.
  geom::detail::UninitialisedVector<std::uint32_t> corners_;
};

/// The growth's corner arrays, written through raw pointers. They are sized kStep triangles
/// at a time, just before the step is written, so that sizing clears (and fills the
/// opposites with kNone) lines the writes then find in cache. push_back's capacity check and
/// size update per element were 7% of the decoder's growth instructions, and sizing the
/// whole arrays up front wrote every page twice, the second time from memory.
class CornerWriter {
 public:
  CornerWriter(CornerTable& out, std::size_t n_triangles, bool polygons)
      : out_(out), max_(3 * n_triangles), polygons_(polygons) {
    out.vertex.clear();
    reserve_huge(out.vertex, max_);
    out.opposite.clear();
    reserve_huge(out.opposite, max_);
    out.diagonal.clear();
    if (polygons) out.diagonal.reserve(max_);
  }
  /// Corners written so far (3 per triangle).
  std::size_t corners() const { return n_; }
  /// Append triangle (a, b, c) with open edges; returns its index. Pre: corners() < 3T.
  std::uint32_t add(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (n_ == end_) [[unlikely]] extend();
    vertex_[n_] = a;
    vertex_[n_ + 1] = b;
    vertex_[n_ + 2] = c;
    const auto t = static_cast<std::uint32_t>(n_ / 3);
    n_ += 3;
    return t;
  }
  std::uint32_t vertex(std::uint32_t c) const { return vertex_[c]; }
  void pair(std::uint32_t a, std::uint32_t b) {
    opposite_[a] = b;
    opposite_[b] = a;
  }
  /// Pre: the writer was made for polygons.
  void set_diagonal(std::uint32_t a, std::uint32_t b, std::uint8_t diagonal) {
    diagonal_[a] = diagonal_[b] = diagonal;
  }

 private:
  static constexpr std::size_t kStep = 1024;  // 12 KiB per array: the step stays in L1
  // Kept out of add(): inlined, its resizes made add() too large to inline in turn, and the
  // call per triangle cost more than the add itself.
  [[gnu::noinline]] void extend() {
    end_ = std::min(end_ + 3 * kStep, max_);
    out_.vertex.resize(end_);  // within the reserved capacity: no copy
    out_.opposite.resize(end_, kNone);
    if (polygons_) out_.diagonal.resize(end_, 0);
    vertex_ = out_.vertex.data();
    opposite_ = out_.opposite.data();
    diagonal_ = out_.diagonal.data();
  }
  CornerTable& out_;
  std::size_t max_;
  bool polygons_;
  std::size_t n_ = 0, end_ = 0;
  std::uint32_t* vertex_ = nullptr;
  std::uint32_t* opposite_ = nullptr;
  std::uint8_t* diagonal_ = nullptr;
};

/// An "other" vertex is usually on the open boundary a few steps beyond the neighbours
/// (Edgebreaker's split offset): step i alternates forward from v and backward from u.
constexpr std::uint32_t kWalkLimit = 4096;

/// The vertex at walk position j (j = 2·i + direction), or kNone when the walk ends first.
std::uint32_t walk_to(const Region& region, std::uint32_t u, std::uint32_t v, std::uint32_t j) {
  std::uint32_t x = (j & 1) ? u : v;
  for (std::uint32_t i = 0; i <= j / 2; ++i) {
    x = (j & 1) ? region.before(x) : region.after(x);
    if (x == kNone) return kNone;
  }
  return x;
}

/// The smallest walk position reaching w, or kNone.
std::uint32_t walk_find(const Region& region, std::uint32_t u, std::uint32_t v, std::uint32_t w) {
  std::uint32_t f = v, b = u;
  for (std::uint32_t i = 0; i < kWalkLimit && (f != kNone || b != kNone); ++i) {
    if (f != kNone) {
      f = region.after(f);
      if (f == w) return 2 * i;
      if (f == v) f = kNone;
    }
    if (b != kNone) {
      b = region.before(b);
      if (b == w) return 2 * i + 1;
      if (b == u) b = kNone;
    }
  }
  return kNone;
}

/// The growth procedure shared by encoder and decoder; the Driver supplies the decisions
/// (the encoder reads them off the input and codes them, the decoder reads them from the
/// stream), so both sides build the same table by construction.
///
/// The traversal and the polygon flag are template parameters: as run-time flags they were
/// tested on every gate (the decoder ran 1% more instructions).
template <Traversal kTraversal, bool kPolygons, class Driver>
void grow_as(Driver& d, std::size_t n_triangles, GrowHints hints, CornerTable& out,
             Scratch& scratch) {
  CornerWriter corners(out, n_triangles, kPolygons);
  Region region(n_triangles, hints.vertices, scratch);
  GateStack stack(region.stack_block());

  auto pair = [&](std::uint32_t a, std::uint32_t b) {
    corners.pair(a, b);
    if constexpr (kPolygons) corners.set_diagonal(a, b, d.diagonal(a, b));
  };
  auto add_triangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    region.add_corner(a);
    region.add_corner(b);
    region.add_corner(c);
    return corners.add(a, b, c);
  };
  // Zip edge from→to (opposite corner k) with its open reverse gate `partner`, or, when
  // there is none (kNone), open a new gate and return it.
  auto attach = [&](std::uint32_t from, std::uint32_t to, std::uint32_t k,
                    std::uint32_t partner) {
    if (partner != kNone) {
      const std::uint32_t c = region.gate(partner).corner;
      d.check_zip(k, c);
      pair(k, c);
      region.close(partner);
      return kNone;
    }
    return region.open(from, to, k);
  };

  while (corners.corners() < 3 * n_triangles) {
    d.begin_seed();
    std::uint32_t s[3];
    for (int j = 0; j < 3; ++j) s[j] = d.seed_vertex(j, region);
    if (s[0] == s[1] || s[1] == s[2] || s[0] == s[2]) d.fail("seed triangle repeats a vertex");
    const std::uint32_t t = add_triangle(s[0], s[1], s[2]);
    d.on_triangle(t);
    for (int j = 0; j < 3; ++j) {
      const std::uint32_t k = 3 * t + static_cast<std::uint32_t>(j);
      const std::uint32_t from = corners.vertex(next_corner(k));
      const std::uint32_t to = corners.vertex(prev_corner(k));
      const std::uint32_t g = attach(from, to, k, region.find(to, from));
      if (g != kNone) stack.push(g);
    }
    // The gate a step pushes last is the next one popped. It is held here instead, with its
    // ends, so that the next step starts from registers: no stack round trip, no record read
    // and no open check on the path from one symbol to the next (nothing closes it between).
    struct Held {
      std::uint32_t gate = kNone, from = kNone, to = kNone, corner = kNone;
      std::uint32_t from_fan = 0, to_fan = 0;  // fan classes of its ends
    } held;
    for (;;) {
      std::uint32_t gid, u, v, gate_corner;
      unsigned fan_u, fan_v;
      if (held.gate != kNone) {
        gid = held.gate, u = held.from, v = held.to, gate_corner = held.corner;
        fan_u = held.from_fan, fan_v = held.to_fan;
        held.gate = kNone;
      } else {
        if (stack.empty()) break;
        gid = stack.pop();
        // The gate under this one is usually popped next: fetch its record while this one grows.
        if (!stack.empty()) region.prefetch(stack.top());
        if (!region.is_open(gid)) continue;
        const Gate& g = region.gate(gid);
        u = g.from, v = g.to, gate_corner = g.corner;
        fan_u = region.fan(u), fan_v = region.fan(v);
      }
      // The drivers read the record (open until the close below); the loop keeps its fields.
      const Gate& gate = region.gate(gid);
      const std::uint32_t right = region.after(v), left = region.before(u);
      const unsigned ctx = (fan_v * kFanClasses + fan_u) * 4 +
                           (right != kNone ? 2 : 0) + (left != kNone ? 1 : 0);
      std::uint32_t w = kNone;
      const unsigned sym = d.gate_symbol(ctx, gate, right, left, region, w);
      if (sym == kBoundary) {
        region.close(gid);
        continue;
      }
      if (w == u || w == v) d.fail("grown triangle repeats a gate vertex");
      // Bounds the gates too (at most one per corner), which live in a block of fixed size.
      if (corners.corners() >= 3 * n_triangles) d.fail("more triangles than the stream's count");
      region.close(gid);
      // The new corner counts (as fan classes) also go with the held gate: read back from the
      // records by the next step, they were a store-to-load round trip on the path to its
      // symbol (the connectivity decode alone 2-3% slower).
      const unsigned fv = Region::fan_class(region.add_corner(v));
      const unsigned fu = Region::fan_class(region.add_corner(u));
      const unsigned fw = Region::fan_class(region.add_corner(w));
      const std::uint32_t nt = corners.add(v, u, w);
      d.on_triangle(nt);
      pair(3 * nt + 2, gate_corner);
      // New edges: u→w (opposite corner v) and w→v (opposite corner u), each zipped with its
      // reverse gate if open. A new vertex has no gates. R (w after v) zips w→v with v→w, the
      // head of v's outgoing list; L (w before u) zips u→w with w→u, the head of u's incoming
      // list: the gates find() would return, without the walk. The other edge is searched
      // when its turn comes, after the first edge's zip.
      auto partner_wv = [&] {
        return sym == kNew ? kNone : sym == kRight ? region.first_out(v) : region.find(v, w);
      };
      auto partner_uw = [&] {
        return sym == kNew ? kNone : sym == kLeft ? region.first_in(u) : region.find(w, u);
      };
      // Push the first-explored gate last, that is, hold it (see Held).
      if constexpr (kTraversal == Traversal::kRightFirst) {
        const std::uint32_t gb = attach(w, v, 3 * nt + 1, partner_wv());
        const std::uint32_t ga = attach(u, w, 3 * nt + 0, partner_uw());
        if (ga != kNone) {
          if (gb != kNone) stack.push(gb);
          held = {ga, u, w, 3 * nt + 0, fu, fw};
        } else if (gb != kNone) {
          held = {gb, w, v, 3 * nt + 1, fw, fv};
        }
      } else {
        const std::uint32_t ga = attach(u, w, 3 * nt + 0, partner_uw());
        const std::uint32_t gb = attach(w, v, 3 * nt + 1, partner_wv());
        if (gb != kNone) {
          if (ga != kNone) stack.push(ga);
          held = {gb, w, v, 3 * nt + 1, fw, fv};
        } else if (ga != kNone) {
          held = {ga, u, w, 3 * nt + 0, fu, fw};
        }
      }
    }
  }
  out.n_vertices = region.n_vertices();
  out.corners_of.clear();
  if (hints.count_corners) region.take_corner_counts(out.corners_of);
}

template <class Driver>
void grow(Driver& d, std::size_t n_triangles, GrowHints hints, bool polygons,
          Traversal traversal, CornerTable& out, Scratch& scratch) {
  using enum Traversal;
  const std::size_t t = n_triangles;
  if (traversal == kRightFirst)
    polygons ? grow_as<kRightFirst, true>(d, t, hints, out, scratch)
             : grow_as<kRightFirst, false>(d, t, hints, out, scratch);
  else
    polygons ? grow_as<kLeftFirst, true>(d, t, hints, out, scratch)
             : grow_as<kLeftFirst, false>(d, t, hints, out, scratch);
}

class Encoder {
 public:
  Encoder(const CornerTable& in, RansEncoder& rans, BitWriter& raw, TraversalOrder& order)
      : in_(in), rans_(rans), raw_(raw), order_(order),
        dec_id_(in.n_vertices, kNone) {
    if (in.n_vertices >= kVisited)
      throw InvalidArgument("compress: more than 2^31 vertices");
    // The traversal visits a shuffled input in random order: one record per corner (vertex,
    // opposite, visited bit) costs one cache miss where three arrays cost three.
    reserve_huge(corner_, in.vertex.size());
    corner_.resize(in.vertex.size());
    for (std::size_t c = 0; c < in.vertex.size(); ++c) corner_[c] = {in.vertex[c], in.opposite[c]};
    order_.vertex_origin.clear();
    order_.corner_origin.clear();
    order_.corner_origin.reserve(in.vertex.size());
  }

  void begin_seed() {
    while (corner_[3 * seed_cursor_].vertex & kVisited) ++seed_cursor_;
    pending_ = 3 * seed_cursor_;
    seeding_ = true;
  }
  std::uint32_t seed_vertex(int j, Region& region) {
    const std::uint32_t orig = corner_[pending_ + static_cast<std::uint32_t>(j)].vertex & ~kVisited;
    std::uint32_t& id = dec_id_[orig];
    if (id == kNone) {
      rans_.encode(m_.seed_new, 1);
      id = region.add_vertex();
      order_.vertex_origin.push_back(orig);
    } else {
      rans_.encode(m_.seed_new, 0);
      m_.seed_other.encode(rans_, raw_, region.n_vertices() - 1 - id);
    }
    return id;
  }
  void on_triangle(std::uint32_t) {
    // pending_ is the input corner that becomes decoded corner 2 (gates) or corner 0 (seeds).
    std::uint32_t c0, c1, c2;
    if (seeding_) {
      c0 = pending_, c1 = pending_ + 1, c2 = pending_ + 2;
    } else {
      c0 = next_corner(pending_), c1 = prev_corner(pending_), c2 = pending_;
    }
    for (std::uint32_t c = pending_ - pending_ % 3, j = 0; j < 3; ++j) {
      corner_[c + j].vertex |= kVisited;
      // The triangles across this one's edges are the next gates' lookups (gate_symbol):
      // fetch them now, while the traversal does other work, not when it waits on them.
      const std::uint32_t o = corner_[c + j].opposite;
      if (o != kNone) __builtin_prefetch(corner_.data() + o);
    }
    order_.corner_origin.push_back(c0);
    order_.corner_origin.push_back(c1);
    order_.corner_origin.push_back(c2);
    seeding_ = true;
  }
  unsigned gate_symbol(unsigned ctx, const Gate& gate, std::uint32_t right, std::uint32_t left,
                       Region& region, std::uint32_t& w) {
    const std::uint32_t oc = order_.corner_origin[gate.corner];
    const std::uint32_t oo = corner_[oc].opposite;
    unsigned sym;
    if (oo == kNone) {
      sym = kBoundary;
    } else {
      const std::uint32_t orig = corner_[oo].vertex;
      if (orig & kVisited) throw InvalidArgument("compress: inconsistent opposite table");
      std::uint32_t& id = dec_id_[orig];
      if (id == kNone) {
        sym = kNew;
        id = region.add_vertex();
        order_.vertex_origin.push_back(orig);
      } else if (id == right) {
        sym = kRight;
      } else if (id == left) {
        sym = kLeft;
      } else if (right != kNone && id == region.after(right)) {
        sym = kRight2;
      } else if (left != kNone && id == region.before(left)) {
        sym = kLeft2;
      } else {
        sym = kOther;
      }
      w = id;
      pending_ = oo;
      seeding_ = false;
    }
    rans_.encode(m_.gate[ctx], sym);
    if (sym == kOther) {
      const std::uint32_t j = walk_find(region, gate.from, gate.to, w);
      rans_.encode(m_.other_on_boundary, j != kNone);
      if (j != kNone) m_.walk.encode(rans_, raw_, j);
      else m_.other.encode(rans_, raw_, region.n_vertices() - 1 - w);
    }
    return sym;
  }
  std::uint8_t diagonal(std::uint32_t a, std::uint32_t) {
    const std::uint8_t diag = in_.diagonal[order_.corner_origin[a]];
    rans_.encode(m_.diagonal[last_diag_], diag);
    last_diag_ = diag;
    return diag;
  }
  void check_zip(std::uint32_t k, std::uint32_t partner) {
    if (corner_[order_.corner_origin[k]].opposite != order_.corner_origin[partner])
      throw InvalidArgument("compress: a directed edge occurs twice (non-manifold input)");
  }
  [[noreturn]] void fail(const char* what) {
    throw InvalidArgument(std::string("compress: ") + what);
  }

 private:
  const CornerTable& in_;
  RansEncoder& rans_;
  BitWriter& raw_;
  TraversalOrder& order_;
  Models m_;
  std::vector<std::uint32_t> dec_id_;
  struct InputCorner {
    std::uint32_t vertex;  // | kVisited once its triangle is decoded
    std::uint32_t opposite;
  };
  static constexpr std::uint32_t kVisited = 0x80000000u;  // vertex ids stay below 2^30
  std::vector<InputCorner> corner_;
  std::uint32_t seed_cursor_ = 0;
  std::uint32_t pending_ = 0;
  bool seeding_ = true;
  unsigned last_diag_ = 0;
};

class Decoder {
 public:
  Decoder(RansDecoder& rans, BitReader& raw, std::size_t n_triangles)
      : rans_(rans), raw_(raw), max_vertices_(3 * n_triangles) {}

  void begin_seed() {}
  std::uint32_t seed_vertex(int, Region& region) {
    if (rans_.decode(m_.seed_new)) return new_vertex(region);
    const std::uint32_t back = m_.seed_other.decode(rans_, raw_);
    if (back >= region.n_vertices()) fail("seed vertex reference out of range");
    return region.n_vertices() - 1 - back;
  }
  void on_triangle(std::uint32_t) {}
  unsigned gate_symbol(unsigned ctx, const Gate& gate, std::uint32_t right, std::uint32_t left,
                       Region& region, std::uint32_t& w) {
    const unsigned sym = rans_.decode(m_.gate[ctx]);
    // The symbol is hard to predict, so the third vertex is picked from a table of every
    // candidate rather than by a branch on it; kNone marks the rare symbols (and errors).
    const std::uint32_t next = region.n_vertices();
    const std::uint32_t candidates[8] = {next,  right, left, kNone, kNone,
                                         region.after_or_none(right),
                                         region.before_or_none(left), kNone};
    w = candidates[sym & 7];
    if (w == kNone) [[unlikely]] return rare_symbol(sym, gate, region, w);
    const bool is_new = sym == kNew;
    if (next + is_new > max_vertices_) fail("more vertices than corners");
    region.add_vertex_if(is_new);
    return sym;
  }
  std::uint8_t diagonal(std::uint32_t, std::uint32_t) {
    const auto diag = static_cast<std::uint8_t>(rans_.decode(m_.diagonal[last_diag_]));
    last_diag_ = diag;
    return diag;
  }
  void check_zip(std::uint32_t, std::uint32_t) {}
  [[noreturn]] void fail(const char* what) {
    throw DecodeError(rans_.offset(), std::string("connectivity: ") + what + " near byte " +
                                          std::to_string(rans_.offset()));
  }

 private:
  unsigned rare_symbol(unsigned sym, const Gate& gate, const Region& region, std::uint32_t& w) {
    switch (sym) {
      case kRight: fail("R symbol without a next boundary vertex");
      case kLeft: fail("L symbol without a previous boundary vertex");
      case kRight2: fail("R2 symbol without a boundary vertex two steps ahead");
      case kLeft2: fail("L2 symbol without a boundary vertex two steps back");
      case kOther: break;
      default: return sym;  // boundary
    }
    if (rans_.decode(m_.other_on_boundary)) {
      const std::uint32_t j = m_.walk.decode(rans_, raw_);
      if (j >= 2 * kWalkLimit) fail("boundary walk too long");
      w = walk_to(region, gate.from, gate.to, j);
      if (w == kNone) fail("boundary walk leaves the boundary");
      return sym;
    }
    const std::uint32_t back = m_.other.decode(rans_, raw_);
    if (back >= region.n_vertices()) fail("vertex reference out of range");
    w = region.n_vertices() - 1 - back;
    return sym;
  }
  std::uint32_t new_vertex(Region& region) {
    if (region.n_vertices() >= max_vertices_) fail("more vertices than corners");
    return region.add_vertex();
  }
  RansDecoder& rans_;
  BitReader& raw_;
  Models m_;
  std::size_t max_vertices_;
  unsigned last_diag_ = 0;
};

}  // namespace

std::size_t connectivity_scratch_bytes(std::size_t n_triangles) {
  return gate_bytes(n_triangles) + max_gates_for(n_triangles) * sizeof(std::uint32_t);
}

void encode_connectivity(const CornerTable& input, bool polygons, Traversal traversal,
                         RansEncoder& rans, BitWriter& raw, CornerTable& decoded,
                         TraversalOrder& order) {
  Encoder enc(input, rans, raw, order);
  Scratch scratch;
  // The encoder runs the degree pass on the decoded table (when it tries predictors 3–5).
  grow(enc, input.n_triangles(), {input.n_vertices, true}, polygons, traversal, decoded, scratch);
}

void decode_connectivity(std::size_t n_triangles, bool polygons, Traversal traversal,
                         RansDecoder& rans, BitReader& raw, CornerTable& decoded,
                         Scratch* scratch, GrowHints hints) {
  Decoder dec(rans, raw, n_triangles);
  Scratch own;
  grow(dec, n_triangles, hints, polygons, traversal, decoded, scratch ? *scratch : own);
}

}  // namespace geom::codec::detail
