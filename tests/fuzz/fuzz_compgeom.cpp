// libFuzzer target for the computational geometry on hard input: the bytes are a point file
// (text lines, at most 2000 points), whose points go through the 2-D Delaunay triangulation
// (checked by check_delaunay_2d: orientation, Euler count, convex boundary, exact in-circle
// test per edge), the Voronoi diagram (cells finite and within the clip box's bounds) and
// the 3-D convex hull (every point on or inside every hull face, by the exact orient3d the
// hull itself uses). Duplicates, collinear, cocircular and huge-coordinate sets come this way.

#include "fuzz_check.h"

#include <geom/compgeom/delaunay2.h>
#include <geom/compgeom/hull3.h>
#include <geom/compgeom/voronoi2.h>
#include <geom/core/errors.h>
#include <geom/io/points.h>
#include <geom/predicates/predicates.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>
#include <vector>

namespace {

// The documented refusals (a non-finite coordinate; coordinates more than 2^400 apart, which
// no exact double arithmetic decides) end a stage; any other exception is a finding.
template <class Stage>
void unless_refused(const Stage& stage) {
  try {
    stage();
  } catch (const geom::InvalidArgument& e) {
    const std::string_view what = e.what();
    FUZZ_CHECK(what.find("2^400 apart") != what.npos || what.find("non-finite") != what.npos);
  }
}

void check_voronoi(const std::vector<Eigen::Vector2d>& xy) {
  const geom::VoronoiResult v = geom::voronoi_2d(xy);
  double lo_x = v.clip[0].x(), hi_x = lo_x, lo_y = v.clip[0].y(), hi_y = lo_y;
  for (const auto& c : v.clip) {
    lo_x = std::min(lo_x, c.x()), hi_x = std::max(hi_x, c.x());
    lo_y = std::min(lo_y, c.y()), hi_y = std::max(hi_y, c.y());
  }
  for (const auto& cell : v.cells)
    for (const auto& p : cell) {
      FUZZ_CHECK(p.allFinite());
      // Cell vertices are floating point: allow their rounding beyond the box.
      const double tx = 1e-9 * (hi_x - lo_x) + 1e-300, ty = 1e-9 * (hi_y - lo_y) + 1e-300;
      FUZZ_CHECK(p.x() >= lo_x - tx && p.x() <= hi_x + tx && p.y() >= lo_y - ty && p.y() <= hi_y + ty);
    }
}

void check_hull(const std::vector<Eigen::Vector3d>& points) {
  const geom::Hull3Result h = geom::convex_hull_3d(points);
  if (h.dimension == 3)
    for (const auto& t : h.triangles)
      for (const auto& p : points)  // no point above an outward face (Shewchuk's sign: < 0)
        FUZZ_CHECK(geom::orient3d(points[t[0]].data(), points[t[1]].data(), points[t[2]].data(), p.data()) >= 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Draco streams are sniffed as meshes, and libdraco sizes its tables from header counts
  // before it reads the data (a 240-byte point cloud took 3.7 GB and ended a run at
  // libFuzzer's memory limit). That reader is fuzz_points' business, not this target's.
  if (size >= 5 && std::memcmp(data, "DRACO", 5) == 0) return 0;
  geom::PointSet s;
  try {
    s = geom::read_points(std::span<const std::byte>(reinterpret_cast<const std::byte*>(data), size), "fuzz.txt",
                          std::nullopt);
  } catch (const geom::ParseError&) {
    return 0;
  }
  if (s.points.empty() || s.points.size() > 2000) return 0;
  std::vector<Eigen::Vector2d> xy;
  for (const auto& p : s.points) xy.emplace_back(p.x(), p.y());

  unless_refused([&] {
    const geom::DelaunayResult d = geom::delaunay_2d(xy);
    FUZZ_CHECK(geom::check_delaunay_2d(xy, d.triangles).empty());
  });
  unless_refused([&] { check_voronoi(xy); });
  unless_refused([&] { check_hull(s.points); });
  return 0;
}
