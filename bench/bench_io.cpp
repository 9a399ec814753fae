// Mesh I/O speed against OpenMesh on a generated 1M-triangle torus, side by side:
//   (a) building a half-edge mesh from an indexed face list,
//   (b) binary PLY file → half-edge mesh,
//   (c) OBJ file → half-edge mesh,
// plus the raw parse (read_soup alone) and the bare cost of reading the file's bytes.
// Usage: bench_io [n]   (torus of n × n quads split in two; default 708 ≈ 1.0M triangles)

#include "support/harness.h"

#include <geom/core/build.h>
#include <geom/io/io.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <numbers>

namespace {

using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;
using geom::bench::fmt;
using geom::bench::ratio;
using geom::bench::time_min;

geom::PolygonSoup torus(int n) {
  geom::PolygonSoup s;
  s.positions.reserve(static_cast<std::size_t>(n) * n);
  const double R = 1.0, r = 0.35;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / n;
      geom::Point p((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
      // Float coordinates, as scanners and most PLY files have them (and OpenMesh stores).
      for (int k = 0; k < 3; ++k) {
        volatile float f = static_cast<float>(p[k]);
        p[k] = f;
      }
      s.positions.push_back(p);
    }
  auto id = [n](int i, int j) { return static_cast<std::uint32_t>(((i + n) % n) * n + (j + n) % n); };
  s.face_offsets.reserve(2ull * n * n + 1);
  s.face_indices.reserve(6ull * n * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      s.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return s;
}

void om_build(const geom::PolygonSoup& s, OmMesh& m) {
  m.clear();
  m.reserve(s.positions.size(), s.face_indices.size() / 2, s.n_faces());
  std::vector<OmMesh::VertexHandle> vh;
  vh.reserve(s.positions.size());
  for (const auto& p : s.positions)
    vh.push_back(m.add_vertex(OmMesh::Point(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                            static_cast<float>(p.z()))));
  for (std::size_t f = 0; f < s.n_faces(); ++f) {
    auto c = s.face(f);
    m.add_face(vh[c[0]], vh[c[1]], vh[c[2]]);
  }
}

double file_mb(const std::filesystem::path& p) { return static_cast<double>(std::filesystem::file_size(p)) / 1e6; }

double read_bytes(const std::filesystem::path& p) {
  return time_min([&] {
    std::ifstream f(p, std::ios::binary);
    std::vector<char> buf(std::filesystem::file_size(p));
    f.read(buf.data(), static_cast<std::streamsize>(buf.size()));
  });
}

}  // namespace

int main(int argc, char** argv) {
  if (geom::bench::wants_help(argc, argv, "usage: bench_io [n]   (a torus of n x n quads split in two; default 708, about 1M triangles)")) return 0;
  const int n = argc > 1 ? std::max(8, std::atoi(argv[1])) : 708;
  const auto dir = std::filesystem::temp_directory_path() / "geom_bench_io";
  std::filesystem::create_directories(dir);
  const geom::PolygonSoup soup = torus(n);
  const auto ply = dir / "torus.ply", obj = dir / "torus.obj";
  geom::write_soup(soup, ply);
  geom::write_soup(soup, obj);
  std::cout << "torus " << n << "x" << n << ": " << soup.positions.size() << " vertices, " << soup.n_faces()
            << " triangles; PLY " << fmt(file_mb(ply)) << " MB, OBJ " << fmt(file_mb(obj)) << " MB\n\n";

  geom::bench::Table table({"task", "input", "geom_s", "openmesh_s", "ratio", "geom_MB/s", "openmesh_MB/s", "faces"});
  std::size_t faces = 0;

  // (a) build from indices
  const double t_build = time_min([&] { faces = geom::build(soup).mesh.n_faces(); });
  OmMesh om;
  const double t_om_build = time_min([&] { om_build(soup, om); });
  table.add({"build from indices", "torus soup", fmt(t_build), fmt(t_om_build), ratio(t_build, t_om_build), "", "",
             std::to_string(faces) + "/" + std::to_string(om.n_faces())});

  for (const auto& [label, path] : {std::pair{"binary PLY", ply}, std::pair{"OBJ", obj}}) {
    const double mb = file_mb(path);
    const double t_bytes = read_bytes(path);
    table.add({std::string("read bytes only"), label, fmt(t_bytes), "", "", fmt(mb / t_bytes, 4), "", ""});
    const double t_parse = time_min([&] { faces = geom::read_soup(path).n_faces(); });
    table.add({std::string("parse to soup"), label, fmt(t_parse), "", "", fmt(mb / t_parse, 4), "", std::to_string(faces)});
    const double t_load = time_min([&] { faces = geom::load_mesh(path).mesh.n_faces(); });
    const double t_om = time_min([&] {
      om.clear();
      OmMesh fresh;
      if (!OpenMesh::IO::read_mesh(fresh, path.string())) std::cerr << "OpenMesh failed to read " << path << "\n";
      om = std::move(fresh);
    });
    table.add({std::string("file to half-edge mesh"), label, fmt(t_load), fmt(t_om), ratio(t_load, t_om),
               fmt(mb / t_load, 4), fmt(mb / t_om, 4), std::to_string(faces) + "/" + std::to_string(om.n_faces())});
  }
  table.print();
  const auto csv = geom::bench::out_dir() / "io.csv";
  table.write_csv(csv);
  std::cout << "\nCSV: " << csv.string() << "\n";
  std::filesystem::remove_all(dir);
  return 0;
}
