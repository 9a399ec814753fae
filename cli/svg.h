#pragma once
/// \file
/// A minimal SVG writer for 2D results (Delaunay triangles, Voronoi cells, hulls): polygons
/// and points in a viewBox fitted to the data, y pointing up.

#include <Eigen/Core>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <geom/core/errors.h>

#include "common.h"

namespace geom::cli {

class Svg {
 public:
  void polygon(const std::vector<Eigen::Vector2d>& poly, const std::string& style) {
    if (poly.empty()) return;
    for (const auto& p : poly) grow(p);
    shapes_.push_back({poly, style, false});
  }
  void points(const std::vector<Eigen::Vector2d>& pts, const std::string& fill) {
    for (const auto& p : pts) grow(p);
    dots_.insert(dots_.end(), pts.begin(), pts.end());
    dot_fill_ = fill;
  }
  /// Writes to `path` ("-" is stdout). Throws Error when the file cannot be written.
  void write(const std::string& path) const {
    double w = std::max(hi_.x() - lo_.x(), 1e-300), h = std::max(hi_.y() - lo_.y(), 1e-300);
    double s = 1000.0 / std::max(w, h);  // draw in a 1000-unit frame: SVG viewers dislike 1e-12
    auto X = [&](const Eigen::Vector2d& p) { return (p.x() - lo_.x()) * s; };
    auto Y = [&](const Eigen::Vector2d& p) { return (hi_.y() - p.y()) * s; };
    std::ostringstream o;
    o.precision(10);
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"-10 -10 " << w * s + 20 << ' '
      << h * s + 20 << "\">\n";
    for (const auto& sh : shapes_) {
      o << "<polygon points=\"";
      for (const auto& p : sh.poly) o << X(p) << ',' << Y(p) << ' ';
      o << "\" style=\"" << sh.style << "\"/>\n";
    }
    for (const auto& p : dots_)
      o << "<circle cx=\"" << X(p) << "\" cy=\"" << Y(p) << "\" r=\"2\" fill=\"" << dot_fill_
        << "\"/>\n";
    o << "</svg>\n";
    if (path == "-") {
      std::cout << o.str();
      return;
    }
    std::ofstream f(path, std::ios::binary);
    f << o.str();
    if (!f) throw Error("cannot write '" + path + "'");
  }

 private:
  struct Shape {
    std::vector<Eigen::Vector2d> poly;
    std::string style;
    bool closed;
  };
  void grow(const Eigen::Vector2d& p) {
    lo_ = lo_.cwiseMin(p);
    hi_ = hi_.cwiseMax(p);
  }
  Eigen::Vector2d lo_{std::numeric_limits<double>::infinity(),
                      std::numeric_limits<double>::infinity()};
  Eigen::Vector2d hi_{-std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity()};
  std::vector<Shape> shapes_;
  std::vector<Eigen::Vector2d> dots_;
  std::string dot_fill_ = "black";
};

/// For the commands that write SVG or a mesh by the output's name: refuses any other name
/// before the work is done. Empty (no output) and "-" are left to the command.
inline void require_svg_or_mesh_output(const std::string& path) {
  if (!path.empty() && path != "-")
    require_extension(path, {".svg", ".obj", ".ply", ".off", ".stl", ".drc", ".gltf", ".glb"},
                      "-o/--output");
}

/// True when `path` ends in .svg (case-insensitive).
inline bool is_svg(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".svg";
}

}  // namespace geom::cli
