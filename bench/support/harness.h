#pragma once
// Tiny benchmark harness: min-of-N wall time, a printed table with ratios, CSV output.
// Peers run side by side in one process; ratios are what we read, since the machines are
// noisy and absolute times drift.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace geom::bench {

/// Smallest wall time of `repeats` runs of f, in seconds.
template <class F>
double time_min(F&& f, int repeats = 3) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < repeats; ++i) {
    auto t0 = std::chrono::steady_clock::now();
    f();
    auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
  }
  return best;
}

/// Smallest process CPU time of `repeats` runs of f, in seconds: for single-threaded work on
/// a loaded machine, where wall time mostly measures the other processes.
template <class F>
double cpu_time_min(F&& f, int repeats = 3) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < repeats; ++i) {
    const std::clock_t t0 = std::clock();
    f();
    best = std::min(best, static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC);
  }
  return best;
}

/// Smallest process CPU time and smallest wall time of `repeats` runs of f, in seconds: for
/// work that may use several cores, where CPU time alone hides the parallel gain.
struct CpuWall {
  double cpu, wall;
};
template <class F>
CpuWall cpu_wall_min(F&& f, int repeats = 3) {
  CpuWall best{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  for (int i = 0; i < repeats; ++i) {
    const std::clock_t c0 = std::clock();
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const auto t1 = std::chrono::steady_clock::now();
    best.cpu = std::min(best.cpu, static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    best.wall = std::min(best.wall, std::chrono::duration<double>(t1 - t0).count());
  }
  return best;
}

/// True (after printing usage) when the command line asks for help: a benchmark must not
/// take "--help" for an argument and start a run of minutes.
inline bool wants_help(int argc, char** argv, const char* usage) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::cout << usage << "\n";
      return true;
    }
  }
  return false;
}

inline std::string fmt(double v, int precision = 3) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

/// ours / peer, printed as "0.52x"; "n/a" when the peer did not run.
inline std::string ratio(double ours, double peer) {
  if (!(peer > 0)) return "n/a";
  return fmt(ours / peer, 3) + "x";
}

class Table {
 public:
  explicit Table(std::vector<std::string> columns) : columns_(std::move(columns)) {}
  void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  const std::vector<std::vector<std::string>>& rows() const { return rows_; }

  void print(std::ostream& os = std::cout) const {
    std::vector<std::size_t> width(columns_.size());
    for (std::size_t c = 0; c < columns_.size(); ++c) width[c] = columns_[c].size();
    for (const auto& r : rows_)
      for (std::size_t c = 0; c < r.size() && c < width.size(); ++c)
        width[c] = std::max(width[c], r[c].size());
    auto line = [&](const std::vector<std::string>& r) {
      for (std::size_t c = 0; c < columns_.size(); ++c) {
        std::string cell = c < r.size() ? r[c] : "";
        os << cell << std::string(width[c] - cell.size() + 2, ' ');
      }
      os << '\n';
    };
    line(columns_);
    for (const auto& r : rows_) line(r);
    os.flush();
  }

  /// Write the table as CSV (for bench/report's plots).
  void write_csv(const std::filesystem::path& path) const {
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    std::ofstream f(path);
    auto line = [&](const std::vector<std::string>& r) {
      for (std::size_t c = 0; c < r.size(); ++c) f << (c ? "," : "") << csv_field(r[c]);
      f << '\n';
    };
    line(columns_);
    for (const auto& r : rows_) line(r);
  }

  /// RFC 4180 quoting, because labels such as "geom (double, binned SAH)" hold commas.
  static std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    return q + "\"";
  }

 private:
  std::vector<std::string> columns_;
  std::vector<std::vector<std::string>> rows_;
};

/// $GEOM_DATA_DIR, else ../shared/meshes relative to the source tree; nullopt when absent.
inline std::optional<std::filesystem::path> data_dir() {
  const char* env = std::getenv("GEOM_DATA_DIR");
  std::filesystem::path dir = env && *env ? env : GEOM_BENCH_DEFAULT_DATA_DIR;
  std::error_code ec;
  if (std::filesystem::is_directory(dir, ec)) return dir;
  std::cerr << "note: GEOM_DATA_DIR not found (" << dir << "); real-mesh rows skipped\n";
  return std::nullopt;
}

/// Where benchmarks write CSV: $GEOM_BENCH_OUT, else bench-out/ in the working directory.
inline std::filesystem::path out_dir() {
  const char* env = std::getenv("GEOM_BENCH_OUT");
  return env && *env ? env : "bench-out";
}

}  // namespace geom::bench
