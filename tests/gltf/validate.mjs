// Validates one glTF 2.0 asset (.gltf with external or embedded buffers, or
// .glb) with the Khronos glTF validator and prints what it found: one line
// of counts, then one line per message. Exit status: 0 without errors, 1 with
// errors, 2 when the file cannot be read or the validator cannot be loaded.
//
// usage: node validate.mjs FILE
// env:   DUALFORM_GLTF_VALIDATOR  the gltf-validator package folder; default
//        ${XDG_CACHE_HOME:-$HOME/.cache}/dualform/node/node_modules/gltf-validator
//        (where tools/fetch-gltf-validator installs it)
import { readFile } from "node:fs/promises";
import { createRequire } from "node:module";
import { homedir } from "node:os";
import path from "node:path";

const severities = ["error", "warning", "info", "hint"];

function validatorFolder() {
    if (process.env.DUALFORM_GLTF_VALIDATOR) return process.env.DUALFORM_GLTF_VALIDATOR;
    const cache = process.env.XDG_CACHE_HOME || path.join(homedir(), ".cache");
    return path.join(cache, "dualform", "node", "node_modules", "gltf-validator");
}

async function main() {
    if (process.argv.length !== 3) {
        console.error("usage: node validate.mjs FILE");
        return 2;
    }
    const file = path.resolve(process.argv[2]);
    let validator;
    try {
        validator = createRequire(import.meta.url)(validatorFolder());
    } catch (e) {
        console.error(`validate: cannot load the glTF validator from ${validatorFolder()} ` +
                      `(tools/fetch-gltf-validator installs it): ${e.message}`);
        return 2;
    }
    let bytes;
    try {
        bytes = await readFile(file);
    } catch (e) {
        console.error(`validate: cannot read ${file}: ${e.message}`);
        return 2;
    }
    const report = await validator.validateBytes(new Uint8Array(bytes), {
        uri: path.basename(file),
        maxIssues: 0,
        externalResourceFunction: (uri) =>
            readFile(path.resolve(path.dirname(file), decodeURIComponent(uri))).then(
                (data) => new Uint8Array(data)),
    });
    const issues = report.issues;
    console.log(`validate: ${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
                `${issues.numInfos} infos, ${issues.numHints} hints ` +
                `(glTF validator ${report.validatorVersion})`);
    const messages = [...issues.messages].sort((a, b) => a.severity - b.severity);
    for (const m of messages) {
        const where = m.pointer !== undefined ? m.pointer : (m.offset !== undefined ? `@${m.offset}` : "");
        console.log(`${severities[m.severity] ?? m.severity} ${m.code} ${where}: ${m.message}`);
    }
    return issues.numErrors === 0 ? 0 : 1;
}

main().then(
    (code) => process.exit(code),
    (e) => {
        console.error(`validate: ${process.argv[2]}: the validator failed: ${e}`);
        process.exit(2);
    });
