// Builds against the installed geom: makes a tetrahedron, checks it, prints its counts.
#include <geom/core/surface_mesh.h>
#include <geom/core/validate.h>

#include <iostream>

int main() {
  geom::SurfaceMesh m;
  auto a = m.add_vertex({0, 0, 0}), b = m.add_vertex({1, 0, 0});
  auto c = m.add_vertex({0, 1, 0}), d = m.add_vertex({0, 0, 1});
  m.add_triangle(a, c, b);
  m.add_triangle(a, b, d);
  m.add_triangle(b, c, d);
  m.add_triangle(c, a, d);
  if (!geom::validate(m).ok()) return 1;
  std::cout << "V=" << m.n_vertices() << " E=" << m.n_edges() << " F=" << m.n_faces() << "\n";
  return m.n_vertices() - m.n_edges() + m.n_faces() == 2 ? 0 : 1;
}
