// shprt's PRT viewer for the browser: loads a .glb written by `shprt export`, reads the transfer
// attributes (_SHPRT_T*) and the convention block (primitives[0].extras.shprt, see
// include/shprt/shade/gltf_export.hpp), and relights the model in a vertex shader under the SH
// light of the file, which the mouse rotates. The shading is shade/shade.hpp's pure diffuse
// model, E = Σ_{i<K′} T_i·L_i, L = albedo/π·E, per vertex; the fragment shader applies exposure,
// the ACES filmic fit and sRGB exactly as `shprt render`'s PNG writer (shade/tonemap.hpp), so
// the same camera and light give the same picture (web/test_web.mjs checks it).
//
// URL parameters (all optional):
//   model=URL                the .glb (default scene.glb)
//   camera=EX,EY,EZ,TX,TY,TZ as `shprt render --camera` (default: the file's default camera)
//   fov=DEG                  vertical field of view (default 60, or the file's camera's)
//   size=WxH                 canvas size in pixels (default: the window)
//   exposure=E               as `shprt render --exposure` (default 1)
//   coeffs=K′                as `shprt render --shading-coeffs` (default: all of the file's K)
//   rotate=Y,P,R             as `shprt render --rotate`: the light turned by Ry·Rx·Rz (degrees)
//   msaa=0|1                 antialiasing (default 1)
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { matrixFromYawPitchRollDeg, rotateSh, shRotationBlocks } from "./sh_rotation.js";

const params = new URLSearchParams(location.search);
const stats = { ready: false, error: null, fps: 0, frames: 0, frameMs: 0 };
window.shprt = stats;

function numbers(name, count) {
    const text = params.get(name);
    if (text === null) return null;
    const v = text.split(",").map(Number);
    if (v.length !== count || v.some((x) => !Number.isFinite(x)))
        throw new Error(`${name}=${text}: expected ${count} numbers`);
    return v;
}

function fail(e) {
    stats.error = String(e && e.message ? e.message : e);
    document.getElementById("error").textContent = stats.error;
    console.error(e);
}

const vertexShader = `
precision highp float;
precision highp int;
precision highp sampler2D;
uniform mat4 modelViewMatrix, projectionMatrix;
uniform sampler2D transfer;   // RGBA32F: texel (v·channels + c)·perChannel + a = coefficients 4a..4a+3
uniform sampler2D light;      // RGBA32F, perChannel × 3: row c = colour c, zero from K′ on
uniform int texWidth, perChannel, channels, used;  // used = ceil(K′/4)
in vec3 position;
in vec3 _shprt_albedo;
out vec3 radiance;
vec4 fetchT(int i) { return texelFetch(transfer, ivec2(i % texWidth, i / texWidth), 0); }
void main() {
    vec3 E = vec3(0.0);
    int base = gl_VertexID * channels * perChannel;
    for (int a = 0; a < used; ++a) {
        vec4 lr = texelFetch(light, ivec2(a, 0), 0);
        vec4 lg = texelFetch(light, ivec2(a, 1), 0);
        vec4 lb = texelFetch(light, ivec2(a, 2), 0);
        if (channels == 1) {
            vec4 t = fetchT(base + a);
            E += vec3(dot(t, lr), dot(t, lg), dot(t, lb));
        } else {
            E += vec3(dot(fetchT(base + a), lr), dot(fetchT(base + perChannel + a), lg),
                      dot(fetchT(base + 2 * perChannel + a), lb));
        }
    }
    radiance = _shprt_albedo / 3.14159265358979 * E;
    gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}`;

const fragmentShader = `
precision highp float;
uniform float exposure;
in vec3 radiance;
out vec4 color;
float aces(float x) {  // shade/tonemap.hpp tonemap_aces
    if (!(x > 0.0)) return 0.0;
    return min((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 1.0);
}
float srgb(float x) {  // core/colour.hpp linear_to_srgb
    if (!(x > 0.0)) return 0.0;
    if (x >= 1.0) return 1.0;
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
void main() {
    vec3 c = radiance * exposure;
    color = vec4(srgb(aces(c.r)), srgb(aces(c.g)), srgb(aces(c.b)), 1.0);
}`;

// The transfer attributes decoded to float and packed into one RGBA32F texture (WebGL2 has at
// most 16 vertex attributes; K = 256 needs 64 VEC4s per vertex). Removes them from the geometry
// so that three.js does not upload them as vertex buffers too.
function transferTexture(geometry, info, maxSize) {
    const V = geometry.attributes.position.count;
    const A = info.attributes.per_channel, C = info.channels, K = info.K;
    const texels = V * C * A;
    const width = Math.min(texels, maxSize);
    const height = Math.ceil(texels / width);
    if (height > maxSize) throw new Error(`transfer needs ${texels} texels, more than this GPU holds`);
    const data = new Float32Array(width * height * 4);
    for (let c = 0; c < C; ++c)
        for (let a = 0; a < A; ++a) {
            const name = `${info.attributes.prefix}${c * A + a}`.toLowerCase();
            const attr = geometry.attributes[name];
            if (!attr || attr.itemSize !== 4 || attr.count !== V)
                throw new Error(`attribute ${name.toUpperCase()} is missing or malformed`);
            const src = attr.array;
            const scale = new Float32Array(4);
            for (let j = 0; j < 4; ++j) {
                const i = 4 * a + j;
                scale[j] = info.encoding === "int16_normalized" ? (i < K ? info.scale[c][i] : 0) : 1;
            }
            for (let v = 0; v < V; ++v) {
                const dst = 4 * ((v * C + c) * A + a);
                for (let j = 0; j < 4; ++j) {
                    const q = src[4 * v + j];
                    data[dst + j] = info.encoding === "int16_normalized"
                        ? Math.max(q / 32767, -1) * scale[j] : q;
                }
            }
            geometry.deleteAttribute(name);
        }
    const texture = new THREE.DataTexture(data, width, height, THREE.RGBAFormat, THREE.FloatType);
    texture.needsUpdate = true;
    return { texture, width };
}

// The clip planes of `shprt render` for this eye and target (shade/camera.cpp fit_clip_planes).
function fitClipPlanes(eye, target, box) {
    const f = target.clone().sub(eye).normalize();
    let far = 0, near = Infinity;
    for (let i = 0; i < 8; ++i) {
        const p = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                                    i & 4 ? box.max.z : box.min.z);
        const d = p.sub(eye).dot(f);
        far = Math.max(far, d);
        near = Math.min(near, d);
    }
    const extent = box.max.clone().sub(box.min).length();
    far = Math.max(far, 1e-3 * Math.max(extent, 1e-6)) * 1.01;
    near = Math.max(Math.min(near, far) * 0.99, far * 1e-3);
    return { near, far };
}

async function main() {
    const canvas = document.getElementById("canvas");
    const size = params.get("size");
    let width = window.innerWidth, height = window.innerHeight;
    if (size !== null) {
        const m = /^(\d+)x(\d+)$/.exec(size);
        if (!m) throw new Error(`size=${size}: expected WxH`);
        [width, height] = [Number(m[1]), Number(m[2])];
    }
    const renderer = new THREE.WebGLRenderer({
        canvas, antialias: params.get("msaa") !== "0", preserveDrawingBuffer: true,
    });
    renderer.setPixelRatio(1);
    renderer.setSize(width, height, true);
    renderer.setClearColor(0x000000, 1);
    const gl = renderer.getContext();
    if (!(gl instanceof WebGL2RenderingContext)) throw new Error("WebGL2 is not available");

    const url = params.get("model") || "scene.glb";
    document.getElementById("model").textContent = url.split("/").pop();
    const gltf = await new GLTFLoader().loadAsync(url);
    let mesh = null;
    gltf.scene.traverse((o) => { if (o.isMesh && !mesh) mesh = o; });
    if (!mesh) throw new Error(`${url} has no mesh`);
    const geometry = mesh.geometry;
    const info = geometry.userData.shprt;
    if (!info || info.format !== "shprt-gltf")
        throw new Error(`${url} has no extras.shprt block: not written by shprt export`);
    if (!geometry.attributes._shprt_albedo) throw new Error(`${url} has no _SHPRT_ALBEDO`);

    const { texture, width: texWidth } =
        transferTexture(geometry, info, gl.getParameter(gl.MAX_TEXTURE_SIZE));
    const A = info.attributes.per_channel;
    const lightData = new Float32Array(A * 3 * 4);
    const lightTexture = new THREE.DataTexture(lightData, A, 3, THREE.RGBAFormat, THREE.FloatType);
    lightTexture.needsUpdate = true;

    const material = new THREE.RawShaderMaterial({
        glslVersion: THREE.GLSL3,
        vertexShader, fragmentShader,
        side: THREE.DoubleSide,  // rooms are seen from inside: no culling, as shprt render
        uniforms: {
            transfer: { value: texture }, light: { value: lightTexture },
            texWidth: { value: texWidth }, perChannel: { value: A },
            channels: { value: info.channels }, used: { value: A },
            exposure: { value: Number(params.get("exposure") ?? 1) },
        },
    });
    const scene = new THREE.Scene();
    const object = new THREE.Mesh(geometry, material);
    object.frustumCulled = false;
    scene.add(object);

    // Camera: as `shprt render` (look_at_camera): up +Y, or −Z looking straight up or down.
    geometry.computeBoundingBox();
    const cam = numbers("camera", 6) ??
        [...info.camera.eye, ...info.camera.target];
    const fov = Number(params.get("fov") ?? (params.get("camera") ? 60 : info.camera.fov_y_deg));
    const eye = new THREE.Vector3(cam[0], cam[1], cam[2]);
    const target = new THREE.Vector3(cam[3], cam[4], cam[5]);
    const { near, far } = fitClipPlanes(eye, target, geometry.boundingBox);
    const camera = new THREE.PerspectiveCamera(fov, width / height, near, far);
    const dir = target.clone().sub(eye).normalize();
    if (dir.clone().cross(new THREE.Vector3(0, 1, 0)).length() < 1e-4) camera.up.set(0, 0, -1);
    camera.position.copy(eye);
    camera.lookAt(target);
    camera.updateMatrixWorld();

    // Light: the file's full-band light, turned by yaw/pitch/roll (URL, then the mouse), cut to K′.
    const bands = Math.round(Math.sqrt(info.light.K));
    const source = info.light.coeffs.map((c) => Float64Array.from(c));
    const ypr = numbers("rotate", 3) ?? [0, 0, 0];
    const slider = document.getElementById("kslider");
    slider.max = String(info.K);
    let kUsed = Number(params.get("coeffs") ?? info.K);
    if (!(kUsed >= 1 && kUsed <= info.K)) kUsed = info.K;
    slider.value = String(kUsed);
    let dirty = true;
    function updateLight() {
        const R = matrixFromYawPitchRollDeg(ypr[0], ypr[1], ypr[2]);
        const identity = ypr.every((x) => x === 0);
        const blocks = identity ? null : shRotationBlocks(R, bands);
        for (let c = 0; c < 3; ++c) {
            const coeffs = identity ? source[c] : rotateSh(blocks, source[c]);
            for (let i = 0; i < 4 * A; ++i)
                lightData[(c * A) * 4 + i] = i < kUsed ? coeffs[i] : 0;
        }
        lightTexture.needsUpdate = true;
        material.uniforms.used.value = Math.ceil(kUsed / 4);
        document.getElementById("klabel").textContent =
            `${kUsed} of ${info.K}` + (Number.isInteger(Math.sqrt(kUsed)) ? ` (${Math.sqrt(kUsed)} bands)` : "");
        dirty = false;
    }
    slider.addEventListener("input", () => { kUsed = Number(slider.value); dirty = true; });
    let drag = null;
    canvas.addEventListener("pointerdown", (e) => { drag = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
    canvas.addEventListener("pointerup", () => { drag = null; });
    canvas.addEventListener("pointermove", (e) => {
        if (!drag) return;
        ypr[0] += (e.clientX - drag[0]) * 0.5;
        ypr[1] = Math.max(-90, Math.min(90, ypr[1] + (e.clientY - drag[1]) * 0.5));
        drag = [e.clientX, e.clientY];
        dirty = true;
    });
    if (size === null)
        window.addEventListener("resize", () => {
            renderer.setSize(window.innerWidth, window.innerHeight, true);
            camera.aspect = window.innerWidth / window.innerHeight;
            camera.updateProjectionMatrix();
        });

    // Frame rate: frames drawn per second of wall time, over windows of at least half a second.
    const fpsLabel = document.getElementById("fps");
    let windowStart = performance.now(), windowFrames = 0;
    function frame(now) {
        if (dirty) updateLight();
        renderer.render(scene, camera);
        stats.frames += 1;
        windowFrames += 1;
        if (now - windowStart >= 500) {
            stats.fps = (1000 * windowFrames) / (now - windowStart);
            stats.frameMs = (now - windowStart) / windowFrames;
            fpsLabel.textContent = `fps: ${stats.fps.toFixed(1)} (${stats.frameMs.toFixed(1)} ms, ` +
                `${geometry.attributes.position.count} vertices, ${width}×${height})`;
            windowStart = now;
            windowFrames = 0;
        }
        stats.ready = true;
        requestAnimationFrame(frame);
    }
    requestAnimationFrame(frame);

    // The canvas as 8-bit RGBA, row 0 at the top (what `shprt render` writes), for the tests.
    window.shprtPixels = () => {
        const px = new Uint8Array(width * height * 4);
        gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, px);
        const flipped = new Uint8Array(px.length), row = width * 4;
        for (let y = 0; y < height; ++y)
            flipped.set(px.subarray((height - 1 - y) * row, (height - y) * row), y * row);
        return flipped;
    };
}

main().catch(fail);
