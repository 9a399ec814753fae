#pragma once
/// \file
/// Internal to geom/io: one reader and one writer per format, over bytes in memory. io.cpp
/// dispatches to these; `name` is the file name used in ParseError messages.

#include <geom/core/soup.h>
#include <geom/io/io.h>

#include <cstddef>
#include <cstring>
#include <filesystem>
#include <vector>
#include <span>
#include <string>

namespace geom::io_detail {

PolygonSoup read_obj(std::span<const std::byte> data, const std::string& name);
PolygonSoup read_ply(std::span<const std::byte> data, const std::string& name);
PolygonSoup read_off(std::span<const std::byte> data, const std::string& name);
PolygonSoup read_stl(std::span<const std::byte> data, const std::string& name);
PolygonSoup read_drc(std::span<const std::byte> data, const std::string& name);

void write_obj(const PolygonSoup& soup, const WriteOptions& options, std::string& out);
void write_ply(const PolygonSoup& soup, const WriteOptions& options, std::string& out);
void write_off(const PolygonSoup& soup, const WriteOptions& options, std::string& out);
void write_stl(const PolygonSoup& soup, const WriteOptions& options, std::string& out);
void write_drc(const PolygonSoup& soup, const WriteOptions& options, std::string& out);

/// A whole file in memory: mapped when it is a regular file, read in one loop otherwise
/// ("-" is stdin). Throws: Error when it cannot be opened or read.
class FileBytes {
 public:
  explicit FileBytes(const std::filesystem::path& path);
  FileBytes(const FileBytes&) = delete;
  FileBytes& operator=(const FileBytes&) = delete;
  ~FileBytes();
  std::span<const std::byte> bytes() const;

 private:
  void* map_ = nullptr;
  std::size_t size_ = 0;
  std::vector<std::byte> buffer_;
};

/// "<stdin>" for "-", else the path as given: the name used in messages.
std::string display_name(const std::filesystem::path& path);

/// A Draco bitstream before 2.0: its decoder sizes tables by unchecked header counts, so
/// neither .drc files nor KHR_draco_mesh_compression primitives of this kind are decoded.
inline bool is_legacy_draco(std::span<const std::byte> data) {
  return data.size() >= 7 && std::memcmp(data.data(), "DRACO", 5) == 0 && std::to_integer<int>(data[5]) < 2;
}

/// Writers' precondition: face indices in range and attribute arrays of the documented
/// lengths. Throws: InvalidArgument naming the first violation.
void check_writable(const PolygonSoup& soup);

}  // namespace geom::io_detail
