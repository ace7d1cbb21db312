// The Khronos glTF validator (npm's gltf-validator) on one file: a JSON line of its counts and messages.
// node scripts/gltf_validate.js FILE.glb   (NODE_PATH: the folder holding node_modules/gltf-validator)
const fs = require('fs');
const validator = require('gltf-validator');
const data = new Uint8Array(fs.readFileSync(process.argv[2]));
validator.validateBytes(data, {maxIssues: 1000}).then((report) => {
  const m = report.issues.messages.map((x) => [x.severity, x.code, x.pointer || '', x.message]);
  console.log(JSON.stringify({errors: report.issues.numErrors, warnings: report.issues.numWarnings,
                              infos: report.issues.numInfos, hints: report.issues.numHints, messages: m}));
}).catch((e) => { console.error('gltf-validator failed: ' + e); process.exit(3); });
