#include <geom/batch/pipeline.h>
#include <geom/core/errors.h>

#include <gtest/gtest.h>

namespace geom::batch {
namespace {

std::string error_of(const std::string& json) {
  try {
    parse_pipeline(json, "p.json");
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  return "";
}

TEST(Pipeline, StringAndObjectStepsMeanTheSame) {
  const Pipeline a = parse_pipeline(
      R"({"steps": ["repair --weld 1e-6", "simplify --ratio 0.25 --keep-boundary", "compress --bits 12 --preserve-order"]})");
  const Pipeline b = parse_pipeline(
      R"({"steps": [{"repair": {"weld": 1e-6}}, {"simplify": {"ratio": 0.25, "keep-boundary": true}},
                    {"compress": {"bits": 12, "preserve-order": true}}]})");
  ASSERT_EQ(a.steps.size(), 3u);
  ASSERT_EQ(b.steps.size(), 3u);
  const auto& sa = std::get<SimplifyStep>(a.steps[1].options).options;
  const auto& sb = std::get<SimplifyStep>(b.steps[1].options).options;
  EXPECT_EQ(sa.ratio, 0.25);
  EXPECT_EQ(sb.ratio, 0.25);
  EXPECT_TRUE(sa.lock_boundary);
  EXPECT_TRUE(sb.lock_boundary);
  EXPECT_EQ(std::get<RepairStep>(b.steps[0].options).options.weld_tolerance, 1e-6);
  EXPECT_EQ(std::get<CompressStep>(a.steps[2].options).options.bits, 12u);
  EXPECT_TRUE(std::get<CompressStep>(b.steps[2].options).options.preserve_order);
  EXPECT_EQ(a.output_extension(".obj"), ".gmc");
}

TEST(Pipeline, CanonicalJsonReadsBackToTheSameSteps) {
  const Pipeline a = parse_steps({"validate --all", "subdivide --scheme loop --levels 2", "convert --format glb"});
  const Pipeline b = parse_pipeline(a.to_json());
  ASSERT_EQ(b.steps.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(a.steps[i].text, b.steps[i].text);
  EXPECT_TRUE(std::get<ValidateStep>(b.steps[0].options).closed);
  EXPECT_EQ(std::get<SubdivideStep>(b.steps[1].options).options.levels, 2);
  EXPECT_EQ(std::get<SubdivideStep>(b.steps[1].options).options.scheme, SubdivisionScheme::kLoop);
  EXPECT_EQ(b.output_extension(".obj"), ".glb");
  EXPECT_EQ(parse_steps({"simplify --faces 10"}).output_extension(".ply"), ".ply");
}

TEST(Pipeline, ErrorsNameTheStepAndTheOption) {
  EXPECT_EQ(error_of(R"({"steps": ["simplify --rato 0.5"]})"),
            "p.json: step 1 (simplify): unknown option --rato (known: --ratio --faces --max-error "
            "--keep-boundary --boundary-weight --min-quality)");
  EXPECT_EQ(error_of(R"({"steps": ["repair", "smooth"]})"),
            "p.json: step 2: unknown step 'smooth' (known: validate, repair, simplify, subdivide, "
            "compress, convert)");
  EXPECT_EQ(error_of(R"({"steps": ["compress --bits 40"]})"),
            "p.json: step 1 (compress): --bits 40 is outside [1, 30]");
  EXPECT_EQ(error_of(R"({"steps": ["compress --bits twelve"]})"),
            "p.json: step 1 (compress): --bits needs a number, found 'twelve'");
  EXPECT_EQ(error_of(R"({"steps": ["compress", "simplify --ratio 0.5"]})"),
            "p.json: step 1 (compress) writes the output, so it must be the last step");
  EXPECT_EQ(error_of(R"({"steps": ["simplify --ratio 0.5 --faces 3"]})"),
            "p.json: step 1 (simplify): give --ratio or --faces, not both");
  EXPECT_EQ(error_of(R"({"steps": ["subdivide --scheme butterfly"]})"),
            "p.json: step 1 (subdivide): --scheme 'butterfly' is not one of: catmull-clark, loop");
  EXPECT_EQ(error_of(R"({"steps": ["simplify --keep-boundary yes --ratio 0.5"]})"),
            "p.json: step 1 (simplify): --keep-boundary takes no value (found 'yes')");
  EXPECT_EQ(error_of(R"({"steps": ["convert"]})"), "p.json: step 1 (convert): needs --format");
  EXPECT_EQ(error_of(R"({"steps": []})"), "p.json: the pipeline has no steps");
  EXPECT_EQ(error_of(R"({"step": []})"), "p.json: expected {\"steps\": [...]}");
  EXPECT_EQ(error_of(R"({"steps": ["repair"], "jobs": 2})"), "p.json: unknown key 'jobs'");
  EXPECT_EQ(error_of(R"({"steps": [3]})"), "p.json: step 1: a step is a string or an object");
  EXPECT_NE(error_of("{\"steps\": [").find("p.json: not JSON"), std::string::npos);
  EXPECT_NE(error_of(R"({"steps": ["repair"], "x": 1e999})").find("p.json: not JSON"), std::string::npos);
  EXPECT_EQ(error_of(R"({"steps": ["simplify --ratio 0.5 --ratio 0.2"]})"),
            "p.json: step 1 (simplify): option --ratio given twice");
}

}  // namespace
}  // namespace geom::batch
