// libFuzzer target for batch pipelines (geom/batch/PIPELINE.md): any text must parse or
// throw InvalidArgument naming the source, and a pipeline that parses must come back the same
// from its canonical JSON (to_json, then parse_pipeline again).

#include "fuzz_check.h"

#include <geom/batch/pipeline.h>
#include <geom/core/errors.h>

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  geom::batch::Pipeline p;
  try {
    p = geom::batch::parse_pipeline(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json");
  } catch (const geom::InvalidArgument&) {
    return 0;
  }
  const std::string canonical = p.to_json();
  const geom::batch::Pipeline again = geom::batch::parse_pipeline(canonical, "canonical");  // must not throw
  FUZZ_CHECK(again.to_json() == canonical && again.steps.size() == p.steps.size());
  return 0;
}
