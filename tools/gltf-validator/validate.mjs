// Validate glTF/GLB files with the Khronos glTF-Validator (npm `gltf-validator`, pinned in
// package.json / package-lock.json beside this file).
//
//   node tools/gltf-validator/validate.mjs FILE.glb [FILE2.glb ...]
//
// Prints one JSON validation report per file, one per line (so a single file gives a single
// JSON document), in the order given. Every issue is reported (maxIssues 0 = unlimited) and
// the timestamp is left out so reports are reproducible.
// Exit status: 0 when no file has an error, 1 when some file has one, 2 when a file cannot be
// read or the validator cannot parse it at all (the reason goes to stderr).
import { readFile } from "node:fs/promises";
import { createRequire } from "node:module";

const require = createRequire(import.meta.url);
const validator = require("gltf-validator");

const paths = process.argv.slice(2);
if (paths.length === 0) {
  process.stderr.write("usage: node validate.mjs FILE.glb [FILE2.glb ...]\n");
  process.exit(2);
}

let status = 0;
for (const path of paths) {
  let report;
  try {
    const bytes = await readFile(path);
    report = await validator.validateBytes(new Uint8Array(bytes), {
      uri: path,
      maxIssues: 0,
      writeTimestamp: false,
    });
  } catch (err) {
    process.stderr.write(`${path}: ${err}\n`);
    process.exit(2);
  }
  process.stdout.write(JSON.stringify(report) + "\n");
  if (report.issues.numErrors > 0) status = 1;
}
process.exit(status);
