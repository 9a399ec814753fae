// Polygon soup → SurfaceMesh. The connectivity is assembled in bulk from flat per-corner
// arrays (corner = one face's use of a vertex, and the halfedge leaving it):
//   1. weld (optional), clean faces (out of range, repeated corners, zero area)
//   2. group halfedges by undirected edge (edge_groups.h) and pair twins; spot duplicates,
//      same-direction neighbours and edges with 3+ faces on the way
//   3. only when neighbours disagree: orient faces by BFS over the pairing, then pair again
//   4. walk the fan of corners around each vertex; every fan after the first becomes a new
//      vertex (bow-ties), then make sure no two edges join the same pair of vertices
//   5. emit halfedges/faces/boundary loops with the low-level SurfaceMesh API, copy attributes
// Clean input runs 1, 2, 4 and 5 once each: linear apart from the short per-vertex sorts.
#include <geom/core/build.h>

#include <geom/core/build_attributes.h>
#include <geom/core/edge_groups.h>
#include <geom/core/geometry.h>
#include <geom/core/weld.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace geom {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

/// Counts one kind of change and keeps the first few examples for the message.
struct Tally {
  std::size_t count = 0;
  std::string examples;
  void add(const std::string& example) {
    if (count++ < 3) examples += (examples.empty() ? "" : "; ") + example;
  }
  std::string message(const std::string& what) const {
    std::string m = what + ": " + std::to_string(count);
    if (!examples.empty()) m += " (e.g. " + examples + (count > 3 ? "; ..." : "") + ")";
    return m;
  }
};

bool finite(const Point& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

class Builder {
 public:
  Builder(const PolygonSoup& soup, const BuildOptions& options, BuildReport& report)
      : soup_(&soup), opt_(options), rep_(report), strict_(options.policy == RepairPolicy::kStrict) {}

  SurfaceMesh run() {
    check_soup(*soup_);
    nv_ = static_cast<std::uint32_t>(soup_->positions.size());
    weld();
    keep_seams();
    clean_faces();
    pair(opt_.orient);
    if (duplicates_found_) {
      remove_duplicates();
      pair(opt_.orient);
    }
    if (opt_.orient && same_direction_pairs_ > 0) {
      orient();
      pair(false);
    } else if (!opt_.orient) {
      count_cut_edges();
    }
    split_fans();
    SurfaceMesh mesh = emit();
    copy_attributes(mesh);
    write_messages();
    return mesh;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw TopologyError("build (strict policy): " + why);
  }
  static std::string s(std::size_t x) { return std::to_string(x); }

  std::uint32_t rep(std::uint32_t v) const { return weld_.empty() ? v : weld_[v]; }

  // ---- 1. welding ---------------------------------------------------------------------
  void weld() {
    if (opt_.weld_tolerance < 0 || nv_ == 0) return;
    Eigen::AlignedBox3d box;
    for (const Point& p : soup_->positions)
      if (finite(p)) box.extend(p);
    double eps = box.isEmpty() ? 0.0 : opt_.weld_tolerance * box.diagonal().norm();
    if (!std::isfinite(eps)) eps = 0.0;
    weld_ = weld_map(soup_->positions, eps);
    for (std::uint32_t v = 0; v < nv_; ++v) {
      if (weld_[v] == v) continue;
      if (welded_.count < 3) welded_.add("vertex " + s(v) + " into " + s(weld_[v]));
      else ++welded_.count;
    }
  }

  // Welding joins vertices whose texture coordinates or normals differ (a seam stored as
  // split vertices, as PLY and glTF store it): those values move to the face corners, so
  // that the seam stays. Colours have no corner form: a joined vertex takes its
  // representative's, which is said.
  void keep_seams() {
    if (weld_.empty()) return;
    const SeamCount n = count_seams(*soup_, weld_);
    recoloured_.count += n.colors;
    if (n.texcoords == 0 && n.normals == 0) return;
    seamed_ = *soup_;
    seams_to_corners(seamed_, weld_);
    seams_kept_.count += std::max(n.texcoords, n.normals);
    soup_ = &seamed_;
  }

  // ---- 1b. face cleaning --------------------------------------------------------------
  void clean_faces() {
    const std::size_t nf = soup_->n_faces();
    const std::size_t nc = soup_->face_indices.size();
    // Corner origins are needed only to carry per-corner attributes.
    const bool keep_corig = !soup_->corner_texcoords.empty() || !soup_->corner_normals.empty();
    offs_.reserve(nf + 1);
    offs_.push_back(0);
    cv_.resize(nc);
    if (keep_corig) corig_.resize(nc);
    forig_.reserve(nf);
    fhash_.reserve(nf);
    const auto& P = soup_->positions;
    const std::uint32_t* idx = soup_->face_indices.data();
    std::vector<Point> pts;
    std::uint32_t w = 0;
    for (std::size_t f = 0; f < nf; ++f) {
      const std::uint32_t b = soup_->face_offsets[f], e = soup_->face_offsets[f + 1];
      bool out_of_range = false;
      for (std::uint32_t c = b; c < e; ++c)
        if (idx[c] >= nv_) {
          std::string ex = "face " + s(f) + " has index " + s(idx[c]) + " with " + s(nv_) + " vertices";
          if (strict_) fail(ex);
          out_of_range_.add(ex);
          out_of_range = true;
          break;
        }
      if (out_of_range) continue;
      const std::uint32_t mark = w;
      bool collapsed = false;
      for (std::uint32_t c = b; c < e; ++c) {
        std::uint32_t v = rep(idx[c]);
        if (w > mark && cv_[w - 1] == v) {
          collapsed = true;
          continue;
        }
        cv_[w] = v;
        if (keep_corig) corig_[w] = c;
        ++w;
      }
      while (w > mark + 1 && cv_[w - 1] == cv_[mark]) {
        --w;
        collapsed = true;
      }
      std::span<const std::uint32_t> face(cv_.data() + mark, w - mark);
      std::string why;
      if (face.size() < 3) {
        why = "fewer than 3 distinct corners";
      } else if (std::uint32_t dup = repeated_vertex(face); dup != kNone) {
        why = "visits vertex " + s(dup) + " twice";
      } else if (!opt_.keep_degenerate &&
                 (face.size() == 3 ? is_collinear(P[face[0]], P[face[1]], P[face[2]])
                                   : zero_area(face, pts))) {
        why = "zero area";
      }
      if (!why.empty()) {
        if (strict_) fail("face " + s(f) + " is degenerate: " + why);
        degenerate_.add("face " + s(f) + ": " + why);
        w = mark;
        continue;
      }
      if (collapsed) {
        if (strict_) fail("face " + s(f) + " repeats a vertex in consecutive corners");
        collapsed_.add("face " + s(f));
      }
      std::uint64_t h = mix64(w - mark);
      for (std::uint32_t c = mark; c < w; ++c) h += mix64(cv_[c]);
      fhash_.push_back(h);
      offs_.push_back(w);
      forig_.push_back(static_cast<std::uint32_t>(f));
    }
    cv_.resize(w);
    if (keep_corig) corig_.resize(w);
    index_corners();
  }

  bool zero_area(std::span<const std::uint32_t> face, std::vector<Point>& pts) const {
    pts.clear();
    for (std::uint32_t v : face) pts.push_back(soup_->positions[v]);
    return is_zero_area_polygon(pts);
  }

  std::uint32_t repeated_vertex(std::span<const std::uint32_t> face) {
    if (face.size() <= 8) {
      for (std::size_t i = 0; i < face.size(); ++i)
        for (std::size_t j = i + 1; j < face.size(); ++j)
          if (face[i] == face[j]) return face[i];
      return kNone;
    }
    scratch_.assign(face.begin(), face.end());
    std::sort(scratch_.begin(), scratch_.end());
    auto it = std::adjacent_find(scratch_.begin(), scratch_.end());
    return it == scratch_.end() ? kNone : *it;
  }

  // An order-independent hash of each face's vertex set, and the face of each corner.
  void index_faces() {
    const std::size_t nf = offs_.size() - 1;
    fhash_.resize(nf);
    for (std::uint32_t f = 0; f < nf; ++f) {
      std::uint64_t h = mix64(offs_[f + 1] - offs_[f]);
      for (std::uint32_t c = offs_[f]; c < offs_[f + 1]; ++c) h += mix64(cv_[c]);
      fhash_[f] = h;
    }
    index_corners();
  }

  // Triangle meshes (the common case) find a corner's face and neighbours by arithmetic;
  // other meshes keep a face per corner.
  void index_corners() {
    tri_ = cv_.size() == 3 * static_cast<std::size_t>(n_faces());
    cf_.clear();
    if (tri_) return;
    cf_.resize(cv_.size());
    for (std::uint32_t f = 0; f < n_faces(); ++f)
      std::fill(cf_.begin() + offs_[f], cf_.begin() + offs_[f + 1], f);
  }

  std::uint32_t face_of(std::uint32_t c) const { return tri_ ? c / 3 : cf_[c]; }
  std::uint32_t nxt(std::uint32_t c) const {
    if (tri_) return c % 3 == 2 ? c - 2 : c + 1;
    std::uint32_t f = cf_[c];
    return c + 1 == offs_[f + 1] ? offs_[f] : c + 1;
  }
  std::uint32_t prv(std::uint32_t c) const {
    if (tri_) return c % 3 == 0 ? c + 2 : c - 1;
    std::uint32_t f = cf_[c];
    return c == offs_[f] ? offs_[f + 1] - 1 : c - 1;
  }
  std::uint32_t face_size(std::uint32_t f) const { return offs_[f + 1] - offs_[f]; }
  std::uint32_t n_faces() const { return static_cast<std::uint32_t>(offs_.size() - 1); }

  bool same_vertex_set(std::uint32_t f, std::uint32_t g) {
    if (fhash_[f] != fhash_[g] || face_size(f) != face_size(g)) return false;
    scratch_.assign(cv_.begin() + offs_[f], cv_.begin() + offs_[f + 1]);
    scratch2_.assign(cv_.begin() + offs_[g], cv_.begin() + offs_[g + 1]);
    std::sort(scratch_.begin(), scratch_.end());
    std::sort(scratch2_.begin(), scratch2_.end());
    return scratch_ == scratch2_;
  }

  std::string edge_name(std::uint32_t c) const {
    return "(" + s(cv_[c]) + ", " + s(cv_[nxt(c)]) + ")";
  }

  // ---- 2. pairing ----------------------------------------------------------------------
  // Pairs the halfedges of each undirected edge greedily in corner (= face) order: each
  // unpaired halfedge takes the next unpaired one running the other way; with
  // any_direction, one running the same way if there is none (its faces disagree on
  // orientation and orient() will settle it). Whatever stays unpaired becomes boundary.
  void pair(bool any_direction) {
    groups_ = detail::group_edges(nv_, offs_, cv_);
    mate_.assign(cv_.size(), kNone);
    same_direction_pairs_ = 0;
    duplicates_found_ = false;
    nonmanifold_ = Tally();
    mixed_groups_.clear();
    const auto& E = groups_.entries;
    groups_.for_each_edge([&](std::uint32_t, std::uint32_t i, std::uint32_t j) {
      const std::uint32_t m = j - i;
      if (m == 1) return;
      // Same vertex set across a shared edge: a duplicate face (checked on every edge, as
      // duplicates share all their edges).
      for (std::uint32_t a = i; a < j && !opt_.keep_degenerate; ++a)
        for (std::uint32_t b = a + 1; b < j; ++b) {
          std::uint32_t f = face_of(E[a].corner), g = face_of(E[b].corner);
          if (same_vertex_set(f, g)) {
            std::uint32_t later = std::max(f, g);
            if (strict_) fail("face " + s(forig_[later]) + " repeats face " + s(forig_[std::min(f, g)]));
            if (!drop_face_.size()) drop_face_.assign(n_faces(), 0);
            if (!drop_face_[later]) {
              drop_face_[later] = 1;
              duplicate_.add("face " + s(forig_[later]) + " repeats face " + s(forig_[std::min(f, g)]));
            }
            duplicates_found_ = true;
          }
        }
      if (m >= 3) {
        std::string faces;
        for (std::uint32_t a = i; a < j && a < i + 4; ++a)
          faces += (a == i ? "" : ", ") + s(forig_[face_of(E[a].corner)]);
        if (strict_) fail("edge " + edge_name(E[i].corner) + " has " + s(m) + " faces (" + faces + ")");
        nonmanifold_.add("edge " + edge_name(E[i].corner) + " with faces " + faces + (m > 4 ? ", ..." : ""));
      }
      bool unpaired = false;
      for (std::uint32_t a = i; a < j; ++a) {
        std::uint32_t ca = E[a].corner;
        if (mate_[ca] != kNone) continue;
        std::uint32_t pick = kNone, any = kNone;
        for (std::uint32_t b = a + 1; b < j && pick == kNone; ++b) {
          std::uint32_t cb = E[b].corner;
          if (mate_[cb] != kNone) continue;
          if (cv_[cb] != cv_[ca]) pick = cb;
          else if (any == kNone) any = cb;
        }
        if (pick == kNone && any_direction) pick = any;
        if (pick == kNone) {
          unpaired = true;
          continue;
        }
        mate_[ca] = pick;
        mate_[pick] = ca;
        if (cv_[pick] == cv_[ca]) {
          ++same_direction_pairs_;
          if (strict_)
            fail("face " + s(forig_[face_of(pick)]) + " is oriented against face " + s(forig_[face_of(ca)]) +
                 " across edge " + edge_name(ca));
        }
      }
      if (unpaired || m >= 3) mixed_groups_.emplace_back(i, j);
    });
  }

  void count_cut_edges() {
    const auto& E = groups_.entries;
    groups_.for_each_edge([&](std::uint32_t, std::uint32_t i, std::uint32_t j) {
      if (j - i == 2 && cv_[E[i].corner] == cv_[E[i + 1].corner]) {
        if (strict_) fail("face " + s(forig_[face_of(E[i + 1].corner)]) + " is oriented against face " +
                          s(forig_[face_of(E[i].corner)]) + " across edge " + edge_name(E[i].corner));
        cut_.add("edge " + edge_name(E[i].corner) + " between faces " + s(forig_[face_of(E[i].corner)]) +
                 " and " + s(forig_[face_of(E[i + 1].corner)]));
      }
    });
  }

  // Drop the faces marked as duplicates and rebuild the per-corner arrays.
  void remove_duplicates() {
    std::vector<std::uint32_t> offs{0}, cv, corig, forig;
    for (std::uint32_t f = 0; f < n_faces(); ++f) {
      if (drop_face_[f]) continue;
      for (std::uint32_t c = offs_[f]; c < offs_[f + 1]; ++c) {
        cv.push_back(cv_[c]);
        if (!corig_.empty()) corig.push_back(corig_[c]);
      }
      offs.push_back(static_cast<std::uint32_t>(cv.size()));
      forig.push_back(forig_[f]);
    }
    offs_.swap(offs);
    cv_.swap(cv);
    corig_.swap(corig);
    forig_.swap(forig);
    drop_face_.clear();
    index_faces();
  }

  // ---- 3. orientation -----------------------------------------------------------------
  // BFS over faces through the pairing: a neighbour across a same-direction pair must flip
  // relative to its parent. A pair that contradicts the BFS assignment marks the component
  // non-orientable and is cut (pair(false) leaves it unpaired). Each component then keeps
  // the orientation most of its faces already had.
  void orient() {
    const std::uint32_t nf = n_faces();
    std::vector<std::uint8_t> flip(nf, 0), seen(nf, 0);
    std::vector<std::uint32_t> queue;
    for (std::uint32_t root = 0; root < nf; ++root) {
      if (seen[root]) continue;
      queue.clear();
      queue.push_back(root);
      seen[root] = 1;
      std::size_t flips = 0;
      for (std::size_t qi = 0; qi < queue.size(); ++qi) {
        std::uint32_t f = queue[qi];
        flips += flip[f];
        for (std::uint32_t c = offs_[f]; c < offs_[f + 1]; ++c) {
          std::uint32_t d = mate_[c];
          if (d == kNone) continue;
          std::uint32_t g = face_of(d);
          std::uint8_t want = flip[f] ^ static_cast<std::uint8_t>(cv_[c] == cv_[d]);
          if (!seen[g]) {
            seen[g] = 1;
            flip[g] = want;
            queue.push_back(g);
          } else if (flip[g] != want && c < d) {
            rep_.orientable = false;
            cut_.add("edge " + edge_name(c) + " between faces " + s(forig_[f]) + " and " + s(forig_[g]));
          }
        }
      }
      if (2 * flips > queue.size())
        for (std::uint32_t f : queue) flip[f] ^= 1;
    }
    for (std::uint32_t f = 0; f < nf; ++f) {
      if (!flip[f]) continue;
      if (flipped_.count < 3) flipped_.add("face " + s(forig_[f]));
      else ++flipped_.count;
      // Reverse the corner order but keep the first corner first.
      std::reverse(cv_.begin() + offs_[f] + 1, cv_.begin() + offs_[f + 1]);
      if (!corig_.empty()) std::reverse(corig_.begin() + offs_[f] + 1, corig_.begin() + offs_[f + 1]);
    }
  }

  // ---- 4. fans --------------------------------------------------------------------------
  // The corner that opens the fan containing c0: the one whose incoming halfedge is
  // boundary, or c0 itself when the fan closes.
  std::uint32_t fan_start(std::uint32_t c0) const {
    std::uint32_t start = c0;
    for (;;) {
      std::uint32_t m = mate_[prv(start)];
      if (m == kNone || m == c0) return start;
      start = m;
    }
  }
  // Calls fn(c) for each corner of the fan opened by `start`, counter-clockwise.
  template <class Fn>
  void for_fan(std::uint32_t start, Fn&& fn) const {
    std::uint32_t c = start;
    do {
      fn(c);
      std::uint32_t m = mate_[c];
      if (m == kNone) break;
      c = nxt(m);
    } while (c != start);
  }

  // Clean input has one fan per vertex. Walking only each vertex's first fan and finding
  // that those fans hold every corner proves it, without a per-corner fan array.
  bool single_fans() {
    const std::uint32_t nc = static_cast<std::uint32_t>(cv_.size());
    first_start_.assign(nv_, kNone);
    std::size_t covered = 0;
    for (std::uint32_t c0 = 0; c0 < nc; ++c0) {
      std::uint32_t v = cv_[c0];
      if (first_start_[v] != kNone) continue;
      first_start_[v] = fan_start(c0);
      for_fan(first_start_[v], [&](std::uint32_t) { ++covered; });
    }
    return covered == nc;
  }

  // Assigns each corner its fan's vertex id (fanv_): the input vertex for a vertex's first
  // fan, nv_ + k for the k-th extra fan.
  void walk_fans() {
    const std::uint32_t nc = static_cast<std::uint32_t>(cv_.size());
    extra_origin_.clear();
    extra_face_.clear();
    extra_start_.clear();
    fanv_.clear();
    if (mixed_groups_.empty() && !any_detached_ && single_fans()) return;
    fanv_.assign(nc, kNone);
    first_start_.assign(nv_, kNone);
    for (std::uint32_t c0 = 0; c0 < nc; ++c0) {
      if (fanv_[c0] != kNone) continue;
      const std::uint32_t start = fan_start(c0);
      std::uint32_t v = cv_[c0], id;
      if (first_start_[v] == kNone) {
        first_start_[v] = start;
        id = v;
      } else {
        id = nv_ + static_cast<std::uint32_t>(extra_origin_.size());
        extra_origin_.push_back(v);
        extra_face_.push_back(face_of(c0));
        extra_start_.push_back(start);
      }
      for_fan(start, [&](std::uint32_t c) { fanv_[c] = id; });
    }
  }

  // Two edges between the same pair of vertices are not a valid mesh. They can only arise
  // on an input edge that kept unpaired halfedges; such a face is detached (its pairings
  // cut) until none is left.
  bool detach_doubled_edges() {
    const auto& E = groups_.entries;
    std::vector<std::uint32_t> to_detach;
    auto check = [&](std::uint32_t i, std::uint32_t j) {
      for (std::uint32_t a = i; a < j; ++a) {
        std::uint32_t ca = E[a].corner;
        if (mate_[ca] != kNone && mate_[ca] < ca) continue;
        auto ka = std::minmax(fanv_[ca], fanv_[nxt(ca)]);
        for (std::uint32_t b = a + 1; b < j; ++b) {
          std::uint32_t cb = E[b].corner;
          if (mate_[cb] != kNone && mate_[cb] < cb) continue;
          if (std::minmax(fanv_[cb], fanv_[nxt(cb)]) != ka) continue;
          std::uint32_t fb = face_of(cb);
          if (mate_[cb] != kNone) fb = std::max(fb, face_of(mate_[cb]));
          to_detach.push_back(fb);
        }
      }
    };
    if (any_detached_) {
      groups_.for_each_edge([&](std::uint32_t, std::uint32_t i, std::uint32_t j) {
        if (j - i >= 2) check(i, j);
      });
    } else {
      for (auto [i, j] : mixed_groups_) check(i, j);
    }
    if (to_detach.empty()) return false;
    if (detached_.size() < n_faces()) detached_.assign(n_faces(), 0);
    for (std::uint32_t f : to_detach) {
      if (detached_[f]) continue;
      detached_[f] = 1;
      detached_tally_.add("face " + s(forig_[f]));
      for (std::uint32_t c = offs_[f]; c < offs_[f + 1]; ++c)
        if (mate_[c] != kNone) {
          mate_[mate_[c]] = kNone;
          mate_[c] = kNone;
        }
    }
    any_detached_ = true;
    return true;
  }

  void split_fans() {
    for (;;) {
      walk_fans();
      if (mixed_groups_.empty() && !any_detached_) break;
      if (!detach_doubled_edges()) break;
    }
    if (extra_origin_.empty()) return;
    if (strict_)
      fail("face " + s(forig_[extra_face_[0]]) + " meets the other faces at vertex " + s(extra_origin_[0]) +
           " only in that vertex (a non-manifold vertex)");
    std::vector<std::uint8_t> counted(nv_, 0);
    std::vector<std::uint32_t> fans(nv_, 1);
    for (std::uint32_t v : extra_origin_) ++fans[v];
    for (std::uint32_t v : extra_origin_) {
      if (counted[v]) continue;
      counted[v] = 1;
      nonmanifold_vertices_.add("vertex " + s(v) + " into " + s(fans[v]));
    }
  }

  // ---- 5. emit --------------------------------------------------------------------------
  SurfaceMesh emit() {
    const std::uint32_t nc = static_cast<std::uint32_t>(cv_.size());
    const std::uint32_t nf = n_faces();
    // Output numbering: kept input vertices in input order, then the split-off copies.
    std::vector<std::uint32_t> out(nv_, kNone);
    std::uint32_t n_out = 0;
    for (std::uint32_t v = 0; v < nv_; ++v) {
      if (rep(v) != v) continue;
      if (first_start_[v] == kNone) {
        ++rep_.unreferenced_vertices;
        if (opt_.drop_unreferenced) {
          if (unreferenced_.count < 3) unreferenced_.add("vertex " + s(v));
          else ++unreferenced_.count;
          continue;
        }
      }
      out[v] = n_out++;
    }
    const std::uint32_t base = n_out;
    n_out += static_cast<std::uint32_t>(extra_origin_.size());
    auto outv = [&](std::uint32_t c) {
      std::uint32_t id = fanv_.empty() ? cv_[c] : fanv_[c];
      return id < nv_ ? out[id] : base + (id - nv_);
    };

    rep_.vertex_map.assign(nv_, Vertex());
    for (std::uint32_t v = 0; v < nv_; ++v)
      if (out[rep(v)] != kNone) rep_.vertex_map[v] = Vertex(out[rep(v)]);
    rep_.vertex_origin.resize(n_out);
    for (std::uint32_t v = 0; v < nv_; ++v)
      if (out[v] != kNone) rep_.vertex_origin[out[v]] = v;
    for (std::size_t k = 0; k < extra_origin_.size(); ++k) rep_.vertex_origin[base + k] = extra_origin_[k];
    rep_.face_origin = forig_;

    std::size_t n_edges = 0;
    for (std::uint32_t c = 0; c < nc; ++c)
      if (mate_[c] == kNone || mate_[c] > c) ++n_edges;

    SurfaceMesh mesh;
    mesh.reserve(n_out, n_edges, nf);
    for (std::uint32_t v = 0; v < n_out; ++v) mesh.new_vertex();
    auto& pos = mesh.positions().vector();
    for (std::uint32_t v = 0; v < n_out; ++v) pos[v] = soup_->positions[rep_.vertex_origin[v]];

    // mate_ turns into he_ in place: entries below c already hold halfedges.
    for (std::uint32_t c = 0; c < nc; ++c) {
      std::uint32_t m = mate_[c];
      if (m != kNone && m < c) {
        mate_[c] = mate_[m] ^ 1u;
        continue;
      }
      Vertex a(outv(c)), b(outv(nxt(c)));
      Halfedge h = mesh.new_edge(a, b);
      mesh.set_vertex(h, b);
      mesh.set_vertex(SurfaceMesh::opposite(h), a);
      mesh.set_face(SurfaceMesh::opposite(h), Face());
      mate_[c] = h.idx();
    }
    he_ = std::move(mate_);
    mate_.clear();
    for (std::uint32_t f = 0; f < nf; ++f) {
      Face fh = mesh.new_face();
      const std::uint32_t b = offs_[f], e = offs_[f + 1];
      for (std::uint32_t c = b; c < e; ++c) {
        mesh.set_face(Halfedge(he_[c]), fh);
        mesh.set_next(Halfedge(he_[c]), Halfedge(he_[c + 1 == e ? b : c + 1]));
      }
      // halfedge(f) ends at the first corner, so vertices(f) starts there.
      mesh.set_halfedge(fh, Halfedge(he_[e - 1]));
    }
    // A vertex's halfedge is its outgoing boundary one when it has one: after fan splitting
    // a vertex is one fan, open at most once, and the fan's recorded start corner is right
    // after that opening. The boundary loop goes on from there too.
    auto anchor = [&](std::uint32_t id, std::uint32_t start) {
      std::uint32_t p = prv(start);
      Halfedge in(he_[p]);
      mesh.set_halfedge(Vertex(id), mesh.is_boundary(SurfaceMesh::opposite(in)) ? SurfaceMesh::opposite(in)
                                                                               : Halfedge(he_[start]));
    };
    for (std::uint32_t v = 0; v < nv_; ++v)
      if (first_start_[v] != kNone) anchor(out[v], first_start_[v]);
    for (std::size_t k = 0; k < extra_start_.size(); ++k)
      anchor(base + static_cast<std::uint32_t>(k), extra_start_[k]);
    for (std::uint32_t c = 0; c < nc; ++c) {
      Halfedge bh = SurfaceMesh::opposite(Halfedge(he_[c]));
      if (mesh.is_boundary(bh)) mesh.set_next(bh, mesh.halfedge(mesh.to_vertex(bh)));
    }
    return mesh;
  }

  // ---- attributes -----------------------------------------------------------------------
  void copy_attributes(SurfaceMesh& mesh) {
    std::vector<std::uint32_t> into;
    if (!corig_.empty()) {
      into.resize(cv_.size());
      for (std::uint32_t c = 0; c < cv_.size(); ++c) into[c] = he_[prv(c)];
    }
    detail::AttributeSources from;
    from.weld = weld_;
    from.vertex_origin = rep_.vertex_origin;
    from.face_origin = forig_;
    from.corner_origin = corig_;
    from.into_corner = into;
    from.corner_halfedge = he_;
    from.groups = &groups_;
    std::vector<std::string> notes;
    detail::copy_attributes(mesh, *soup_, from, notes);
    for (const auto& note : notes) ignored_.add(note);
  }

  void write_messages() {
    auto& r = rep_;
    r.welded_vertices = welded_.count;
    r.dropped_out_of_range = out_of_range_.count;
    r.dropped_degenerate = degenerate_.count;
    r.dropped_duplicate = duplicate_.count;
    r.collapsed_corners = collapsed_.count;
    r.split_nonmanifold_edges = nonmanifold_.count;
    r.split_nonmanifold_vertices = nonmanifold_vertices_.count;
    r.flipped_faces = flipped_.count;
    r.cut_edges = cut_.count;
    r.detached_faces = detached_tally_.count;
    r.dropped_unreferenced = unreferenced_.count;
    auto put = [&](const Tally& t, const std::string& what) {
      if (t.count) r.messages.push_back(t.message(what));
    };
    put(welded_, "welded vertices");
    put(out_of_range_, "dropped faces with out-of-range indices");
    put(degenerate_, "dropped degenerate faces");
    put(duplicate_, "dropped duplicate faces");
    put(collapsed_, "faces with repeated consecutive corners collapsed");
    put(nonmanifold_, "non-manifold edges split (extra faces keep their own edge)");
    put(detached_tally_, "faces detached from a non-manifold edge");
    put(nonmanifold_vertices_, "non-manifold vertices split into one vertex per fan");
    put(flipped_, "faces flipped to agree with their neighbours");
    put(cut_, opt_.orient ? "edges cut where the surface is not orientable"
                          : "edges left as boundary where neighbouring faces disagree in orientation");
    put(unreferenced_, "dropped unreferenced vertices");
    put(seams_kept_, "welded vertices whose texture coordinates or normals differ (kept per face corner, so the seam stays)");
    put(recoloured_, "welded vertices whose colour differs (they take their representative's colour)");
    put(ignored_, "attributes ignored");
  }

  const PolygonSoup* soup_;
  PolygonSoup seamed_;  // the input with seam values moved to the corners (keep_seams)
  const BuildOptions& opt_;
  BuildReport& rep_;
  const bool strict_;
  std::uint32_t nv_ = 0;

  std::vector<std::uint32_t> weld_;
  std::vector<std::uint32_t> offs_, cv_, corig_, forig_, cf_;
  std::vector<std::uint64_t> fhash_;
  std::vector<std::uint32_t> mate_, fanv_, extra_origin_, extra_face_, extra_start_, he_;
  std::vector<std::uint32_t> first_start_;  ///< per input vertex: its first fan's start corner
  std::vector<std::pair<std::uint32_t, std::uint32_t>> mixed_groups_;
  std::vector<std::uint8_t> drop_face_, detached_;
  std::vector<std::uint32_t> scratch_, scratch2_;
  detail::EdgeGroups groups_;
  std::size_t same_direction_pairs_ = 0;
  bool tri_ = false;
  bool duplicates_found_ = false, any_detached_ = false;

  Tally welded_, out_of_range_, degenerate_, duplicate_, collapsed_, nonmanifold_,
      nonmanifold_vertices_, flipped_, cut_, unreferenced_, ignored_, detached_tally_, seams_kept_, recoloured_;
};

}  // namespace

bool BuildReport::changed() const {
  return welded_vertices || dropped_out_of_range || dropped_degenerate || dropped_duplicate ||
         split_nonmanifold_edges || split_nonmanifold_vertices || flipped_faces ||
         collapsed_corners || cut_edges || detached_faces || dropped_unreferenced;
}

BuildResult build(const PolygonSoup& soup, const BuildOptions& options) {
  BuildResult result;
  Builder builder(soup, options, result.report);
  result.mesh = builder.run();
  return result;
}

}  // namespace geom
