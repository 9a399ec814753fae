// KHR_draco_mesh_compression primitives through libdraco: the glTF names each attribute by
// Draco's unique id, and the decoded points are the primitive's vertices.

#include <geom/io/formats.h>
#include <geom/io/gltf_buffers.h>

#include <draco/compression/decode.h>
#include <draco/core/decoder_buffer.h>
#include <draco/mesh/mesh.h>

#include <cmath>
#include <cstring>
#include <new>

namespace geom::gltf_detail {

DracoPrimitive decode_draco(std::span<const std::byte> bytes, const std::vector<DracoAttribute>& wanted,
                            const Context& ctx, const std::string& where) {
  const std::string w = where + ".extensions.KHR_draco_mesh_compression";
  if (io_detail::is_legacy_draco(bytes))
    ctx.fail(w, "Draco bitstream before 2.0 (the extension requires 2.x)");
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::unique_ptr<draco::Mesh> mesh;
  try {
    auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
    if (!type.ok() || type.value() != draco::TRIANGULAR_MESH) ctx.fail(w, "not a Draco triangle mesh");
    draco::Decoder decoder;
    auto r = decoder.DecodeMeshFromBuffer(&buffer);
    if (!r.ok()) ctx.fail(w, "Draco decoding failed: " + r.status().error_msg_string());
    mesh = std::move(r).value();
  } catch (const std::bad_alloc&) {
    ctx.fail(w, "Draco's decoder ran out of memory: the stream declares more than memory holds");
  }
  DracoPrimitive out;
  out.points = mesh->num_points();
  out.triangles.reserve(3 * static_cast<std::size_t>(mesh->num_faces()));
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t p = mesh->face(f)[k].value();
      if (p >= out.points) ctx.fail(w, "face " + std::to_string(f.value()) + " names a missing point");
      out.triangles.push_back(p);
    }
  for (const DracoAttribute& a : wanted) {
    const draco::PointAttribute* att = mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(a.unique_id));
    if (!att) ctx.fail(w + ".attributes." + a.semantic, "Draco stream has no attribute " + std::to_string(a.unique_id));
    if (att->num_components() < a.components)
      ctx.fail(w + ".attributes." + a.semantic, "Draco attribute has " + std::to_string(att->num_components()) +
                                                    " components, expected " + std::to_string(a.components));
    out.semantics.push_back(a.semantic);
    std::vector<double>& values = out.attributes.emplace_back(out.points * a.components);
    for (draco::PointIndex p(0); p < mesh->num_points(); ++p) {
      double x[4] = {};
      att->ConvertValue<double>(att->mapped_index(p), static_cast<std::int8_t>(a.components), x);
      for (int c = 0; c < a.components; ++c) {
        if (!std::isfinite(x[c])) ctx.fail(w, a.semantic + " of point " + std::to_string(p.value()) + " is not finite");
        values[p.value() * a.components + c] = x[c];
      }
    }
  }
  return out;
}

}  // namespace geom::gltf_detail
