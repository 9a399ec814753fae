#pragma once
/// \file
/// Internal to geom/io: OBJ's named face sets ("o" objects, "g" groups, "usemtl" materials)
/// as a reader meets them, and as a writer puts them back. A statement sets the current name;
/// every face after it takes that name until the next one.

#include <geom/core/soup.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace geom::io_detail {

class FaceNameTrack {
 public:
  /// The name the following faces take (empty: none, as after a bare "g").
  void set(std::string_view name);
  /// One more face, taking the current name.
  void face();
  /// Append a later piece of the same file (read in parallel): its faces before its first
  /// statement take the name current at the end of this one.
  void append(const FaceNameTrack& later);
  /// One entry per face, or empty when the file named none.
  FaceNames finish() &&;

 private:
  std::uint32_t index(const std::string& name);

  std::vector<std::string> names_;
  std::unordered_map<std::string, std::uint32_t> index_;
  std::vector<std::uint32_t> of_face_;  // the faces from the first statement on
  std::size_t leading_ = 0;             // faces before the first statement
  bool named_ = false;                  // a statement was seen
  std::uint32_t current_ = FaceNames::kUnnamed;
};

/// Writes "<keyword> <name>" before face f when its name differs from face f − 1's (a bare
/// keyword when it has none). Nothing when `names` is empty.
void write_face_name(const FaceNames& names, const char* keyword, std::size_t f, std::string& out);

}  // namespace geom::io_detail
