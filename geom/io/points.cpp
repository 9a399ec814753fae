#include <geom/io/points.h>
#include <geom/io/formats.h>
#include <geom/io/text.h>

#include <cmath>
#include <cstdio>

namespace geom {
namespace {

PointSet read_text_points(std::span<const std::byte> data, const std::string& name) {
  io_detail::TextCursor in(data, name);
  PointSet out;
  out.dimension = 0;
  while (!in.at_end()) {
    in.skip_blanks();
    if (in.at_eol()) {
      in.skip_line();
      continue;
    }
    double x[3];
    int n = 0;
    for (;;) {
      in.skip_blanks();
      if (in.at_eol()) break;
      if (n == 3) in.fail("more than 3 numbers on a point line");
      const char* p = in.pos();
      const char* q = io_detail::parse_double(p, in.end(), x[n]);
      if (!q || (q < in.end() && !io_detail::is_blank(*q) && *q != ',' && *q != '\n' && *q != '#'))
        in.bad_token("a number");
      if (!std::isfinite(x[n])) in.fail("coordinate is NaN or infinite");
      ++n;
      in.set_pos(q);
      in.skip_blanks();
      if (!in.at_end() && *in.pos() == ',') in.set_pos(in.pos() + 1);
    }
    if (n < 2) in.fail("a point needs 2 or 3 coordinates, found " + std::to_string(n));
    if (out.dimension == 0) out.dimension = n;
    if (n != out.dimension)
      in.fail("point with " + std::to_string(n) + " coordinates in a file of " + std::to_string(out.dimension) +
              "D points");
    out.points.emplace_back(x[0], x[1], n == 3 ? x[2] : 0.0);
    in.skip_line();
  }
  if (out.dimension == 0) out.dimension = 3;
  return out;
}

PointSet from_soup(PolygonSoup&& soup) {
  PointSet out;
  out.points = std::move(soup.positions);
  out.dimension = 3;
  return out;
}

}  // namespace

PointSet read_points(std::span<const std::byte> data, const std::string& name, std::optional<FileFormat> format) {
  if (!format) format = sniff_format(data);
  if (format) return from_soup(read_soup(data, *format, name));
  return read_text_points(data, name);
}

PointSet read_points(const std::filesystem::path& path) {
  std::optional<FileFormat> format;
  if (path != "-") {
    try {
      format = format_from_path(path);
    } catch (const InvalidArgument&) {
      // Not a mesh extension: sniff the content, else text.
    }
  }
  if (format) return from_soup(read_soup(path, ReadOptions{.format = format}));
  const io_detail::FileBytes file(path);
  return read_points(file.bytes(), io_detail::display_name(path));
}

}  // namespace geom
