#include <geom/batch/batch.h>
#include <geom/compress/container/codec.h>
#include <geom/core/errors.h>
#include <geom/core/validate.h>
#include <geom/io/io.h>

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <unistd.h>

namespace geom::batch {
namespace {
namespace fs = std::filesystem;

// An n×n grid of quads in the plane z = 0: (n+1)² vertices, n² faces, one boundary loop.
PolygonSoup grid(std::uint32_t n) {
  PolygonSoup s;
  for (std::uint32_t y = 0; y <= n; ++y)
    for (std::uint32_t x = 0; x <= n; ++x) s.positions.emplace_back(x, y, 0.0);
  for (std::uint32_t y = 0; y < n; ++y)
    for (std::uint32_t x = 0; x < n; ++x) {
      const std::uint32_t a = y * (n + 1) + x;
      const std::uint32_t q[4] = {a, a + 1, a + n + 2, a + n + 1};
      s.add_face(q);
    }
  return s;
}

// Three triangles on the edge 0-1: a non-manifold edge.
PolygonSoup fin() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  const std::uint32_t f[3][3] = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  for (const auto& t : f) s.add_face(t);
  return s;
}

class Batch : public ::testing::Test {
 protected:
  void SetUp() override {
    root = fs::temp_directory_path() /
           ("geom_batch_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
            "_" + std::to_string(::getpid()));
    fs::remove_all(root);
    in = root / "in";
    out = root / "out";
    fs::create_directories(in / "sub");
    write_soup(grid(4), in / "a.obj");
    write_soup(grid(6), in / "sub" / "b.ply");
    write_soup(fin(), in / "fin.off");
    std::ofstream(in / "broken.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
    std::ofstream(in / "notes.txt") << "not a mesh\n";
    std::ofstream(in / ".hidden.obj") << "v 0 0 0\n";
  }
  void TearDown() override { fs::remove_all(root); }

  std::vector<Task> tasks(const Pipeline& p) { return plan(p, in, find_meshes(in, out), out); }

  fs::path root, in, out;
};

TEST_F(Batch, FindsMeshesByExtensionSkippingHiddenFilesAndTheOutputFolder) {
  fs::create_directories(out);
  write_soup(grid(1), out / "old.obj");
  const auto found = find_meshes(in, out);
  ASSERT_EQ(found.size(), 4u);
  EXPECT_EQ(found[0].filename(), "a.obj");
  EXPECT_EQ(found[1].filename(), "broken.obj");
  EXPECT_EQ(found[2].filename(), "fin.off");
  EXPECT_EQ(found[3].filename(), "b.ply");
  EXPECT_THROW(find_meshes(in / "missing"), Error);
}

TEST_F(Batch, PlanKeepsRelativePathsAndSeparatesCollidingOutputs) {
  write_soup(grid(2), in / "a.ply");
  const auto t = tasks(parse_steps({"convert --format stl"}));
  ASSERT_EQ(t.size(), 5u);
  EXPECT_EQ(t[0].output_name, "a.obj.stl");
  EXPECT_EQ(t[1].output_name, "a.ply.stl");
  EXPECT_EQ(t[4].input_name, "sub/b.ply");
  EXPECT_EQ(t[4].output_name, "sub/b.stl");
  EXPECT_THROW(plan(parse_steps({"repair"}), in, find_meshes(in), in), InvalidArgument);
}

TEST_F(Batch, AnInputThatIsASymbolicLinkKeepsItsPlaceInTheTree) {
  fs::create_directories(root / "elsewhere");
  write_soup(grid(2), root / "elsewhere" / "x.obj");
  fs::create_symlink(root / "elsewhere" / "x.obj", in / "sub" / "linked.obj");
  const Pipeline p = parse_steps({"simplify --ratio 0.5"});
  const auto t = tasks(p);
  const auto it = std::find_if(t.begin(), t.end(), [](auto& x) { return x.input_name == "sub/linked.obj"; });
  ASSERT_NE(it, t.end());
  EXPECT_EQ(process(p, *it).status, "ok");
  EXPECT_TRUE(fs::is_regular_file(out / "sub" / "linked.obj"));
  EXPECT_FALSE(fs::is_symlink(out / "sub" / "linked.obj"));
}

TEST_F(Batch, ProcessesGoodFilesAndRecordsBadOnesWithTheirMessage) {
  const Pipeline p = parse_steps({"repair", "subdivide --levels 1", "simplify --ratio 0.5"});
  const auto t = tasks(p);
  std::vector<Record> records;
  const Summary s = run(p, t, {.jobs = 2}, [&](const Record& r) { records.push_back(r); });
  EXPECT_EQ(s.total, 4u);
  EXPECT_EQ(s.ok, 3u);
  EXPECT_EQ(s.failed, 1u);
  EXPECT_FALSE(s.interrupted);
  ASSERT_EQ(records.size(), 4u);
  for (const Record& r : records) {
    if (r.input == "broken.obj") {
      EXPECT_EQ(r.status, "failed");
      EXPECT_NE(r.error.find("broken.obj:3"), std::string::npos) << r.error;
      continue;
    }
    ASSERT_EQ(r.status, "ok") << r.input << ": " << r.error;
    const LoadResult back = load_mesh(out / r.output);
    EXPECT_TRUE(validate(back.mesh).ok());
    EXPECT_EQ(back.mesh.n_faces(), r.after.faces);
    ASSERT_EQ(r.steps.size(), 5u);
    EXPECT_EQ(r.steps[2].step, "subdivide --levels 1");
  }
  const Record a = *std::find_if(records.begin(), records.end(), [](auto& r) { return r.input == "a.obj"; });
  EXPECT_EQ(a.before.faces, 16u);   // 4×4 quads
  // 64 quads → 128 triangles, halved: a collapse removes one or two triangles, so the
  // simplifier stops at the target or one below it, as the flat grid's order of ties decides.
  EXPECT_LE(a.after.faces, 64u);
  EXPECT_GE(a.after.faces, 63u);
  EXPECT_EQ(a.before.vertices, 25u);
}

TEST_F(Batch, ExistingOutputsFailSkipOrAreReplacedAsAsked) {
  const Pipeline p = parse_steps({"simplify --ratio 0.5"});
  const Task t = tasks(p)[0];
  ASSERT_EQ(process(p, t).status, "ok");
  const auto written = fs::last_write_time(t.output);
  const Record again = process(p, t);
  EXPECT_EQ(again.status, "failed");
  EXPECT_NE(again.error.find("output exists"), std::string::npos);
  EXPECT_EQ(process(p, t, ExistingOutput::kSkip).status, "skipped");
  EXPECT_EQ(fs::last_write_time(t.output), written);
  EXPECT_EQ(process(p, t, ExistingOutput::kOverwrite).status, "ok");
}

TEST_F(Batch, ValidateStepFailsNonManifoldInputThatRepairWouldHide) {
  const auto t = tasks(parse_steps({"validate --manifold", "compress"}));
  const Task& fin_task = t[2];
  ASSERT_EQ(fin_task.input_name, "fin.off");
  const Record r = process(parse_steps({"validate --manifold", "compress"}), fin_task);
  EXPECT_EQ(r.status, "failed");
  EXPECT_EQ(r.error, "validate: not manifold: 1 edges with 3 or more faces; 2 non-manifold vertices");
  EXPECT_FALSE(fs::exists(fin_task.output));
  EXPECT_EQ(process(parse_steps({"repair", "compress"}), fin_task).status, "ok");
}

TEST_F(Batch, CompressRecordsTheSplitOfANonManifoldSourceUnlessARepairCameFirst) {
  auto representative = [&](const Pipeline& p) {
    const Task fin_task = tasks(p)[2];
    EXPECT_EQ(process(p, fin_task, ExistingOutput::kOverwrite).status, "ok");
    std::ifstream f(fin_task.output, std::ios::binary);
    const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(f), {}};
    return decompress(bytes).vertex_representative;
  };
  const std::vector<std::uint32_t> rep = representative(parse_steps({"compress"}));
  ASSERT_FALSE(rep.empty());
  std::size_t own = 0;
  for (std::uint32_t v = 0; v < rep.size(); ++v) own += rep[v] == v;
  EXPECT_EQ(own, fin().positions.size());  // joined, the source's five vertices
  EXPECT_TRUE(representative(parse_steps({"repair", "compress"})).empty());
  EXPECT_TRUE(representative(parse_steps({"simplify --ratio 1", "compress"})).empty());
}

TEST_F(Batch, AStopRequestStartsNoNewFileAndPartialOutputsAreCleanedUp) {
  const Pipeline p = parse_steps({"repair"});
  const auto t = tasks(p);
  std::atomic<bool> stop{true};
  std::size_t seen = 0;
  const Summary s = run(p, t, {.jobs = 2, .stop = &stop}, [&](const Record&) { ++seen; });
  EXPECT_TRUE(s.interrupted);
  EXPECT_EQ(seen, 0u);
  EXPECT_FALSE(fs::exists(out / "a.obj"));

  fs::create_directories(out / "sub");
  std::ofstream(out / "sub" / ".b.ply.geom-partial-123-0") << "half a file";
  std::ofstream(out / "keep.ply") << "not ours to delete";
  EXPECT_EQ(remove_partial_outputs(out), 1u);
  EXPECT_FALSE(fs::exists(out / "sub" / ".b.ply.geom-partial-123-0"));
  EXPECT_TRUE(fs::exists(out / "keep.ply"));
}

TEST_F(Batch, RecordsAreOneJsonLine) {
  const Pipeline p = parse_steps({"compress --bits 10"});
  const Record r = process(p, tasks(p)[0]);
  const std::string line = r.to_json();
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_NE(line.find("\"status\":\"ok\""), std::string::npos);
  EXPECT_NE(line.find("\"output\":\"a.gmc\""), std::string::npos);
  EXPECT_NE(line.find("\"step\":\"compress --bits 10\""), std::string::npos);
}

}  // namespace
}  // namespace geom::batch
