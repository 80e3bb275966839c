// Runs the Khronos glTF-Validator on each file named on the command line. Prints one line per
// file, "PATH: E errors, W warnings", then each error; exits 1 when any file has an error.
const validator = require('gltf-validator');
const fs = require('fs');

(async () => {
  let failed = 0;
  for (const path of process.argv.slice(2)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(path)), {
      maxIssues: 1000,
    });
    const { numErrors, numWarnings } = report.issues;
    console.log(`${path}: ${numErrors} errors, ${numWarnings} warnings`);
    for (const issue of report.issues.messages) {
      if (issue.severity <= 1) {
        console.log(`  ${issue.severity === 0 ? 'error' : 'warning'} ${issue.code}: ${issue.message} ${issue.pointer || ''}`);
      }
    }
    if (numErrors > 0) failed += 1;
  }
  process.exit(failed > 0 ? 1 : 0);
})();
