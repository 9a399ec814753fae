#include <geom/io/formats.h>
#include <geom/io/gltf.h>
#include <geom/io/io.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string_view>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace geom {
namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::optional<FileFormat> format_from_extension(const std::filesystem::path& path) {
  const std::string ext = lower(path.extension().string());
  if (ext == ".obj") return FileFormat::kObj;
  if (ext == ".ply") return FileFormat::kPly;
  if (ext == ".off") return FileFormat::kOff;
  if (ext == ".stl") return FileFormat::kStl;
  if (ext == ".drc") return FileFormat::kDrc;
  if (ext == ".gltf") return FileFormat::kGltf;
  if (ext == ".glb") return FileFormat::kGlb;
  return std::nullopt;
}

void write_all(const std::filesystem::path& path, std::string_view bytes) {
  const bool is_stdout = path == "-";
  std::FILE* f = is_stdout ? stdout : std::fopen(path.c_str(), "wb");
  if (!f) throw Error("cannot open '" + path.string() + "' for writing: " + std::strerror(errno));
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const bool flushed = std::fflush(f) == 0;
  if (!is_stdout) std::fclose(f);
  if (!ok || !flushed) throw Error("cannot write '" + path.string() + "': " + std::strerror(errno));
}

bool starts_with(std::span<const std::byte> head, std::string_view s) {
  return head.size() >= s.size() && std::memcmp(head.data(), s.data(), s.size()) == 0;
}

std::string dispatch_write(const PolygonSoup& soup, FileFormat format, const WriteOptions& options) {
  io_detail::check_writable(soup);
  std::string out;
  switch (format) {
    case FileFormat::kObj: io_detail::write_obj(soup, options, out); break;
    case FileFormat::kPly: io_detail::write_ply(soup, options, out); break;
    case FileFormat::kOff: io_detail::write_off(soup, options, out); break;
    case FileFormat::kStl: io_detail::write_stl(soup, options, out); break;
    case FileFormat::kDrc: io_detail::write_drc(soup, options, out); break;
    case FileFormat::kGltf: out = write_gltf(gltf_from_soup(soup), false); break;
    case FileFormat::kGlb: out = write_gltf(gltf_from_soup(soup), true); break;
  }
  return out;
}

}  // namespace

namespace io_detail {

std::string display_name(const std::filesystem::path& path) {
  return path == "-" ? std::string("<stdin>") : path.string();
}

FileBytes::FileBytes(const std::filesystem::path& path) {
  const bool is_stdin = path == "-";
  const int fd = is_stdin ? STDIN_FILENO : ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw Error("cannot open '" + path.string() + "': " + std::strerror(errno));
  struct stat st {};
  if (!is_stdin && ::fstat(fd, &st) == 0) {
    if (S_ISDIR(st.st_mode)) {
      ::close(fd);
      throw Error("cannot read '" + path.string() + "': it is a directory");
    }
    if (S_ISREG(st.st_mode) && st.st_size > 0) {
      void* p = ::mmap(nullptr, static_cast<std::size_t>(st.st_size), PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
      if (p != MAP_FAILED) {
        ::close(fd);
        map_ = p;
        size_ = static_cast<std::size_t>(st.st_size);
        return;
      }
    }
  }
  std::size_t used = 0;
  buffer_.resize(65536);
  for (;;) {
    if (used == buffer_.size()) buffer_.resize(2 * buffer_.size());
    const ssize_t n = ::read(fd, buffer_.data() + used, buffer_.size() - used);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      if (!is_stdin) ::close(fd);
      throw Error("cannot read '" + display_name(path) + "': " + std::strerror(err));
    }
    if (n == 0) break;
    used += static_cast<std::size_t>(n);
  }
  if (!is_stdin) ::close(fd);
  buffer_.resize(used);
  size_ = used;
}

FileBytes::~FileBytes() {
  if (map_) ::munmap(map_, size_);
}

std::span<const std::byte> FileBytes::bytes() const {
  return map_ ? std::span<const std::byte>(static_cast<const std::byte*>(map_), size_)
              : std::span<const std::byte>(buffer_.data(), size_);
}

void check_writable(const PolygonSoup& soup) {
  const std::size_t v = soup.positions.size();
  const std::size_t c = soup.face_indices.size();
  const std::size_t f = soup.n_faces();
  if (!soup.face_offsets.empty()) {
    if (soup.face_offsets.front() != 0 || soup.face_offsets.back() != c)
      throw InvalidArgument("soup face_offsets must start at 0 and end at the corner count");
    for (std::size_t i = 0; i + 1 < soup.face_offsets.size(); ++i)
      if (soup.face_offsets[i] > soup.face_offsets[i + 1])
        throw InvalidArgument("soup face_offsets decrease at face " + std::to_string(i));
  } else if (c != 0) {
    throw InvalidArgument("soup has face indices but no face_offsets");
  }
  for (std::size_t i = 0; i < c; ++i)
    if (soup.face_indices[i] >= v)
      throw InvalidArgument("face index " + std::to_string(soup.face_indices[i]) +
                            " out of range (" + std::to_string(v) + " vertices)");
  auto check = [](std::size_t n, std::size_t want, const char* what) {
    if (n != 0 && n != want)
      throw InvalidArgument(std::string("soup ") + what + " has " + std::to_string(n) +
                            " entries, expected 0 or " + std::to_string(want));
  };
  check(soup.vertex_normals.size(), v, "vertex_normals");
  check(soup.vertex_colors.size(), v, "vertex_colors");
  check(soup.vertex_texcoords.size(), v, "vertex_texcoords");
  check(soup.corner_texcoords.size(), c, "corner_texcoords");
  check(soup.corner_normals.size(), c, "corner_normals");
  for (const auto& s : soup.vertex_scalars) check(s.values.size(), v, "vertex scalar");
  for (const auto& s : soup.face_scalars) check(s.values.size(), f, "face scalar");
  for (const auto& e : soup.creases)
    if (e.a >= v || e.b >= v) throw InvalidArgument("crease vertex out of range");
  for (const auto& e : soup.corners)
    if (e.v >= v) throw InvalidArgument("corner tag vertex out of range");
}

}  // namespace io_detail

const char* format_name(FileFormat format) {
  switch (format) {
    case FileFormat::kObj: return "obj";
    case FileFormat::kPly: return "ply";
    case FileFormat::kOff: return "off";
    case FileFormat::kStl: return "stl";
    case FileFormat::kDrc: return "drc";
    case FileFormat::kGltf: return "gltf";
    case FileFormat::kGlb: return "glb";
  }
  return "unknown";
}

FileFormat format_from_path(const std::filesystem::path& path) {
  if (auto f = format_from_extension(path)) return *f;
  const std::string ext = path.extension().string();
  throw InvalidArgument("unknown mesh file extension '" + ext + "' in '" + path.string() +
                        "' (expected .obj, .ply, .off, .stl, .drc, .gltf or .glb)");
}

std::optional<FileFormat> sniff_format(std::span<const std::byte> head) {
  if (starts_with(head, "ply\n") || starts_with(head, "ply\r")) return FileFormat::kPly;
  if (starts_with(head, "DRACO")) return FileFormat::kDrc;
  if (starts_with(head, "glTF")) return FileFormat::kGlb;
  // Binary STL: 80-byte header and a triangle count that matches the size exactly (only
  // decisive when `head` is the whole file, which is how read_soup calls it).
  if (head.size() >= 84) {
    std::uint32_t n;
    std::memcpy(&n, head.data() + 80, 4);
    if (head.size() == 84 + 50ull * n) return FileFormat::kStl;
  }
  std::size_t i = 0;
  const auto* c = reinterpret_cast<const char*>(head.data());
  while (i < head.size() && std::isspace(static_cast<unsigned char>(c[i]))) ++i;
  std::string_view rest(c + i, head.size() - i);
  if (rest.starts_with("solid")) return FileFormat::kStl;
  if (rest.starts_with("{") && rest.find("\"asset\"") != std::string_view::npos) return FileFormat::kGltf;
  {
    std::size_t k = 0;
    if (rest.starts_with("ST")) k = 2;
    while (k < rest.size() && k < 6 && (rest[k] == 'C' || rest[k] == 'N' || rest[k] == '4')) ++k;
    if (rest.substr(k).starts_with("OFF")) return FileFormat::kOff;
  }
  // OBJ: the first non-comment line starts with a known keyword.
  while (!rest.empty()) {
    std::size_t nl = rest.find('\n');
    std::string_view line = rest.substr(0, nl);
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    if (!line.empty() && line.front() != '#' && line.front() != '\r') {
      for (std::string_view kw : {"v ", "vn ", "vt ", "f ", "o ", "g ", "s ", "mtllib ", "usemtl ",
                                  "v\t", "f\t"})
        if (line.starts_with(kw)) return FileFormat::kObj;
      return std::nullopt;
    }
    if (nl == std::string_view::npos) break;
    rest.remove_prefix(nl + 1);
  }
  return std::nullopt;
}

namespace {

PolygonSoup read_any(std::span<const std::byte> data, FileFormat format, const std::string& name) {
  switch (format) {
    case FileFormat::kObj: return io_detail::read_obj(data, name);
    case FileFormat::kPly: return io_detail::read_ply(data, name);
    case FileFormat::kOff: return io_detail::read_off(data, name);
    case FileFormat::kStl: return io_detail::read_stl(data, name);
    case FileFormat::kDrc: return io_detail::read_drc(data, name);
    case FileFormat::kGltf:
    case FileFormat::kGlb: return flatten(read_gltf(data, name));
  }
  throw InvalidArgument("unknown file format");
}

PolygonSoup read_file(const std::filesystem::path& path, const ReadOptions& options) {
  std::optional<FileFormat> format = options.format;
  if (!format && path == "-")
    throw InvalidArgument("reading from stdin ('-') needs an explicit format");
  if (!format) format = format_from_extension(path);
  const io_detail::FileBytes file(path);
  const std::span<const std::byte> data = file.bytes();
  if (!format) format = sniff_format(data);
  if (!format)
    throw InvalidArgument("cannot tell the format of '" + path.string() +
                          "' from its extension or content (expected OBJ, PLY, OFF, STL, DRC or glTF)");
  // glTF may keep its buffers in files beside it.
  if (*format == FileFormat::kGltf || *format == FileFormat::kGlb) {
    // "Duck.gltf" has no parent path; its buffers are in the current folder.
    const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    return flatten(read_gltf(data, io_detail::display_name(path), path == "-" ? std::filesystem::path() : folder));
  }
  return read_any(data, *format, io_detail::display_name(path));
}

// A file of no vertex and no face is a wrong file (a text file named .obj, a glTF without
// meshes), and reading it as an empty mesh would let info, convert and batch report "ok".
PolygonSoup require_geometry(PolygonSoup soup, const std::string& name) {
  if (!soup.positions.empty() || soup.n_faces() > 0) return soup;
  std::string why;  // what the reader skipped may be all there was (a glTF of lines)
  for (const std::string& w : soup.warnings) why += "; " + w;
  throw ParseError(name, ParseError::Unit::kNone, 0, "no geometry: the file holds no vertex and no face" + why);
}

}  // namespace

PolygonSoup read_soup(std::span<const std::byte> data, FileFormat format, const std::string& name) {
  return require_geometry(read_any(data, format, name), name);
}

PolygonSoup read_soup(const std::filesystem::path& path, const ReadOptions& options) {
  return require_geometry(read_file(path, options), io_detail::display_name(path));
}

std::vector<std::byte> write_soup(const PolygonSoup& soup, FileFormat format,
                                  const WriteOptions& options) {
  std::string bytes = dispatch_write(soup, format, options);
  std::vector<std::byte> out(bytes.size());
  if (!bytes.empty()) std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

void write_soup(const PolygonSoup& soup, const std::filesystem::path& path,
                const WriteOptions& options) {
  std::optional<FileFormat> format = options.format;
  if (!format && path == "-")
    throw InvalidArgument("writing to stdout ('-') needs an explicit format");
  if (!format) format = format_from_path(path);
  write_all(path, dispatch_write(soup, *format, options));
}

LoadResult load_mesh(const std::filesystem::path& path, const ReadOptions& read,
                     const BuildOptions& options) {
  PolygonSoup soup = read_soup(path, read);
  BuildResult r = build(soup, options);
  return {std::move(r.mesh), std::move(r.report), std::move(soup.warnings),
          std::move(soup.material_libraries)};
}

void save_mesh(const SurfaceMesh& mesh, const std::filesystem::path& path,
               const WriteOptions& options) {
  PolygonSoup soup = to_soup(mesh);
  if (!soup.face_materials.empty() && soup.material_libraries.empty())
    soup.material_libraries = options.material_libraries;
  write_soup(soup, path, options);
}

}  // namespace geom
