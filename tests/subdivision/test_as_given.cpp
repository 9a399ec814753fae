// Subdividing a soup as given against OpenSubdiv Far given the same faces: non-manifold
// edges and vertices, repeated corners, duplicate and zero-area faces, faces that disagree
// on orientation, and every OpenSubdiv regression shape Far accepts. Counts, faces and
// positions must agree at every level (positions to 1e-12 of the bounding-box diagonal).

#include "osd_oracle.h"
#include "shapes.h"
#include "support/data.h"

#include <geom/io/io.h>
#include <geom/subdivision/subdivision.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace geom {
namespace {

using test::OsdParams;

double diagonal(const std::vector<Point>& points) {
  Eigen::AlignedBox3d box;
  for (const Point& p : points) box.extend(p);
  return box.isEmpty() ? 1.0 : std::max(box.diagonal().norm(), 1e-300);
}

SubdivideOptions options_of(const OsdParams& p, int levels) {
  SubdivideOptions o;
  o.scheme = p.scheme;
  o.levels = levels;
  o.boundary = p.boundary;
  o.crease_method = p.crease_method;
  return o;
}

/// Geom's as-given refinement of `soup` equals OpenSubdiv's at levels 1..p.levels.
/// Returns false (and checks nothing) when Far refuses the topology.
bool expect_soup_matches_osd(const PolygonSoup& soup, const OsdParams& p, const std::string& what) {
  SCOPED_TRACE(what);
  const test::OsdRun osd = test::run_osd(test::osd_input(soup), p);
  if (!osd.accepted) return false;
  const double tol = 1e-12 * diagonal(soup.positions);
  for (int k = 1; k <= p.levels; ++k) {
    SCOPED_TRACE("level " + std::to_string(k));
    const SoupSubdivideResult r = subdivide(soup, options_of(p, k));
    const PolygonSoup& s = r.soup;
    EXPECT_EQ(s.positions.size(), osd.positions[k].size());
    EXPECT_EQ(s.n_faces(), osd.faces[k].size());
    if (s.positions.size() != osd.positions[k].size() || s.n_faces() != osd.faces[k].size())
      return true;
    EXPECT_EQ(r.per_level.back().vertices, osd.positions[k].size());
    double worst = 0.0;
    for (std::size_t v = 0; v < s.positions.size(); ++v)
      worst = std::max(worst, (s.positions[v] - osd.positions[k][v]).norm());
    EXPECT_LE(worst, tol);
    std::size_t differing_faces = 0;
    for (std::size_t f = 0; f < s.n_faces(); ++f) {
      auto face = s.face(f);
      differing_faces += !std::equal(face.begin(), face.end(), osd.faces[k][f].begin(),
                                     osd.faces[k][f].end(), [](std::uint32_t a, int b) {
                                       return static_cast<int>(a) == b;
                                     });
    }
    EXPECT_EQ(differing_faces, 0u);
  }
  return true;
}

OsdParams cc(int levels) {
  OsdParams p;
  p.levels = levels;
  return p;
}

PolygonSoup soup_of(const std::vector<Point>& points, const std::vector<std::vector<std::uint32_t>>& faces) {
  PolygonSoup s;
  s.positions = points;
  for (const auto& f : faces) s.add_face(std::span<const std::uint32_t>(f.data(), f.size()));
  return s;
}

// Three quads on one edge (a fin), the edge's ends and the far corners varied in height.
PolygonSoup fin() {
  return soup_of({{0, 0, 0}, {0, 1, 0}, {1, 0, 0.1}, {1, 1, 0}, {-1, 0, 0}, {-1, 1, 0.2},
                  {0, 0, 1}, {0, 1, 1.1}},
                 {{0, 1, 3, 2}, {1, 0, 4, 5}, {0, 1, 7, 6}});
}

TEST(AsGiven, FinOfThreeQuadsMatchesOpenSubdiv) {
  PolygonSoup s = fin();
  EXPECT_TRUE(expect_soup_matches_osd(s, cc(3), "fin"));
  const SoupSubdivideResult r = subdivide(s, options_of(cc(1), 1));
  EXPECT_EQ(r.nonmanifold_edges, 1u);
  EXPECT_EQ(r.nonmanifold_vertices, 2u);
  EXPECT_EQ(r.soup.positions.size(), 8u + 10u + 3u);  // vertices, edges, faces of level 0
}

TEST(AsGiven, BowTieVertexMatchesOpenSubdiv) {
  // Two quad fans (pyramids without bases) meeting only at their apex.
  PolygonSoup s = soup_of({{0, 0, 0}, {1, 0, 1}, {0, 1, 1}, {-1, 0, 1}, {0, -1, 1},
                           {1, 0, -1}, {0, 1, -1}, {-1, 0, -1}, {0, -1, -1.2}},
                          {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1},
                           {0, 6, 5}, {0, 7, 6}, {0, 8, 7}, {0, 5, 8}});
  EXPECT_TRUE(expect_soup_matches_osd(s, cc(3), "bow-tie"));
  OsdParams loop = cc(3);
  loop.scheme = SubdivisionScheme::kLoop;
  EXPECT_TRUE(expect_soup_matches_osd(s, loop, "bow-tie, Loop"));
  EXPECT_EQ(subdivide(s, options_of(cc(1), 1)).nonmanifold_vertices, 1u);
}

TEST(AsGiven, RepeatedCornerMatchesOpenSubdiv) {
  // A quad listing vertex 1 twice in a row and a pentagon visiting vertex 0 twice.
  PolygonSoup s = soup_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0.3}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0.5}},
                          {{0, 1, 1, 2}, {1, 4, 5, 2}, {0, 2, 3, 0, 2}});
  EXPECT_TRUE(expect_soup_matches_osd(s, cc(2), "repeated corners"));
  EXPECT_GE(subdivide(s, options_of(cc(1), 1)).degenerate_edges, 1u);
}

TEST(AsGiven, DuplicateAndZeroAreaFacesAreKeptAndMatchOpenSubdiv) {
  // A quad twice the same way, once the other way, and a triangle on a line.
  PolygonSoup s = soup_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0.2}, {0, 1, 0}, {2, 0, 0}, {3, 0, 0}},
                          {{0, 1, 2, 3}, {0, 1, 2, 3}, {3, 2, 1, 0}, {1, 4, 5}});
  EXPECT_TRUE(expect_soup_matches_osd(s, cc(2), "duplicates"));
  EXPECT_EQ(subdivide(s, options_of(cc(1), 1)).soup.n_faces(), 4u * 3u + 3u);
}

TEST(AsGiven, FacesThatDisagreeOnOrientationMatchOpenSubdiv) {
  // A 3×1 strip whose middle quad runs the other way.
  PolygonSoup s = soup_of({{0, 0, 0}, {1, 0, 0.1}, {2, 0, 0}, {3, 0, 0.2}, {0, 1, 0}, {1, 1, 0},
                           {2, 1, 0.3}, {3, 1, 0}},
                          {{0, 1, 5, 4}, {1, 5, 6, 2}, {2, 3, 7, 6}});
  EXPECT_TRUE(expect_soup_matches_osd(s, cc(3), "orientation"));
  EXPECT_EQ(subdivide(s, options_of(cc(1), 1)).nonmanifold_edges, 2u);
}

TEST(AsGiven, ManifoldSoupGivesTheMeshPathsResult) {
  PolygonSoup s = to_soup(test::cube());
  s.creases.push_back({0, 1, 2.5});
  const SoupSubdivideResult r = subdivide(s, options_of(cc(2), 2));
  EXPECT_EQ(r.split_vertices, 0u);
  EXPECT_EQ(r.nonmanifold_edges + r.nonmanifold_vertices, 0u);
  EXPECT_TRUE(expect_soup_matches_osd(s, cc(3), "creased cube"));
}

TEST(AsGiven, BadInputIsRefusedNamingTheFace) {
  PolygonSoup s = soup_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 7}});
  EXPECT_THROW(
      {
        try {
          subdivide(s);
        } catch (const InvalidArgument& e) {
          EXPECT_NE(std::string(e.what()).find("face 0"), std::string::npos) << e.what();
          throw;
        }
      },
      InvalidArgument);
}

BoundaryInterpolation boundary_of_tag(std::optional<int> tag) {
  if (!tag || *tag == 2) return BoundaryInterpolation::kEdges;
  return *tag == 0 ? BoundaryInterpolation::kNone : BoundaryInterpolation::kEdgesAndCorners;
}

/// Every regression shape (the project's copies under tests/data/opensubdiv, and those in
/// $GEOM_DATA_DIR/opensubdiv), as given, at 2 or 3 levels.
TEST(AsGiven, MatchesOpenSubdivOnEveryRegressionShapeItAccepts) {
  std::vector<std::filesystem::path> files;
  for (const auto& dir : {std::filesystem::path(GEOM_SOURCE_DIR) / "tests/data/opensubdiv",
                          test::data_dir().value_or("") / "opensubdiv"}) {
    if (!std::filesystem::is_directory(dir)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      if (entry.path().extension() == ".obj") files.push_back(entry.path());
  }
  ASSERT_GE(files.size(), 80u) << "tests/data/opensubdiv is part of the repository";
  int tested = 0, refused = 0, skipped_loop = 0;
  for (const auto& path : files) {
    const std::string name = path.filename().string();
    PolygonSoup soup = read_soup(path);
    OsdParams p = cc(soup.face_indices.size() < 800 ? 3 : 2);
    p.boundary = boundary_of_tag(soup.boundary_interpolation);
    // geom has no bilinear scheme: those shapes' faces are refined with Catmull-Clark.
    if (name.rfind("loop_", 0) == 0) {
      bool triangles = true;
      for (std::size_t f = 0; f < soup.n_faces(); ++f) triangles &= soup.face(f).size() == 3;
      if (!triangles) {
        ++skipped_loop;
        continue;
      }
      p.scheme = SubdivisionScheme::kLoop;
    }
    std::ifstream text(path);
    std::stringstream all;
    all << text.rdbuf();
    if (all.str().find("creasemethod 0/0/1 chaikin") != std::string::npos)
      p.crease_method = CreaseMethod::kChaikin;
    if (expect_soup_matches_osd(soup, p, name)) ++tested;
    else ++refused;
  }
  std::cout << "regression shapes: " << tested << " matched, " << refused
            << " refused by OpenSubdiv, " << skipped_loop << " Loop shapes with non-triangles\n";
  EXPECT_GE(tested, 120);
}

}  // namespace
}  // namespace geom
