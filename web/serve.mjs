// A tiny static server for the viewer (Node's own http module, no dependencies): serves web/
// (the page and node_modules/, where `npm ci` put three.js) at /, and one more folder of .glb
// files at /files/.
//
//   node web/serve.mjs [--port 8000] [--files DIR]
//   then open http://localhost:8000/?model=files/scene.glb
//
// Only GET and HEAD; paths are resolved inside their root (no ".." escapes); prints one line
// "serving http://127.0.0.1:PORT/" when it listens (--port 0 picks a free port).
import { createReadStream, statSync } from "node:fs";
import http from "node:http";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const args = process.argv.slice(2);
function option(name, fallback) {
    const i = args.indexOf(name);
    return i >= 0 && i + 1 < args.length ? args[i + 1] : fallback;
}
const port = Number(option("--port", "8000"));
const files = path.resolve(option("--files", process.cwd()));
const types = {
    ".html": "text/html; charset=utf-8", ".js": "text/javascript; charset=utf-8",
    ".mjs": "text/javascript; charset=utf-8", ".json": "application/json",
    ".glb": "model/gltf-binary", ".png": "image/png", ".css": "text/css",
};

function resolve(urlPath) {
    const p = decodeURIComponent(urlPath);
    const [root, rest] = p.startsWith("/files/") ? [files, p.slice(7)] : [here, p.slice(1)];
    const full = path.resolve(root, rest || "index.html");
    return full === root || full.startsWith(root + path.sep) ? full : null;
}

const server = http.createServer((req, res) => {
    const full = req.method === "GET" || req.method === "HEAD"
        ? resolve(new URL(req.url, "http://x").pathname) : null;
    let st = null;
    try { st = full && statSync(full); } catch { st = null; }
    if (!st || !st.isFile()) {
        res.writeHead(404, { "content-type": "text/plain" });
        res.end("not found\n");
        return;
    }
    res.writeHead(200, {
        "content-type": types[path.extname(full).toLowerCase()] || "application/octet-stream",
        "content-length": st.size, "cache-control": "no-store",
    });
    if (req.method === "HEAD") res.end();
    else createReadStream(full).pipe(res);
});
server.listen(port, "127.0.0.1", () => {
    console.log(`serving http://127.0.0.1:${server.address().port}/ (files: ${files})`);
});
