'use strict';
// Validates one .glb (or .gltf) file with the Khronos glTF validator (the npm package pinned in
// package.json beside this file, installed by tools/setup-deps.sh). Prints the validator's report as
// JSON on stdout and exits 0 only when it has no errors; 1 when it has errors; 2 when the file or
// the validator cannot be used.
//   node tests/gltf-validator/validate.js file.glb
const fs = require('fs');
const path = require('path');

const file = process.argv[2];
if (!file || process.argv.length > 3) {
  console.error('usage: node validate.js FILE.glb');
  process.exit(2);
}

let validator;
try {
  validator = require('gltf-validator');
} catch (e) {
  console.error('error: the gltf-validator package is not installed; run tools/setup-deps.sh');
  process.exit(2);
}

let bytes;
try {
  bytes = new Uint8Array(fs.readFileSync(file));
} catch (e) {
  console.error(`error: ${file}: ${e.message}`);
  process.exit(2);
}

validator
    .validateBytes(bytes, {uri: path.basename(file), maxIssues: 0, writeTimestamp: false})
    .then((report) => {
      process.stdout.write(JSON.stringify(report, null, 2) + '\n');
      process.exit(report.issues.numErrors === 0 ? 0 : 1);
    })
    .catch((e) => {
      console.error(`error: ${file}: ${e && e.message ? e.message : e}`);
      process.exit(2);
    });
