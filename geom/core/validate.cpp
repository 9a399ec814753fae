#include <geom/core/validate.h>

#include <algorithm>
#include <sstream>
#include <vector>

namespace geom {
namespace {

class Collector {
 public:
  explicit Collector(std::size_t max) : max_(max) {}
  template <class H>
  void add(H h, const std::string& what) {
    if (report.problems.size() >= max_) {
      truncated = true;
      return;
    }
    std::ostringstream s;
    s << h << ": " << what;
    report.problems.push_back(s.str());
  }
  bool full() const { return report.problems.size() >= max_; }
  ValidationReport report;
  bool truncated = false;

 private:
  std::size_t max_;
};

void check_vertices(const SurfaceMesh& m, Collector& out) {
  for (Vertex v : m.vertices()) {
    Halfedge h = m.halfedge(v);
    if (!h.is_valid()) continue;
    if (!m.is_valid(h)) { out.add(v, "halfedge out of range"); continue; }
    if (m.is_deleted(h)) { out.add(v, "halfedge is deleted"); continue; }
    if (m.from_vertex(h) != v) { out.add(v, "halfedge does not leave the vertex"); continue; }
    // Walk the fan; a broken ring must not hang the check.
    bool has_boundary = false;
    std::size_t steps = 0;
    Halfedge x = h;
    do {
      if (m.from_vertex(x) != v) { out.add(v, "rotation left the vertex"); break; }
      has_boundary |= m.is_boundary(x);
      x = m.ccw_rotated(x);
    } while (x != h && ++steps <= m.halfedges_size());
    if (steps > m.halfedges_size()) out.add(v, "outgoing halfedges do not form a cycle");
    if (has_boundary && !m.is_boundary(h))
      out.add(v, "has a boundary halfedge but its halfedge is not one");
  }
}

void check_halfedges(const SurfaceMesh& m, Collector& out) {
  for (Halfedge h : m.halfedges()) {
    if (out.full()) return;
    Halfedge n = m.next(h), p = m.prev(h);
    if (!n.is_valid() || !m.is_valid(n) || m.is_deleted(n)) { out.add(h, "next is invalid or deleted"); continue; }
    if (!p.is_valid() || !m.is_valid(p) || m.is_deleted(p)) { out.add(h, "prev is invalid or deleted"); continue; }
    if (m.prev(n) != h) out.add(h, "prev(next(h)) != h");
    if (m.next(p) != h) out.add(h, "next(prev(h)) != h");
    if (SurfaceMesh::opposite(SurfaceMesh::opposite(h)) != h || SurfaceMesh::opposite(h) == h)
      out.add(h, "opposite is not an involution");
    Vertex v = m.to_vertex(h);
    if (!v.is_valid() || !m.is_valid(v) || m.is_deleted(v)) { out.add(h, "to_vertex is invalid or deleted"); continue; }
    if (m.from_vertex(n) != v) out.add(h, "next(h) does not start where h ends");
    if (m.from_vertex(h) == v) out.add(h, "is a loop (from == to)");
    if (m.face(n) != m.face(h)) out.add(h, "next(h) lies in another face");
    Face f = m.face(h);
    if (f.is_valid() && (!m.is_valid(f) || m.is_deleted(f))) out.add(h, "face is out of range or deleted");
    if (m.is_isolated(v)) out.add(h, "points to a vertex that claims to be isolated");
  }
}

void check_faces(const SurfaceMesh& m, Collector& out) {
  for (Face f : m.faces()) {
    if (out.full()) return;
    Halfedge h = m.halfedge(f);
    if (!h.is_valid() || !m.is_valid(h) || m.is_deleted(h)) { out.add(f, "halfedge invalid or deleted"); continue; }
    std::size_t n = 0;
    Halfedge x = h;
    do {
      if (m.face(x) != f) { out.add(f, "loop contains a halfedge of another face"); break; }
      x = m.next(x);
    } while (x != h && ++n <= m.halfedges_size());
    if (n > m.halfedges_size()) {
      out.add(f, "halfedge loop does not close");
      continue;
    }
    if (n + 1 < 3) out.add(f, "has fewer than 3 corners");
    // A face may not pass through a vertex twice (a dangling edge inside it would).
    std::vector<std::uint32_t> corners;
    for (Vertex v : m.vertices(f)) corners.push_back(v.idx());
    std::sort(corners.begin(), corners.end());
    if (std::adjacent_find(corners.begin(), corners.end()) != corners.end())
      out.add(f, "visits a vertex twice");
  }
}

void check_property_sizes(const SurfaceMesh& m, Collector& out) {
  if (m.props<Vertex>().size() != m.vertices_size()) out.add(Vertex(0), "vertex property size mismatch");
  if (m.props<Halfedge>().size() != m.halfedges_size()) out.add(Halfedge(0), "halfedge property size mismatch");
  if (m.props<Edge>().size() != m.edges_size()) out.add(Edge(0), "edge property size mismatch");
  if (m.props<Face>().size() != m.faces_size()) out.add(Face(0), "face property size mismatch");
}

}  // namespace

std::string ValidationReport::to_string() const {
  std::string s;
  for (const auto& p : problems) s += p + "\n";
  return s;
}

ValidationReport validate(const SurfaceMesh& mesh, std::size_t max_problems) {
  Collector out(max_problems);
  check_property_sizes(mesh, out);
  check_halfedges(mesh, out);
  check_vertices(mesh, out);
  check_faces(mesh, out);
  if (out.truncated) out.report.problems.push_back("... more problems not listed");
  return out.report;
}

RequirementCheck check_requirements(const PolygonSoup& soup, const Requirements& required) {
  BuildOptions no_changes;
  no_changes.orient = false;
  BuildResult built = build(soup, no_changes);
  RequirementCheck check{analyze(soup), std::move(built.report), {}};
  const TopologyReport& t = check.topology;
  auto& failures = check.failures;
  for (const auto& p : validate(built.mesh).problems) failures.push_back("invalid mesh: " + p);
  if (required.manifold && !t.manifold) {
    std::string why = "not manifold:";
    auto add = [&why](std::size_t n, const char* what) {
      // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on " " + to_string.
      if (n) why.append(" ").append(std::to_string(n)).append(what);
    };
    add(t.nonmanifold_edges, " edges with 3 or more faces;");
    add(t.nonmanifold_vertices, " non-manifold vertices;");
    add(t.degenerate_faces, " degenerate faces;");
    if (why.back() == ';') why.pop_back();
    failures.push_back(why);
  }
  if (required.closed && !t.closed)
    failures.push_back("not closed: " + std::to_string(t.boundary_loops) + " boundary loops (" +
                       std::to_string(t.boundary_edges) + " boundary edges)");
  if (required.oriented) {
    // build() with orient=false still detects faces that disagree with their neighbours; a
    // build that may orient reports them as the flips it makes.
    const BuildReport o = build(soup, BuildOptions{}).report;
    if (!o.orientable || !t.orientable)
      failures.push_back("not orientable: some component is a one-sided surface");
    else if (o.flipped_faces)
      failures.push_back("not consistently oriented: " + std::to_string(o.flipped_faces) +
                         " faces disagree with their neighbours");
  }
  return check;
}

}  // namespace geom
