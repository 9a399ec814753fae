// Runs the Khronos glTF-Validator (npm package gltf-validator, installed by scripts/install-deps
// into .cache/gltf-validator) on each file named on the command line and prints one JSON line
// per file: {"file", "errors", "warnings", "messages": [the errors, at most 20]}.
// Exit status 0 when every file has no error, 1 otherwise, 2 on a usage or set-up problem.
import { createRequire } from "module";
import { readFile } from "fs/promises";
import path from "path";
import { fileURLToPath } from "url";

const here = path.dirname(fileURLToPath(import.meta.url));
const modules = process.env.GEOM_GLTF_VALIDATOR ?? path.join(here, "..", ".cache", "gltf-validator", "node_modules");
let validator;
try {
  validator = createRequire(path.join(modules, "x.js"))("gltf-validator");
} catch (e) {
  console.error(`gltf-validate: gltf-validator not found under ${modules} (run scripts/install-deps)`);
  process.exit(2);
}
if (process.argv.length < 3) {
  console.error("usage: node scripts/gltf-validate.mjs FILE.glb|FILE.gltf ...");
  process.exit(2);
}

let failed = false;
for (const file of process.argv.slice(2)) {
  const data = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(data, {
    uri: path.basename(file),
    maxIssues: 1000,
    externalResourceFunction: (uri) =>
      readFile(path.join(path.dirname(file), decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
  });
  const errors = report.issues.messages.filter((m) => m.severity === 0);
  if (report.issues.numErrors > 0) failed = true;
  console.log(JSON.stringify({
    file,
    errors: report.issues.numErrors,
    warnings: report.issues.numWarnings,
    messages: errors.slice(0, 20).map((m) => `${m.code} ${m.pointer ?? ""}: ${m.message}`),
  }));
}
process.exit(failed ? 1 : 0);
