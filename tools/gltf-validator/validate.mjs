// Validates one glTF or GLB file with the Khronos glTF validator
// (npm package gltf-validator, pinned in package.json, installed by
// scripts/test.sh) and prints its report as JSON on stdout.
//
//   node tools/gltf-validator/validate.mjs FILE.glb
//
// Exit status: 0 when the report was printed (whatever it says: read
// issues.numErrors), 2 when the file cannot be read or validated.
import { readFile } from 'node:fs/promises';
import { createRequire } from 'node:module';
import { basename } from 'node:path';

const validator = createRequire(import.meta.url)('gltf-validator');

const file = process.argv[2];
if (!file || process.argv.length > 3) {
  console.error('usage: node validate.mjs FILE.glb|FILE.gltf');
  process.exit(2);
}
try {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: basename(file),
    maxIssues: 0, // report every issue
  });
  console.log(JSON.stringify(report, null, 2));
} catch (e) {
  console.error(`${file}: ${e && e.message ? e.message : e}`);
  process.exit(2);
}
