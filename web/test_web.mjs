// The browser viewer against `shprt render`, in headless Chromium (Debian's chromium, driven by
// puppeteer-core; WebGL2 on SwiftShader, so no GPU is needed). For the built-in room baked small,
// exported with `shprt export`, it loads web/index.html with a fixed camera, size and light and
// compares the canvas with `shprt render` of the same .shprt file (same camera, light, size, one
// sample per pixel) pixel by pixel on the 8-bit sRGB codes, three times: the file's light with all
// K coefficients, the light turned by --rotate (the page's JavaScript SH rotation) with K′ < K
// (the page's K′), and the file's light from an `export --half` file (int16 decoding). Also
// checks that a mouse drag and the K′ slider change the picture, that the page reports its
// frame rate, that its loading indicator shows while the model loads and goes at the first frame,
// and that a sun exported with --sun is drawn with a shadow map (a point in the box's shadow keeps
// the sky's colour, a lit one brightens). Used by the CTest test web_viewer (tests/CMakeLists.txt).
//
//   node web/test_web.mjs --shprt PATH/shprt --work DIR [--screenshot OUT.png]
//
// Exit 0: pass; 1: fail; 77: skipped (no Chromium, or `npm ci` not run), with the reason.
// CHROMIUM=/path overrides /usr/bin/chromium.
import { execFileSync, spawn } from "node:child_process";
import { existsSync, mkdirSync, rmSync } from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

// Tolerances on |page − shprt render| over all pixels and RGB channels, in 8-bit sRGB codes
// (measured values: web/README.md and the test's output).
// Measured on Debian 12 (Chromium 156, SwiftShader; shprt render on Mesa llvmpipe): mean 0.07,
// 99th percentile 1, 0.065 % of values off by more than 16 (pixels on silhouettes, where the two
// rasterisers cover a pixel differently; the largest difference there is ~230). The two
// references differ from each other by far more (checked below), so these bounds discriminate.
const kMaxMean = 0.5;      // mean absolute difference
const kMaxP99 = 2;         // 99th percentile
const kMaxOver16 = 0.003;  // share of values differing by more than 16 (silhouette pixels)

const here = path.dirname(fileURLToPath(import.meta.url));
const args = process.argv.slice(2);
const option = (name) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : undefined; };
const resolved = (p) => (p === undefined ? p : path.resolve(p));
const shprt = resolved(option("--shprt")), work = resolved(option("--work"));
const screenshot = resolved(option("--screenshot"));
if (!shprt || !work) {
    console.error("usage: node web/test_web.mjs --shprt PATH/shprt --work DIR [--screenshot OUT.png]");
    process.exit(2);
}
const chromium = process.env.CHROMIUM || "/usr/bin/chromium";
if (!existsSync(chromium)) {
    console.log(`SKIP: no Chromium at ${chromium} (apt-get install chromium, or scripts/setup)`);
    process.exit(77);
}
let puppeteer;
try {
    puppeteer = (await import("puppeteer-core")).default;
    if (!existsSync(path.join(here, "node_modules/three/build/three.module.js"))) throw new Error();
} catch {
    console.log("SKIP: puppeteer-core or three missing (run `npm ci` in web/, or scripts/setup)");
    process.exit(77);
}

rmSync(work, { recursive: true, force: true });
mkdirSync(work, { recursive: true });
const run = (...a) => execFileSync(shprt, a, { cwd: work, stdio: ["ignore", "pipe", "inherit"] });

// The scene: the paper's room, 8 bands, few samples (the test compares shading, not bakes).
const camera = "1.9,2.1,2.4,-1.2,0.4,-1.5";
const lights = ["--light", "sun:0.4,0.8,-0.3,10", "--light", "gradient"];
const [W, H] = [480, 270];
run("bake", "builtin:room", "-o", "room.shprt", "--coeffs", "64", "--samples", "256");
run("export", "room.shprt", "-o", "room.glb", ...lights);
run("export", "room.shprt", "-o", "room_half.glb", "--half", ...lights);
const cases = [
    { name: "file light, K'=K", model: "room.glb", page: "", render: [] },
    { name: "rotated light, K'=16", model: "room.glb", page: "&rotate=40,25,-10&coeffs=16",
      render: ["--rotate", "40,25,-10", "--shading-coeffs", "16"] },
    { name: "--half export, file light", model: "room_half.glb", page: "", render: [] },
];
cases.forEach((c, i) => {
    run("render", "room.shprt", "-o", `ref${i}.png`, ...lights, ...c.render, "--camera", camera,
        "--size", `${W}x${H}`, "--samples", "1");
});

// The server, on a free port.
const server = spawn(process.execPath, [path.join(here, "serve.mjs"), "--port", "0", "--files", work],
                     { stdio: ["ignore", "pipe", "inherit"] });
const base = await new Promise((resolve, reject) => {
    server.stdout.on("data", (d) => {
        const m = /serving (http:\/\/\S+)/.exec(String(d));
        if (m) resolve(m[1]);
    });
    server.on("exit", (code) => reject(new Error(`serve.mjs exited (${code})`)));
});

const browser = await puppeteer.launch({
    executablePath: chromium, headless: true,
    args: ["--no-sandbox", "--headless=new", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
           "--ignore-gpu-blocklist"],
});
let failed = false;
try {
    const page = await browser.newPage();
    page.on("console", (m) => { if (m.type() === "error") console.log(`page: ${m.text()}`); });
    page.on("pageerror", (e) => console.log(`page error: ${e.message}`));
    const open = async (model, query, viewport) => {
        await page.setViewport(viewport);
        await page.goto(`${base}?model=files/${model}${query}`);
        await page.waitForFunction("window.shprt && (window.shprt.error || window.shprt.frames >= 3)",
                                   { timeout: 60000 });
        const error = await page.evaluate("window.shprt.error");
        if (error) throw new Error(`the page failed: ${error}`);
    };
    const decodePng = (file) => page.evaluate(async (url) => {
        const blob = await (await fetch(url)).blob();
        const bitmap = await createImageBitmap(blob, { colorSpaceConversion: "none", premultiplyAlpha: "none" });
        const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
        const ctx = canvas.getContext("2d");
        ctx.drawImage(bitmap, 0, 0);
        return Array.from(ctx.getImageData(0, 0, bitmap.width, bitmap.height).data);
    }, `${base}files/${file}`);

    const refs = [];
    for (const [i, c] of cases.entries()) {
        await open(c.model, `&camera=${camera}&size=${W}x${H}&msaa=0${c.page}`, { width: W, height: H });
        const got = await page.evaluate("Array.from(window.shprtPixels())");
        const ref = await decodePng(`ref${i}.png`);
        refs.push(ref);
        if (got.length !== ref.length) throw new Error(`size mismatch: ${got.length} vs ${ref.length}`);
        const diffs = [];
        for (let p = 0; p < got.length; p += 4)
            for (let ch = 0; ch < 3; ++ch) diffs.push(Math.abs(got[p + ch] - ref[p + ch]));
        diffs.sort((a, b) => a - b);
        const mean = diffs.reduce((s, d) => s + d, 0) / diffs.length;
        const p99 = diffs[Math.floor(0.99 * (diffs.length - 1))];
        const over16 = diffs.filter((d) => d > 16).length / diffs.length;
        const meanRef = ref.reduce((s, v, k) => s + (k % 4 === 3 ? 0 : v), 0) / (ref.length * 0.75);
        const ok = mean <= kMaxMean && p99 <= kMaxP99 && over16 <= kMaxOver16 && meanRef > 20;
        console.log(`${ok ? "ok  " : "FAIL"} ${c.name}: mean |diff| ${mean.toFixed(3)} (≤ ${kMaxMean}), ` +
                    `99th percentile ${p99} (≤ ${kMaxP99}), > 16: ${(100 * over16).toFixed(3)} % ` +
                    `(≤ ${100 * kMaxOver16} %), max ${diffs[diffs.length - 1]}, mean code of ` +
                    `the reference ${meanRef.toFixed(1)} (> 20: not a black picture)`);
        if (!ok) failed = true;
    }

    // The bounds tell the two lights apart: the references differ by far more than them.
    let apart = 0;
    for (let p = 0; p < refs[0].length; ++p) if (p % 4 !== 3) apart += Math.abs(refs[0][p] - refs[1][p]);
    apart /= refs[0].length * 0.75;
    console.log(`${apart > 4 * kMaxMean ? "ok  " : "FAIL"} the two references differ by a mean ` +
                `${apart.toFixed(2)} (> ${4 * kMaxMean}: the test tells lights apart)`);
    if (!(apart > 4 * kMaxMean)) failed = true;

    // The controls: a mouse drag turns the light, the slider changes K′; each changes the picture.
    const meanDiff = (a, b) => a.reduce((sum, v, k) => sum + Math.abs(v - b[k]), 0) / a.length;
    const nextFrames = async () => {
        const n = await page.evaluate("window.shprt.frames");
        await page.waitForFunction(`window.shprt.frames >= ${n + 2}`, { timeout: 30000 });
        return page.evaluate("Array.from(window.shprtPixels())");
    };
    const before = await nextFrames();
    await page.mouse.move(W / 2, H / 2);
    await page.mouse.down();
    await page.mouse.move(W / 2 + 120, H / 2 + 30, { steps: 4 });
    await page.mouse.up();
    const dragged = await nextFrames();
    await page.$eval("#kslider", (e) => { e.value = "4"; e.dispatchEvent(new Event("input")); });
    const sliderLabel = await (await nextFrames(), page.$eval("#klabel", (e) => e.textContent));
    const slid = await page.evaluate("Array.from(window.shprtPixels())");
    const [dDrag, dSlide] = [meanDiff(before, dragged), meanDiff(dragged, slid)];
    const controlsOk = dDrag > 1 && dSlide > 1 && sliderLabel.startsWith("4 of 64");
    console.log(`${controlsOk ? "ok  " : "FAIL"} a drag changes the picture by ${dDrag.toFixed(2)}, ` +
                `the slider (K′ = 4: "${sliderLabel}") by ${dSlide.toFixed(2)} (> 1 each)`);
    if (!controlsOk) failed = true;

    // The frame rate the page reports (after its first half-second window).
    await page.waitForFunction("window.shprt.fps > 0", { timeout: 30000 });
    const fps = await page.evaluate("window.shprt.fps");
    const label = await page.$eval("#fps", (e) => e.textContent);
    console.log(`ok   frame rate reported: "${label}"`);
    if (!(fps > 0) || !label.startsWith("fps: ")) failed = true;

    // The sun (export --sun): a KHR_lights_punctual light the page draws with a shadow map beside
    // the SH sky. A box on a plane, the sun 45° up from +X: the floor at x = −1 is in the box's
    // shadow, at x = +1 in the sun. Against the same file drawn without its sun (sun=0): the lit
    // point brightens, the shadowed one stays the sky's.
    run("bake", "builtin:box_on_plane", "-o", "box.shprt", "--coeffs", "16", "--samples", "64");
    run("export", "box.shprt", "-o", "box_sun.glb", "--sun", "1,1,0,1", "--light", "gradient");
    const sunPage = "&camera=0,5,4,0,0,0&size=320x180&msaa=0";
    const codes = async () => {
        const px = await page.evaluate("Array.from(window.shprtPixels())");
        const at = async (p) => {
            const [x, y] = (await page.evaluate(`window.shprtProject([${p}])`)).map(Math.round);
            let sum = 0;  // the mean of a 3 × 3 block's RGB codes
            for (let dy = -1; dy <= 1; ++dy)
                for (let dx = -1; dx <= 1; ++dx)
                    for (let c = 0; c < 3; ++c) sum += px[4 * ((y + dy) * 320 + x + dx) + c];
            return sum / 27;
        };
        return { shadow: await at("-1,0,0"), lit: await at("1,0,0"),
                 sun: await page.evaluate("window.shprt.sun") };
    };

    // First the loading indicator, on the sun's page: the model's response held back 400 ms, the
    // indicator is on the page while it loads and gone at the first frame.
    await page.setViewport({ width: 320, height: 180 });
    await page.setRequestInterception(true);
    const hold = (request) => {
        if (request.isInterceptResolutionHandled()) return;
        if (request.url().endsWith(".glb")) setTimeout(() => request.continue(), 400);
        else request.continue();
    };
    page.on("request", hold);
    await page.goto(`${base}?model=files/box_sun.glb${sunPage}`, { waitUntil: "domcontentloaded" });
    const whileLoading = await page.$eval("#loading", (e) =>
        [getComputedStyle(e).display !== "none" && e.offsetWidth > 0, e.textContent]);
    await page.waitForFunction("window.shprt.error || window.shprt.frames >= 3", { timeout: 60000 });
    const afterLoad = await page.evaluate(() =>
        [getComputedStyle(document.getElementById("loading")).display, window.shprt.loading.log]);
    page.off("request", hold);
    await page.setRequestInterception(false);
    const loadingOk = whileLoading[0] && whileLoading[1].startsWith("loading the model") &&
        afterLoad[0] === "none" && afterLoad[1].at(-1) === "hidden" &&
        afterLoad[1].some((t) => / %/.test(t));
    console.log(`${loadingOk ? "ok  " : "FAIL"} loading indicator: shown while the model loads ` +
                `("${whileLoading[1]}"), then display ${afterLoad[0]}; it said ` +
                `${JSON.stringify([...afterLoad[1].slice(0, 2), "…", ...afterLoad[1].slice(-2)])}`);
    if (!loadingOk) failed = true;

    const withSun = await codes();
    await open("box_sun.glb", sunPage + "&sun=0", { width: 320, height: 180 });
    const without = await codes();
    const d = withSun.sun?.direction ?? [0, 0, 0];
    const sunOk = withSun.sun !== null && without.sun === null &&
        Math.abs(d[0] - Math.SQRT1_2) < 1e-3 && Math.abs(d[1] - Math.SQRT1_2) < 1e-3 &&
        Math.abs(withSun.sun.intensity - 3) < 1e-3 &&
        withSun.lit > without.lit + 20 && Math.abs(withSun.shadow - without.shadow) <= 3;
    console.log(`${sunOk ? "ok  " : "FAIL"} sun: the page reports ${JSON.stringify(withSun.sun)}; ` +
                `floor in the sun ${withSun.lit.toFixed(1)} (sky alone ${without.lit.toFixed(1)}), ` +
                `in the box's shadow ${withSun.shadow.toFixed(1)} (sky alone ` +
                `${without.shadow.toFixed(1)}): lit > sky + 20, shadow = sky ± 3`);
    if (!sunOk) failed = true;

    if (screenshot) {
        // The README's picture: the room as scripts/demo bakes it (K = 256, S = 4096).
        run("bake", "builtin:room", "-o", "shot.shprt", "--coeffs", "256", "--samples", "4096");
        run("export", "shot.shprt", "-o", "shot.glb", ...lights);
        await open("shot.glb", "", { width: 1280, height: 720 });
        await page.waitForFunction("window.shprt.fps > 0", { timeout: 30000 });
        await page.screenshot({ path: screenshot });
        console.log(`screenshot -> ${screenshot}`);
    }
} catch (e) {
    console.log(`FAIL: ${e.message}`);
    failed = true;
} finally {
    await browser.close();
    server.kill();
}
process.exit(failed ? 1 : 0);
