// Validates a .gltf file with the Khronos glTF validator (npm package gltf-validator, installed by
// scripts/install-deps.sh), loading its external resources (buffers, images) from beside it.
// Prints the report's counts and every message; exits 1 when there is any error or warning.
//   node scripts/validate-gltf.mjs path/to/material.gltf
import { createRequire } from 'module';
import fs from 'fs';
import path from 'path';

const require = createRequire(import.meta.url);
let validator;
for (const where of [process.env.GLTF_VALIDATOR, 'gltf-validator', '/usr/lib/node_modules/gltf-validator',
                     '/usr/local/lib/node_modules/gltf-validator']) {
  if (!where) continue;
  try { validator = require(where); break; } catch (e) { /* try the next place */ }
}
if (!validator) {
  console.error('validate-gltf: gltf-validator is not installed (scripts/install-deps.sh installs it with npm)');
  process.exit(2);
}
const file = process.argv[2];
if (!file) {
  console.error('usage: node scripts/validate-gltf.mjs FILE.gltf');
  process.exit(2);
}
const dir = path.dirname(file);
const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
  uri: path.basename(file),
  externalResourceFunction: (uri) => new Promise((resolve, reject) => {
    fs.readFile(path.join(dir, decodeURIComponent(uri)), (err, data) => err ? reject(err.toString()) : resolve(new Uint8Array(data)));
  }),
});
const issues = report.issues;
console.log(`errors ${issues.numErrors} warnings ${issues.numWarnings} infos ${issues.numInfos} hints ${issues.numHints}`);
for (const m of issues.messages) console.log(`${['error', 'warning', 'info', 'hint'][m.severity]} ${m.code} ${m.pointer || ''}: ${m.message}`);
process.exit(issues.numErrors > 0 || issues.numWarnings > 0 ? 1 : 0);
