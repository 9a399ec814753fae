// Draco (.drc) through the Draco library. Reading keeps Draco's position values as the
// vertices (so attribute seams do not split the topology) and turns normals and texture
// coordinates into per-corner values, plus per-vertex ones when every vertex's corners
// agree. Writing stores float32 positions (bit-exact for float input when
// drc_position_bits = 0, quantised otherwise), fans polygons into triangles, and carries
// vertex normals and texture coordinates.

#include <geom/io/formats.h>

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/core/decoder_buffer.h>
#include <draco/core/encoder_buffer.h>
#include <draco/mesh/mesh.h>
#include <draco/point_cloud/point_cloud.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <new>

namespace geom::io_detail {
namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw ParseError(name, ParseError::Unit::kByte, 0, what);
}

template <class T>
void corner_attribute(const draco::PointAttribute* att, const std::vector<draco::PointIndex>& corner_points,
                      const std::vector<std::uint32_t>& corner_vertex, std::size_t nv, std::vector<T>& corners,
                      std::vector<T>& per_vertex) {
  constexpr int kDims = T::SizeAtCompileTime;
  if (!att || att->num_components() < kDims) return;
  corners.resize(corner_points.size());
  std::vector<std::int64_t> value_of(nv, -1);
  bool consistent = true;
  for (std::size_t c = 0; c < corner_points.size(); ++c) {
    const draco::AttributeValueIndex vi = att->mapped_index(corner_points[c]);
    double x[4] = {};
    att->ConvertValue<double>(vi, static_cast<std::int8_t>(kDims), x);
    for (int k = 0; k < kDims; ++k) corners[c][k] = x[k];
    std::int64_t& seen = value_of[corner_vertex[c]];
    if (seen < 0) seen = vi.value();
    else if (seen != vi.value()) consistent = false;
  }
  if (!consistent) return;
  per_vertex.assign(nv, T::Zero());
  for (std::size_t c = 0; c < corner_points.size(); ++c) per_vertex[corner_vertex[c]] = corners[c];
}

/// Decodes a mesh or point cloud; `mesh` is set when it is a mesh (the same object).
std::unique_ptr<draco::PointCloud> decode_geometry(draco::DecoderBuffer& buffer,
                                                   draco::EncodedGeometryType type,
                                                   const std::string& name, const draco::Mesh*& mesh) {
  draco::Decoder decoder;
  if (type == draco::TRIANGULAR_MESH) {
    auto r = decoder.DecodeMeshFromBuffer(&buffer);
    if (!r.ok()) fail(name, "Draco mesh decoding failed: " + r.status().error_msg_string());
    std::unique_ptr<draco::Mesh> m = std::move(r).value();
    mesh = m.get();
    return m;
  }
  if (type == draco::POINT_CLOUD) {
    auto r = decoder.DecodePointCloudFromBuffer(&buffer);
    if (!r.ok()) fail(name, "Draco point cloud decoding failed: " + r.status().error_msg_string());
    return std::move(r).value();
  }
  fail(name, "unsupported Draco geometry type");
}

}  // namespace

PolygonSoup read_drc(std::span<const std::byte> data, const std::string& name) {
  // Draco's decoder for the 2017 pre-release bitstreams (1.x) sizes its tables by header
  // counts it never checks: a crafted 136-byte file took 12 GB and 20-50 s to be refused
  // (found by fuzz_points). Bitstreams from 2.0 on (every Draco release since 1.0, and the
  // only ones KHR_draco_mesh_compression allows) are checked by Draco itself, except against
  // the memory their counts ask for (below).
  if (is_legacy_draco(data))
    fail(name, "Draco bitstream " + std::to_string(std::to_integer<int>(data[5])) + "." +
                   std::to_string(std::to_integer<int>(data[6])) +
                   " (before 2.0) is not read: its decoder trusts unchecked sizes; re-encode the "
                   "file with a current Draco encoder");
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(data.data()), data.size());
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok()) fail(name, "not a Draco file: " + type.status().error_msg_string());
  std::unique_ptr<draco::PointCloud> cloud;
  const draco::Mesh* mesh = nullptr;
  try {
    cloud = decode_geometry(buffer, type.value(), name, mesh);
  } catch (const std::bad_alloc&) {
    // 2.x streams are checked, but not against the memory their counts ask for: a 240-byte
    // point cloud declaring 16.8M points took 3.7 GB and 8 s to be refused (fuzz_compgeom).
    fail(name, "Draco's decoder ran out of memory: the file declares more points or faces "
               "than memory holds (Draco sizes its tables from the header before reading data)");
  }
  const draco::PointAttribute* pos = cloud->GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (!pos || pos->num_components() < 3) fail(name, "Draco file has no 3D position attribute");
  PolygonSoup soup;
  const std::size_t nv = pos->size();
  soup.positions.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    double x[3];
    pos->ConvertValue<double>(draco::AttributeValueIndex(static_cast<std::uint32_t>(v)), 3, x);
    soup.positions[v] = Point(x[0], x[1], x[2]);
    if (!soup.positions[v].allFinite()) fail(name, "vertex " + std::to_string(v) + " is NaN or infinite");
  }
  std::vector<draco::PointIndex> corner_points;
  if (mesh) {
    const std::size_t nf = mesh->num_faces();
    corner_points.reserve(3 * nf);
    soup.face_offsets.reserve(nf + 1);
    soup.face_indices.reserve(3 * nf);
    soup.face_offsets.push_back(0);
    for (std::uint32_t f = 0; f < nf; ++f) {
      const draco::Mesh::Face& face = mesh->face(draco::FaceIndex(f));
      for (int k = 0; k < 3; ++k) {
        if (face[k].value() >= cloud->num_points()) fail(name, "face " + std::to_string(f) + " names a missing point");
        const std::uint32_t v = pos->mapped_index(face[k]).value();
        if (v >= nv) fail(name, "face " + std::to_string(f) + " names a missing position");
        soup.face_indices.push_back(v);
        corner_points.push_back(face[k]);
      }
      soup.face_offsets.push_back(static_cast<std::uint32_t>(soup.face_indices.size()));
    }
    if (nf == 0) soup.face_offsets.clear();
  }
  corner_attribute(cloud->GetNamedAttribute(draco::GeometryAttribute::NORMAL), corner_points, soup.face_indices, nv,
                   soup.corner_normals, soup.vertex_normals);
  corner_attribute(cloud->GetNamedAttribute(draco::GeometryAttribute::TEX_COORD), corner_points, soup.face_indices,
                   nv, soup.corner_texcoords, soup.vertex_texcoords);
  if (!mesh) {
    // A point cloud: attributes are per point; with identity mapping they are per vertex.
    for (auto [type_id, dims] : {std::pair{draco::GeometryAttribute::NORMAL, 3}, {draco::GeometryAttribute::TEX_COORD, 2}}) {
      const draco::PointAttribute* att = cloud->GetNamedAttribute(type_id);
      if (!att || att->num_components() < dims || cloud->num_points() != nv) continue;
      for (std::uint32_t p = 0; p < nv; ++p) {
        double x[3] = {};
        att->ConvertValue<double>(att->mapped_index(draco::PointIndex(p)), static_cast<std::int8_t>(dims), x);
        if (dims == 3) soup.vertex_normals.emplace_back(x[0], x[1], x[2]);
        else soup.vertex_texcoords.emplace_back(x[0], x[1]);
      }
    }
  }
  return soup;
}

namespace {

// The vertices a Draco file of the soup holds, ascending: all of a point cloud's, else those
// some face uses.
std::vector<std::uint32_t> used_vertices(const PolygonSoup& soup) {
  std::vector<std::uint32_t> kept;
  std::vector<bool> used(soup.positions.size(), soup.n_faces() == 0);
  for (std::uint32_t v : soup.face_indices) used[v] = true;
  for (std::uint32_t v = 0; v < used.size(); ++v)
    if (used[v]) kept.push_back(v);
  return kept;
}

}  // namespace

void write_drc(const PolygonSoup& soup, const WriteOptions& options, std::string& out) {
  if (options.drc_position_bits < 0 || options.drc_position_bits > 30)
    throw InvalidArgument("drc_position_bits must be 0 (lossless) to 30, got " +
                          std::to_string(options.drc_position_bits));
  if (options.drc_level < 0 || options.drc_level > 10)
    throw InvalidArgument("drc_level must be 0 to 10, got " + std::to_string(options.drc_level));
  if (soup.positions.size() > std::numeric_limits<std::uint32_t>::max() / 2)
    throw InvalidArgument("too many vertices for Draco");
  // A mesh keeps only the vertices its faces use, in their order: Draco's Edgebreaker coder
  // drops the others, and its sequential decoder refuses a mesh with more points than three
  // per triangle (a lossless file with one isolated vertex beside a triangle did not decode).
  // A point cloud (no faces) keeps every point.
  const std::vector<std::uint32_t> kept = used_vertices(soup);
  const std::size_t nv = kept.size();
  draco::Mesh mesh;
  mesh.set_num_points(static_cast<std::uint32_t>(nv));
  auto add = [&](draco::GeometryAttribute::Type type, int dims, auto value_of) {
    draco::GeometryAttribute ga;
    ga.Init(type, nullptr, static_cast<std::uint8_t>(dims), draco::DT_FLOAT32, false, sizeof(float) * dims, 0);
    const int id = mesh.AddAttribute(ga, true, static_cast<std::uint32_t>(nv));
    draco::PointAttribute* att = mesh.attribute(id);
    for (std::uint32_t v = 0; v < nv; ++v) {
      float x[3];
      for (int k = 0; k < dims; ++k) x[k] = static_cast<float>(value_of(kept[v], k));
      att->SetAttributeValue(draco::AttributeValueIndex(v), x);
    }
  };
  add(draco::GeometryAttribute::POSITION, 3, [&](std::uint32_t v, int k) { return soup.positions[v][k]; });
  if (options.attributes && !soup.vertex_normals.empty())
    add(draco::GeometryAttribute::NORMAL, 3, [&](std::uint32_t v, int k) { return soup.vertex_normals[v][k]; });
  if (options.attributes && !soup.vertex_texcoords.empty())
    add(draco::GeometryAttribute::TEX_COORD, 2, [&](std::uint32_t v, int k) { return soup.vertex_texcoords[v][k]; });
  std::vector<std::uint32_t> index(soup.positions.size(), 0);
  for (std::uint32_t v = 0; v < nv; ++v) index[kept[v]] = v;
  for (std::size_t f = 0; f < soup.n_faces(); ++f) {
    const auto face = soup.face(f);
    for (std::size_t k = 2; k < face.size(); ++k)
      mesh.AddFace({draco::PointIndex(index[face[0]]), draco::PointIndex(index[face[k - 1]]),
                    draco::PointIndex(index[face[k]])});
  }
  draco::Encoder encoder;
  const int speed = 10 - options.drc_level;
  encoder.SetSpeedOptions(speed, speed);
  if (options.drc_position_bits > 0) {
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, options.drc_position_bits);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
  } else {
    // Without quantisation only the sequential coder keeps float values exact.
    encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
  }
  draco::EncoderBuffer buffer;
  const draco::Status status = mesh.num_faces() > 0 ? encoder.EncodeMeshToBuffer(mesh, &buffer)
                                                    : encoder.EncodePointCloudToBuffer(mesh, &buffer);
  if (!status.ok()) throw Error("Draco encoding failed: " + status.error_msg_string());
  out.assign(buffer.data(), buffer.size());
}

}  // namespace geom::io_detail
