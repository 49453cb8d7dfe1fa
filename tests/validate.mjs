// Runs the Khronos glTF validator (npm `gltf-validator`) on each file named on the
// command line and prints one JSON line per file:
//   {"file", "errors", "warnings", "infos", "hints", "messages": [{code, severity, pointer, message}]}
// (severity: 0 error, 1 warning, 2 info, 3 hint). tests/gltf_validator.rs decides what
// passes; this script only reports. Install with `npm ci` (scripts/test does it).
import { readFile } from "node:fs/promises";
import { createRequire } from "node:module";

const require = createRequire(import.meta.url);
const validator = require("gltf-validator");

for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: file,
    maxIssues: 0, // report everything
    // .gltf files embed their buffer; nothing external to load.
    externalResourceFunction: (uri) =>
      Promise.reject(new Error(`unexpected external resource ${uri}`)),
  });
  const issues = report.issues;
  console.log(
    JSON.stringify({
      file,
      validatorVersion: report.validatorVersion,
      errors: issues.numErrors,
      warnings: issues.numWarnings,
      infos: issues.numInfos,
      hints: issues.numHints,
      messages: issues.messages.map((m) => ({
        code: m.code,
        severity: m.severity,
        pointer: m.pointer,
        message: m.message,
      })),
    }),
  );
}
