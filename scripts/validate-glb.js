// Validates GLB files with the Khronos glTF validator (npm package gltf-validator):
//   NODE_PATH=DIR/node_modules node scripts/validate-glb.js FILE.glb...
// Prints each file's error and warning counts and its first errors; exits 1 if any file has
// an error. Warnings are reported, not failed on (a source's own warnings carry over: a
// material that needs tangents on a mesh without them).
const validator = require('gltf-validator');
const fs = require('fs');
const path = require('path');

(async () => {
  let failed = 0;
  for (const file of process.argv.slice(2)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
      uri: file,
      externalResourceFunction: () => Promise.reject(new Error('a GLB written by dynlod has no external resources')),
    });
    const { numErrors, numWarnings, messages } = report.issues;
    console.log(`${path.basename(file)}: ${numErrors} errors, ${numWarnings} warnings`);
    for (const m of messages.filter((m) => m.severity === 0).slice(0, 5)) {
      console.log(`    ${m.code} ${m.pointer || ''} ${m.message}`);
    }
    failed += numErrors > 0 ? 1 : 0;
  }
  if (failed > 0) {
    console.log(`${failed} file(s) with errors`);
    process.exit(1);
  }
})().catch((e) => {
  console.error(e);
  process.exit(2);
});
