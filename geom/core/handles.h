#pragma once
/// \file
/// Strongly typed 32-bit element handles. A `Vertex` compares only with a `Vertex`: mixing
/// kinds is a compile error, which catches a whole class of index bugs that pmp and OpenMesh
/// allow.

#include <compare>
#include <cstdint>
#include <functional>
#include <limits>
#include <ostream>

namespace geom {

template <class Tag>
class Handle {
 public:
  static constexpr std::uint32_t kInvalid = std::numeric_limits<std::uint32_t>::max();

  constexpr Handle() = default;
  constexpr explicit Handle(std::uint32_t index) : idx_(index) {}

  constexpr std::uint32_t idx() const { return idx_; }
  constexpr bool is_valid() const { return idx_ != kInvalid; }
  constexpr explicit operator bool() const { return is_valid(); }

  constexpr auto operator<=>(const Handle&) const = default;

 private:
  std::uint32_t idx_ = kInvalid;
};

struct VertexTag {};
struct HalfedgeTag {};
struct EdgeTag {};
struct FaceTag {};

using Vertex = Handle<VertexTag>;
using Halfedge = Handle<HalfedgeTag>;
using Edge = Handle<EdgeTag>;
using Face = Handle<FaceTag>;

/// Printable name of a handle kind, for messages ("vertex 12").
template <class H> constexpr const char* kind_name();
template <> constexpr const char* kind_name<Vertex>() { return "vertex"; }
template <> constexpr const char* kind_name<Halfedge>() { return "halfedge"; }
template <> constexpr const char* kind_name<Edge>() { return "edge"; }
template <> constexpr const char* kind_name<Face>() { return "face"; }

template <class Tag>
std::ostream& operator<<(std::ostream& os, Handle<Tag> h) {
  os << kind_name<Handle<Tag>>() << ' ';
  return h.is_valid() ? os << h.idx() : os << "<invalid>";
}

}  // namespace geom

template <class Tag>
struct std::hash<geom::Handle<Tag>> {
  std::size_t operator()(geom::Handle<Tag> h) const noexcept {
    return std::hash<std::uint32_t>{}(h.idx());
  }
};
