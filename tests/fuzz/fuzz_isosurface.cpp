// libFuzzer target for marching cubes on hard grids: the bytes choose a small grid (2–9
// samples a side, float or double, with a huge origin or anisotropic spacing) and its
// samples, drawn from values that stress the rules of marching_cubes.h: samples equal to the
// level or one ulp beside it, ±inf, ±0, subnormals, ±DBL_MAX and NaN. Checked on every run:
// - a NaN sample is refused with InvalidArgument, and nothing else is;
// - the arrays are edge- and vertex-manifold and consistently oriented, every vertex used;
// - boundary edges lie on the grid's outer faces only, and there are none when stats.closed;
// - a closed surface's normals point out of the region it encloses (by signed volume);
// - no vertex outside the grid's box, no two vertices or corners of a triangle coincide
//   (where the coordinates resolve 1/1024 of a cell);
// - normals, when asked for, are unit or zero; the serial and parallel runs make the same
//   triangles;
// - the SurfaceMesh validates with the arrays' counts.

#include "fuzz_check.h"

#include "../isosurface/surface_check.h"

#include <geom/core/errors.h>
#include <geom/core/validate.h>
#include <geom/isosurface/marching_cubes.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

struct Bytes {
  const std::uint8_t* data;
  std::size_t size, at = 0;
  std::uint8_t next() { return at < size ? data[at++] : 0; }
};

// A sample from one byte: near the level most of the time, so that ties and saddles come up.
double sample(std::uint8_t b, double level) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kMax = std::numeric_limits<double>::max();
  constexpr double kSub = std::numeric_limits<double>::denorm_min();
  switch (b % 16) {
    case 0: return level;
    case 1: return std::nextafter(level, kInf);
    case 2: return std::nextafter(level, -kInf);
    case 3: return kInf;
    case 4: return -kInf;
    case 5: return kMax;
    case 6: return -kMax;
    case 7: return kSub;
    case 8: return -0.0;
    case 9: return b == 9 ? std::numeric_limits<double>::quiet_NaN() : level + 1;
    default: return level + (double(b >> 4) - 7.5) * (b % 16 - 9);
  }
}

// Signed volume in cell units about the grid's centre, so that a huge origin cancels.
double cell_volume(const geom::IsoSurface& s, const geom::GridView& g) {
  const geom::GridDims& d = g.dims;
  const Eigen::Vector3d centre(double(d.nx - 1) / 2, double(d.ny - 1) / 2, double(d.nz - 1) / 2);
  auto cell = [&](std::uint32_t i) -> Eigen::Vector3d {
    return (s.positions[i] - g.geometry.origin).cwiseQuotient(g.geometry.spacing) - centre;
  };
  double v = 0;
  for (const auto& t : s.triangles) v += cell(t[0]).dot(cell(t[1]).cross(cell(t[2]))) / 6;
  return v;
}

void check_arrays(const geom::IsoSurface& s, const geom::GridView& g, double level,
                  geom::NormalDirection toward, bool resolved, bool normals) {
  const geom::test::SurfaceCheck c = geom::test::check_surface(s);
  FUZZ_CHECK(c.repeated_directed_edges == 0 && c.nonmanifold_vertices == 0);
  FUZZ_CHECK(c.unused_vertices == 0);
  FUZZ_CHECK(s.stats.vertices == s.positions.size() && s.stats.triangles == s.triangles.size());
  FUZZ_CHECK(geom::test::boundary_edges_off_grid_boundary(g, s) == 0);
  if (s.stats.closed) FUZZ_CHECK(c.boundary_edges == 0);
  if (s.stats.closed && !s.triangles.empty()) {
    // The outer samples are all on one side; the normals leave the region they enclose.
    const bool outside_above = g.at(0, 0, 0) >= level;
    const bool outward = outside_above == (toward == geom::NormalDirection::kIncreasing);
    FUZZ_CHECK(outward ? cell_volume(s, g) > 0 : cell_volume(s, g) < 0);
  }
  if (resolved) FUZZ_CHECK(c.degenerate_triangles == 0 && c.coincident_vertices == 0);
  const Eigen::Vector3d lo = g.geometry.origin;
  const Eigen::Vector3d hi = g.position(g.dims.nx - 1, g.dims.ny - 1, g.dims.nz - 1);
  for (const geom::Point& p : s.positions)
    FUZZ_CHECK(p.allFinite() && (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all());
  FUZZ_CHECK(s.normals.size() == (normals ? s.positions.size() : 0));
  for (const geom::Normal& n : s.normals)
    FUZZ_CHECK(n.allFinite() && (n.squaredNorm() == 0 || std::abs(n.norm() - 1) < 1e-12));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes in{data, size};
  const geom::GridDims dims{2u + in.next() % 8, 2u + in.next() % 8, 2u + in.next() % 8};
  const std::uint8_t flags = in.next();
  geom::MarchingCubesOptions o;
  const double levels[4] = {0.0, 0.5, -3.0, 1e300};
  o.level = levels[flags & 3];
  o.normals_toward = flags & 4 ? geom::NormalDirection::kDecreasing : geom::NormalDirection::kIncreasing;
  o.compute_normals = (flags & 8) != 0;
  const bool use_double = (flags & 16) != 0;
  geom::GridGeometry geometry;
  if (flags & 32) geometry.origin = {1e9, -1e9, 3.5e8};
  if (flags & 64) geometry.spacing = {1e-3, 1.0, 1e4};

  std::vector<double> values(dims.size());
  bool nan = false;
  for (double& v : values) {
    v = sample(in.next(), o.level);
    if (!use_double) v = static_cast<float>(v);  // a float grid holds what a float can
    nan |= std::isnan(v);
  }
  std::vector<float> floats(values.begin(), values.end());
  geom::GridView g{dims, geometry, std::span<const double>(values)};
  if (!use_double) g.values = std::span<const float>(floats);

  // 1/1024 of a cell is resolved when a cell holds 2^20 ulps of the largest coordinate.
  const double extent = (geometry.origin.cwiseAbs() + geometry.spacing * 9.0).maxCoeff();
  const bool resolved = geometry.spacing.minCoeff() > extent * 0x1p-32;

  geom::IsoSurface serial, parallel;
  try {
    o.parallel = false;
    serial = geom::marching_cubes_arrays(g, o);
    o.parallel = true;
    parallel = geom::marching_cubes_arrays(g, o);
  } catch (const geom::InvalidArgument&) {
    FUZZ_CHECK(nan);
    return 0;
  }
  FUZZ_CHECK(!nan);
  check_arrays(serial, g, o.level, o.normals_toward, resolved, o.compute_normals);
  // Slabs number their vertices in their own order; the triangles must be the same.
  FUZZ_CHECK(geom::test::triangle_set(parallel) == geom::test::triangle_set(serial));

  const geom::MarchingCubesResult r = geom::marching_cubes(g, o);
  FUZZ_CHECK(geom::validate(r.mesh).ok());
  FUZZ_CHECK(r.mesh.n_faces() == serial.triangles.size() && r.mesh.n_vertices() == serial.positions.size());
  return 0;
}
