#pragma once
// Where tests find real meshes: $GEOM_DATA_DIR, else the configured default
// (../shared/meshes beside the repository). Extended tests skip with a message when absent.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

namespace geom::test {

inline std::optional<std::filesystem::path> data_dir() {
  const char* env = std::getenv("GEOM_DATA_DIR");
  std::filesystem::path dir = env && *env ? env : GEOM_DEFAULT_DATA_DIR;
  std::error_code ec;
  if (std::filesystem::is_directory(dir, ec)) return dir;
  return std::nullopt;
}

/// The project's own small meshes (data/ in the repository).
inline std::filesystem::path project_data(const std::string& name) {
  return std::filesystem::path(GEOM_SOURCE_DIR) / "data" / name;
}

}  // namespace geom::test

/// Skip the current test with a message when the real-mesh directory is absent; otherwise
/// bind `dir` to it.
#define GEOM_REQUIRE_DATA_DIR(dir)                                                  \
  auto dir##_opt = ::geom::test::data_dir();                                        \
  if (!dir##_opt) GTEST_SKIP() << "GEOM_DATA_DIR not found; set it to the meshes"; \
  const std::filesystem::path dir = *dir##_opt
