// Every malformed file in tests/corpus gets a ParseError naming the file and the line or
// byte offset: never a crash, a hang or an unbounded allocation.

#include <geom/io/io.h>
#include <geom/io/points.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>

using namespace geom;

namespace {

std::vector<std::filesystem::path> corpus_files() {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(GEOM_CORPUS_DIR))
    if (e.is_regular_file() && e.path().extension() != ".md") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(Corpus, HasFilesForEveryReader) {
  std::size_t obj = 0, ply = 0, off = 0, stl = 0;
  for (const auto& p : corpus_files()) {
    const auto ext = p.extension();
    obj += ext == ".obj";
    ply += ext == ".ply";
    off += ext == ".off";
    stl += ext == ".stl";
  }
  EXPECT_GE(obj, 5u);
  EXPECT_GE(ply, 5u);
  EXPECT_GE(off, 5u);
  EXPECT_GE(stl, 5u);
}

TEST(Corpus, EveryMalformedFileIsAParseErrorWithFileAndLocation) {
  const std::regex location(R"(:[0-9]+: |: byte [0-9]+: )");
  for (const auto& path : corpus_files()) {
    SCOPED_TRACE(path.filename().string());
    try {
      PolygonSoup s = read_soup(path);
      ADD_FAILURE() << "read without error: " << s.positions.size() << " vertices";
    } catch (const ParseError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path.filename().string()), std::string::npos) << msg;
      EXPECT_TRUE(std::regex_search(msg, location)) << msg;
      EXPECT_NE(e.unit(), ParseError::Unit::kNone) << msg;
    }
  }
}

TEST(Corpus, PointReaderRejectsMalformedMeshFilesToo) {
  for (const auto& path : corpus_files()) {
    SCOPED_TRACE(path.filename().string());
    EXPECT_THROW(read_points(path), ParseError);
  }
}
