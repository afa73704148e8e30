// Validates glTF 2.0 files (.gltf, .glb) with the Khronos glTF-Validator.
//
//   npm install && node validate.mjs ../../models/checker-cube.glb [more.gltf ...]
//
// Prints every message of every report (errors, warnings, infos, hints) and exits 1 if any
// file has an error, or a warning not listed in ALLOWED_WARNINGS; 2 if a file cannot be
// read or is not glTF at all. External resources of a .gltf are read relative to the file.

import { readFile } from "node:fs/promises";
import path from "node:path";
import { validateBytes, version } from "gltf-validator";

// Warning codes that do not fail the check, each with the reason it is acceptable.
// Empty: every model the project generates must be free of warnings.
const ALLOWED_WARNINGS = new Map([
  // ["CODE", "why this warning is harmless for our files"],
]);

const SEVERITY = ["error", "warning", "info", "hint"];

async function validate(file) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    writeTimestamp: false,
    externalResourceFunction: async (uri) =>
      new Uint8Array(await readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)))),
  });
  const issues = report.issues;
  let failures = issues.numErrors;
  // This validator does not know KHR_texture_basisu: it warns that an image's mimeType
  // 'image/ktx2' is not PNG or JPEG and that it cannot recognise the image's format. Those
  // two warnings are allowed for exactly the images whose mimeType is 'image/ktx2'.
  const ktx2Images = new Set(
    issues.messages
      .filter((m) => m.code === "VALUE_NOT_IN_LIST" && m.message.includes("'image/ktx2'"))
      .map((m) => (m.pointer ?? "").replace(/\/mimeType$/, "")),
  );
  const ktx2Warning = (m) =>
    (m.code === "VALUE_NOT_IN_LIST" && ktx2Images.has((m.pointer ?? "").replace(/\/mimeType$/, ""))) ||
    (m.code === "IMAGE_UNRECOGNIZED_FORMAT" && ktx2Images.has(m.pointer ?? ""));
  for (const m of issues.messages) {
    const severity = SEVERITY[m.severity] ?? `severity ${m.severity}`;
    let note = "";
    if (m.severity === 1) {
      if (ALLOWED_WARNINGS.has(m.code)) {
        note = ` (allowed: ${ALLOWED_WARNINGS.get(m.code)})`;
      } else if (ktx2Warning(m)) {
        note = " (allowed: a KHR_texture_basisu image, which this validator does not know)";
      } else {
        failures += 1;
      }
    }
    console.log(`  ${severity} ${m.code} at ${m.pointer ?? m.offset ?? "-"}: ${m.message}${note}`);
  }
  const info = report.info ?? {};
  console.log(
    `${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
      `${issues.numInfos} infos, ${issues.numHints} hints ` +
      `(generator: ${info.generator ?? "?"}, ${info.drawCallCount ?? "?"} draw calls, ` +
      `${info.totalVertexCount ?? "?"} vertices, ${info.totalTriangleCount ?? "?"} triangles)`,
  );
  return failures === 0;
}

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error("usage: node validate.mjs FILE.gltf|FILE.glb ...");
  process.exit(2);
}
console.log(`glTF-Validator ${version()}`);
let ok = true;
for (const file of files) {
  try {
    ok = (await validate(file)) && ok;
  } catch (error) {
    console.error(`${file}: cannot validate: ${error}`);
    process.exit(2);
  }
}
process.exit(ok ? 0 : 1);
