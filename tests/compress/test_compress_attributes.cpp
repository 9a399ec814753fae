// Normals and texture coordinates through the codec: bounds, order, flat decode, version
// handling and hostile attribute streams.

#include "compress/meshes.h"

#include <geom/compress/container/codec.h>
#include <geom/core/soup.h>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>

namespace geom {
namespace {

/// A torus (or grid) with a smooth normal field and UVs from the parameters (scaled so the
/// UV box is not the unit square), plus a few awkward normals: zero, down, along the axes.
SurfaceMesh with_attributes(const test::Arrays& a) {
  SurfaceMesh m = a.build();
  auto n = m.add_property<Vertex, Normal>(prop::kVertexNormal);
  auto t = m.add_property<Vertex, TexCoord>(prop::kVertexTexCoord);
  for (Vertex v : m.vertices()) {
    const Point& p = m.position(v);
    n[v] = Normal(std::sin(p.x()), std::cos(p.y()), std::sin(p.z() + p.x()));
    t[v] = TexCoord(0.3 + 2.0 * std::atan2(p.y(), p.x()), -1.0 + p.z() + 0.1 * p.x());
  }
  n[Vertex(0)] = Normal::Zero();
  n[Vertex(1)] = Normal(0, 0, -2);
  n[Vertex(2)] = Normal(1, 0, 0);
  n[Vertex(3)] = Normal(0, -1, 0);
  n[Vertex(4)] = Normal(1e-150, 0, -1e-150);
  return m;
}

double angle(const Normal& a, const Normal& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

void expect_attributes_round_trip(const SurfaceMesh& in, const CompressOptions& opt) {
  const CompressResult c = compress(in, opt);
  EXPECT_EQ(c.bytes[4], 2) << "a stream with attributes is version 2";
  EXPECT_GT(c.stats.normal_bytes, 0u);
  EXPECT_GT(c.stats.texcoord_bytes, 0u);
  std::size_t corners = 0;
  for (Face f : in.faces()) corners += in.valence(f);
  EXPECT_LE(c.bytes.size(), max_compressed_size(in.n_vertices(), in.n_faces(), corners, 2));
  const DecompressResult d = decompress(c.bytes);
  const auto n_in = in.get_property<Vertex, Normal>(prop::kVertexNormal);
  const auto t_in = in.get_property<Vertex, TexCoord>(prop::kVertexTexCoord);
  const auto n_out = d.mesh.get_property<Vertex, Normal>(prop::kVertexNormal);
  const auto t_out = d.mesh.get_property<Vertex, TexCoord>(prop::kVertexTexCoord);
  ASSERT_TRUE(n_out && t_out);
  EXPECT_DOUBLE_EQ(d.texcoord_max_error, c.stats.texcoord_max_error);
  const double angle_bound = 4.5 / std::ldexp(1.0, static_cast<int>(opt.normal_bits));
  const double uv_bound = c.stats.texcoord_max_error * (1 + 1e-9);
  for (std::uint32_t i = 0; i < d.mesh.n_vertices(); ++i) {
    const Vertex out(i), src(c.vertex_permutation[i]);
    ASSERT_NEAR(n_out[out].norm(), 1.0, 1e-12) << "vertex " << i;
    const Normal expect = n_in[src].norm() > 0 ? n_in[src].normalized() : Normal(0, 0, 1);
    ASSERT_LE(angle(n_out[out], expect), angle_bound) << "vertex " << i;
    ASSERT_LE((t_out[out] - t_in[src]).cwiseAbs().maxCoeff(), uv_bound) << "vertex " << i;
  }
  // The flat decoder returns the same attributes, per decoded vertex.
  const codec::FlatDecode f = codec::decompress_flat(c.bytes);
  ASSERT_EQ(f.normals.size(), 3 * d.mesh.n_vertices());
  ASSERT_EQ(f.texcoords.size(), 2 * d.mesh.n_vertices());
  if (!opt.preserve_order) {
    for (std::uint32_t i = 0; i < d.mesh.n_vertices(); ++i) {
      ASSERT_NEAR(f.normals[3 * i + 2], n_out[Vertex(i)].z(), 1e-6);
      ASSERT_NEAR(f.texcoords[2 * i], t_out[Vertex(i)].x(), 1e-5);
    }
  }
}

TEST(CompressAttributes, TorusRoundTripWithinBounds) {
  const SurfaceMesh m = with_attributes(test::torus(24, 16));
  expect_attributes_round_trip(m, {});
  expect_attributes_round_trip(m, {.level = 9, .normal_bits = 6, .texcoord_bits = 8});
  expect_attributes_round_trip(m, {.preserve_order = true, .normal_bits = 16, .texcoord_bits = 20});
}

TEST(CompressAttributes, QuadGridWithIsolatedVertexInOrder) {
  test::Arrays a = test::grid(7, 5, true);
  a.points.push_back(Point(9, 9, 9));  // isolated: coded after the connected vertices
  const SurfaceMesh m = with_attributes(a);
  expect_attributes_round_trip(m, {.preserve_order = true});
  expect_attributes_round_trip(m, {.level = 0});
}

TEST(CompressAttributes, DroppedOnRequestAndAbsentStaysVersionOne) {
  const SurfaceMesh m = with_attributes(test::torus(12, 8));
  const CompressResult c = compress(m, {.normal_bits = 0, .texcoord_bits = 0});
  EXPECT_EQ(c.bytes[4], 1);
  const DecompressResult d = decompress(c.bytes);
  EXPECT_FALSE((d.mesh.get_property<Vertex, Normal>(prop::kVertexNormal)));
  EXPECT_FALSE((d.mesh.get_property<Vertex, TexCoord>(prop::kVertexTexCoord)));
  // Without attributes the stream is byte-identical to one from a mesh that never had them.
  EXPECT_EQ(c.bytes, compress(test::torus(12, 8).build(), {}).bytes);
  // Normals only.
  const CompressResult n = compress(m, {.texcoord_bits = 0});
  EXPECT_EQ(n.bytes[4], 2);
  EXPECT_EQ(n.stats.texcoord_bytes, 0u);
  EXPECT_TRUE((decompress(n.bytes).mesh.get_property<Vertex, Normal>(prop::kVertexNormal)));
}

TEST(CompressAttributes, VersionOneRejectsAttributeFlagsAndTruncationsThrow) {
  CompressResult c = compress(test::torus(12, 8).build(), {});
  c.bytes[5] |= 8;  // NORMALS in a version-1 stream
  try {
    decompress(c.bytes);
    FAIL() << "accepted attribute flags in version 1";
  } catch (const DecodeError& e) {
    EXPECT_EQ(e.offset(), 5u);
    EXPECT_NE(std::string(e.what()).find("version 1"), std::string::npos) << e.what();
  }
  const CompressResult a = compress(with_attributes(test::torus(12, 8)), {});
  for (std::size_t len = 0; len < a.bytes.size(); ++len)
    EXPECT_THROW(decompress(std::span(a.bytes.data(), len)), DecodeError) << len;
  std::vector<std::uint8_t> bad = a.bytes;
  bad[40] = 1;  // normal bits 1
  EXPECT_THROW(decompress(bad), DecodeError);
}

TEST(CompressAttributes, InvalidAttributesThrowNamingTheVertex) {
  SurfaceMesh m = with_attributes(test::torus(12, 8));
  m.get_property<Vertex, Normal>(prop::kVertexNormal)[Vertex(7)] = Normal(NAN, 0, 1);
  try {
    compress(m, {});
    FAIL() << "accepted a NaN normal";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 7"), std::string::npos) << e.what();
  }
  EXPECT_THROW(compress(m, {.normal_bits = 1}), InvalidArgument);
  EXPECT_THROW(compress(m, {.normal_bits = 21}), InvalidArgument);
  EXPECT_THROW(compress(m, {.texcoord_bits = 31}), InvalidArgument);
  EXPECT_NO_THROW(compress(m, {.normal_bits = 0}));
}

}  // namespace
}  // namespace geom
