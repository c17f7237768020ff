// Validates .glb files with the Khronos glTF Validator (npm gltf-validator) and fails unless each
// has no errors and no warnings. Infos and hints are printed, not counted: they are suggestions,
// not defects. With --shprt and --work it first exports the built-in room (baked small) as
// float32, as --half, with the standard attributes and with a --sun (KHR_lights_punctual), and
// validates those: the CTest test web_gltf_validator.
//
//   node web/test_gltf.mjs [--shprt PATH/shprt --work DIR] [FILE.glb ...]
//   exit 0: all valid; 1: a finding; 77: skipped (`npm ci` not run in web/)
import { execFileSync } from "node:child_process";
import { mkdirSync, readFileSync, rmSync } from "node:fs";
import path from "node:path";

let validator;
try {
    validator = (await import("gltf-validator")).default;
} catch {
    console.log("SKIP: gltf-validator is not installed (run `npm ci` in web/, or scripts/setup)");
    process.exit(77);
}

const args = process.argv.slice(2), files = [];
let shprt, work;
for (let i = 0; i < args.length; ++i) {
    if (args[i] === "--shprt") shprt = path.resolve(args[++i]);
    else if (args[i] === "--work") work = path.resolve(args[++i]);
    else files.push(args[i]);
}
if (shprt && work) {
    rmSync(work, { recursive: true, force: true });
    mkdirSync(work, { recursive: true });
    const run = (...a) => execFileSync(shprt, a, { cwd: work, stdio: ["ignore", "inherit", "inherit"] });
    run("bake", "builtin:room", "-o", "room.shprt", "--coeffs", "16", "--samples", "64");
    run("export", "room.shprt", "-o", "room.glb");
    run("export", "room.shprt", "-o", "room_half.glb", "--half", "--bands", "3", "--light",
        "sun:0.4,0.8,-0.3,5", "--rotate", "30,0,0");
    run("export", "room.shprt", "-o", "room_standard.glb", "--attributes", "standard", "--bands",
        "3");
    run("export", "room.shprt", "-o", "room_sun.glb", "--sun", "0.4,0.8,-0.3,1", "--light",
        "gradient", "--bands", "2");
    files.push(path.join(work, "room.glb"), path.join(work, "room_half.glb"),
               path.join(work, "room_standard.glb"), path.join(work, "room_sun.glb"));
}

let failed = files.length === 0;
for (const file of files) {
    const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
        uri: file, maxIssues: 100,
    });
    const n = report.issues;
    console.log(`${file}: ${n.numErrors} errors, ${n.numWarnings} warnings, ${n.numInfos} infos, ` +
                `${n.numHints} hints (validator ${report.validatorVersion})`);
    for (const m of n.messages.slice(0, 20))
        console.log(`  [${["error", "warning", "info", "hint"][m.severity]}] ${m.code} ` +
                    `${m.pointer ?? ""}: ${m.message}`);
    if (n.numErrors > 0 || n.numWarnings > 0) failed = true;
}
process.exit(failed ? 1 : 0);
