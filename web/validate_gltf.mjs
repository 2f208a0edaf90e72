// Validates glb files with the Khronos glTF validator (npm gltf-validator):
//   node web/validate_gltf.mjs FILE.glb...
// Prints one line per file (errors, warnings, and the extensions used); exits 1 if any file has
// an error.
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

let failed = false;
for (const file of process.argv.slice(2)) {
  const data = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(data, { uri: file, maxIssues: 50 });
  const issues = report.issues;
  const used = (report.info && report.info.extensionsUsed) || [];
  console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings` +
              `${used.length ? ', extensions ' + used.join(' ') : ''}`);
  for (const m of issues.messages)
    if (m.severity <= 1)
      console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code}: ${m.message} (${m.pointer || ''})`);
  if (issues.numErrors > 0)
    failed = true;
}
process.exit(failed ? 1 : 0);
