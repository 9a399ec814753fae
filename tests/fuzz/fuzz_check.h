#pragma once
// The fuzz targets' one assertion: a failed check prints its file, line and condition before
// aborting, so a crash report says which rule broke, not only that one did. A macro because
// clang 14 with libstdc++ 12 has no std::source_location.

#include <cstdio>
#include <cstdlib>

namespace geom::fuzz {

[[noreturn, gnu::cold]] inline void check_failed(const char* file, int line, const char* condition) {
  std::fprintf(stderr, "%s:%d: fuzz check failed: %s\n", file, line, condition);
  std::abort();
}

}  // namespace geom::fuzz

#define FUZZ_CHECK(...) \
  ((__VA_ARGS__) ? void() : ::geom::fuzz::check_failed(__FILE__, __LINE__, #__VA_ARGS__))
