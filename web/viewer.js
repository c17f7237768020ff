// shprt's PRT viewer for the browser: loads a .glb written by `shprt export`, reads the transfer
// attributes (_SHPRT_T*) and the convention block (primitives[0].extras.shprt, see
// include/shprt/shade/gltf_export.hpp), and relights the model in a vertex shader under the SH
// light of the file, which the mouse rotates. The shading is shade/shade.hpp's pure diffuse
// model, E = Σ_{i<K′} T_i·L_i, L = albedo/π·E, per vertex; the fragment shader applies exposure,
// the ACES filmic fit and sRGB exactly as `shprt render`'s PNG writer (shade/tonemap.hpp), so
// the same camera and light give the same picture (web/test_web.mjs checks it).
//
// A sun kept out of the SH sum (`shprt export --sun`) comes as a KHR_lights_punctual directional
// light, which GLTFLoader turns into a THREE.DirectionalLight: the page draws it with three.js's
// own shadow map (PCF, its camera fitted to the model's bounds), the mesh casting and receiving,
// and adds its direct light ρ/π · E_sun · max(0, n·s) · shadow per fragment to the SH sky. The
// file's SH light is then the sky alone, so the sun is counted once. The sun's bounced light of an
// interreflected bake is not drawn here (the file carries the whole transfer T, not T − T₀).
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
//   sun=0                    leave the file's sun out (default: drawn when the file has one)
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { matrixFromYawPitchRollDeg, rotateSh, shRotationBlocks } from "./sh_rotation.js";

const params = new URLSearchParams(location.search);
const stats = { ready: false, error: null, fps: 0, frames: 0, frameMs: 0, sun: null };
window.shprt = stats;

function numbers(name, count) {
    const text = params.get(name);
    if (text === null) return null;
    const v = text.split(",").map(Number);
    if (v.length !== count || v.some((x) => !Number.isFinite(x)))
        throw new Error(`${name}=${text}: expected ${count} numbers`);
    return v;
}

// The loading indicator (index.html's #loading): the bytes of the model as they arrive, then
// "preparing" while the transfer is packed; hidden at the first frame or replaced by the error.
// stats.loading records what it showed, for the tests.
stats.loading = { visible: true, log: ["shown"] };
function loadingProgress(event) {
    const bar = document.getElementById("loadbar"), text = document.getElementById("loadtext");
    if (event.lengthComputable && event.total > 0) {
        bar.max = event.total;
        bar.value = event.loaded;
        text.textContent = `loading the model… ${Math.round((100 * event.loaded) / event.total)} %` +
            ` of ${(event.total / 1048576).toFixed(1)} MiB`;
    } else {
        text.textContent = `loading the model… ${(event.loaded / 1048576).toFixed(1)} MiB`;
    }
    stats.loading.log.push(text.textContent);
}
function loadingDone(message) {
    if (!stats.loading.visible) return;
    if (message) {
        document.getElementById("loadtext").textContent = message;
        stats.loading.log.push(message);
        return;
    }
    document.getElementById("loading").style.display = "none";
    stats.loading.visible = false;
    stats.loading.log.push("hidden");
}

function fail(e) {
    stats.error = String(e && e.message ? e.message : e);
    loadingDone(`failed: ${stats.error}`);
    document.getElementById("error").textContent = stats.error;
    console.error(e);
}

// A ShaderMaterial (three.js declares position, normal and the matrices, and with `lights` its
// light and shadow uniforms), written in GLSL 3.
const vertexShader = `
precision highp int;
precision highp sampler2D;
#include <common>
#include <shadowmap_pars_vertex>
uniform sampler2D transfer;   // RGBA32F: texel (v·channels + c)·perChannel + a = coefficients 4a..4a+3
uniform sampler2D light;      // RGBA32F, perChannel × 3: row c = colour c, zero from K′ on
uniform int texWidth, perChannel, channels, used;  // used = ceil(K′/4)
in vec3 _shprt_albedo;
out vec3 radiance;
out vec3 albedo;
out vec3 worldNormal;
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
    albedo = _shprt_albedo;
    // The sun's term needs the file's normal (as shprt shade --sun: max(0, n·s), no flip toward
    // the eye) and three.js's shadow coordinates (shadowmap_vertex reads these two names).
    vec3 transformedNormal = normalMatrix * normal;
    vec4 worldPosition = modelMatrix * vec4(position, 1.0);
    worldNormal = normalize(mat3(modelMatrix) * normal);
    #include <shadowmap_vertex>
    gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}`;

const fragmentShader = `
#include <common>
#include <packing>
#include <lights_pars_begin>
#include <shadowmap_pars_fragment>
uniform float exposure;
uniform vec3 sunWorld;        // unit, toward the sun (world space)
in vec3 radiance;
in vec3 albedo;
in vec3 worldNormal;
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
    vec3 L = radiance;
#if NUM_DIR_LIGHTS > 0
    // The sun's direct light: ρ/π · E_sun · max(0, n·s) · shadow (directionalLights[0].color is
    // three.js's colour × intensity, the irradiance in the file's lux).
    float shadow = 1.0;
  #if defined(USE_SHADOWMAP) && NUM_DIR_LIGHT_SHADOWS > 0
    DirectionalLightShadow s = directionalLightShadows[0];
    shadow = getShadow(directionalShadowMap[0], s.shadowMapSize, s.shadowIntensity, s.shadowBias,
                       s.shadowRadius, vDirectionalShadowCoord[0]);
  #endif
    L += albedo / PI * directionalLights[0].color * max(dot(normalize(worldNormal), sunWorld), 0.0) * shadow;
#endif
    vec3 c = L * exposure;
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

// The file's sun (KHR_lights_punctual, loaded by GLTFLoader as a DirectionalLight) drawn with a
// shadow map: an orthographic shadow camera along the light, fitted to the model's bounding box
// seen from the sun (the scenes are bounded; a large one spreads the map's texels thinner: 2048²
// over the box), the mesh casting and receiving. PCF with a filter radius that follows the sun's
// angular radius at a quarter of the model's size (tan r · extent/4, in shadow-map texels, at
// least 1): a fixed-width penumbra, not PCSS.
function addSun(gltf, info, object, scene, renderer, box, material) {
    let sun = null;
    gltf.scene.traverse((o) => { if (o.isDirectionalLight && !sun) sun = o; });
    if (!sun || params.get("sun") === "0") return;
    gltf.scene.updateMatrixWorld(true);
    const toSun = new THREE.Vector3();  // the light shines along its node's −Z
    sun.getWorldDirection(toSun);       // three.js: the object's +Z in world space
    toSun.normalize();
    const light = new THREE.DirectionalLight(sun.color, sun.intensity);
    const center = box.getCenter(new THREE.Vector3());
    const extent = box.getSize(new THREE.Vector3()).length();
    light.position.copy(center).addScaledVector(toSun, extent);
    light.target.position.copy(center);
    light.castShadow = true;
    const size = 2048;
    light.shadow.mapSize.set(size, size);
    // The shadow camera: the box's corners in the light's frame give its left/right/top/bottom
    // and near/far.
    light.updateMatrixWorld(true);
    light.target.updateMatrixWorld(true);
    const cam = light.shadow.camera;
    cam.position.copy(light.position);
    cam.lookAt(center);
    cam.updateMatrixWorld(true);
    const inverse = cam.matrixWorldInverse;
    const lo = new THREE.Vector3(Infinity, Infinity, Infinity), hi = lo.clone().negate();
    for (let i = 0; i < 8; ++i) {
        const p = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                                    i & 4 ? box.max.z : box.min.z).applyMatrix4(inverse);
        lo.min(p);
        hi.max(p);
    }
    const margin = 1e-3 * extent;
    cam.left = lo.x - margin; cam.right = hi.x + margin;
    cam.bottom = lo.y - margin; cam.top = hi.y + margin;
    cam.near = Math.max(-hi.z - margin, 1e-4 * extent); cam.far = -lo.z + margin;
    cam.updateProjectionMatrix();
    const texel = Math.max(cam.right - cam.left, cam.top - cam.bottom) / size;
    const radiusDeg = info.sun?.radius_deg ?? 0.27;
    light.shadow.radius = Math.max(1, Math.tan(radiusDeg * Math.PI / 180) * extent / 4 / texel);
    light.shadow.bias = -2e-4;
    light.shadow.normalBias = 2 * texel;
    renderer.shadowMap.enabled = true;
    renderer.shadowMap.type = THREE.PCFShadowMap;
    object.castShadow = true;
    object.receiveShadow = true;
    scene.add(light, light.target);
    material.uniforms.sunWorld.value.copy(toSun);
    stats.sun = {
        direction: toSun.toArray(), intensity: light.intensity, color: light.color.toArray(),
        shadowMapSize: size, shadowRadius: light.shadow.radius,
        shadowCamera: { left: cam.left, right: cam.right, bottom: cam.bottom, top: cam.top,
                        near: cam.near, far: cam.far },
    };
    document.getElementById("sun").textContent =
        `sun: ${light.intensity.toPrecision(4)} lux toward (${toSun.toArray().map((x) => x.toFixed(2)).join(", ")}), shadow map ${size}²`;
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
    const gltf = await new GLTFLoader().loadAsync(url, loadingProgress);
    loadingDone("preparing the transfer…");
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

    const material = new THREE.ShaderMaterial({
        glslVersion: THREE.GLSL3,
        vertexShader, fragmentShader,
        lights: true,            // three.js's light and shadow uniforms (the sun, if any)
        side: THREE.DoubleSide,  // rooms are seen from inside: no culling, as shprt render
        uniforms: {
            ...THREE.UniformsUtils.clone(THREE.UniformsLib.lights),
            transfer: { value: texture }, light: { value: lightTexture },
            texWidth: { value: texWidth }, perChannel: { value: A },
            channels: { value: info.channels }, used: { value: A },
            exposure: { value: Number(params.get("exposure") ?? 1) },
            sunWorld: { value: new THREE.Vector3(0, 1, 0) },
        },
    });
    const scene = new THREE.Scene();
    const object = new THREE.Mesh(geometry, material);
    object.frustumCulled = false;
    scene.add(object);
    geometry.computeBoundingBox();
    addSun(gltf, info, object, scene, renderer, geometry.boundingBox, material);

    // Camera: as `shprt render` (look_at_camera): up +Y, or −Z looking straight up or down.
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
        loadingDone();
        requestAnimationFrame(frame);
    }
    requestAnimationFrame(frame);

    // The pixel (x right, y down) where the world point p appears, for the tests.
    window.shprtProject = (p) => {
        const v = new THREE.Vector3(p[0], p[1], p[2]).project(camera);
        return [(v.x + 1) / 2 * width, (1 - v.y) / 2 * height];
    };

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
