"""What engines keep of `shprt export`'s transfer (docs/web.md, "Engines"): exports a sphere with
the custom and the standard attributes and opens both with the importers installed here —
Blender's glTF importer (`blender -b`) and gltfpack — then checks the table in docs/web.md:

  Blender 3.4: TEXCOORD_0..7 become UV maps holding the coefficients exactly (V flipped,
               v_blender = 1 - v); the convention block becomes the mesh's and the object's custom
               property "shprt"; the custom _SHPRT_T* attributes are dropped.
  gltfpack 0.18: drops the texture coordinates (no texture samples them) and the custom
               attributes alike; the transfer does not survive it.

A missing importer is skipped with a line; none at all: exit 77 (CTest: skipped).
    python3 tests/engines/check_gltf_engines.py SHPRT WORKDIR
"""
import json
import os
import shutil
import struct
import subprocess
import sys

BLENDER_SCRIPT = r'''
import json, sys
import numpy
if not hasattr(numpy, "bool"):
    numpy.bool = bool  # Debian 12's importer still says numpy.bool, gone since numpy 1.24
import bpy
args = sys.argv[sys.argv.index("--") + 1:]
out = {}
for path in args[1:]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    obj = [o for o in bpy.data.objects if o.type == "MESH"][0]
    me = obj.data
    loops = [[me.vertices[l.vertex_index].co[:] for l in me.loops]]
    uv = [[tuple(d.uv) for d in layer.data] for layer in me.uv_layers]
    out[path] = {"uv_layers": len(uv), "uv": uv, "co": loops[0],
                 "attributes": [a.name for a in me.attributes],
                 "mesh_shprt": "shprt" in me.keys(), "object_shprt": "shprt" in obj.keys()}
with open(args[0], "w") as f:  # a file: Blender exits without flushing a piped stdout
    json.dump(out, f)
'''


def read_glb(path):
    data = open(path, "rb").read()
    length = struct.unpack_from("<I", data, 12)[0]
    gltf = json.loads(data[20:20 + length])
    return gltf, data[20 + length + 8:]


def accessor(gltf, bin_, index):
    a = gltf["accessors"][index]
    view = gltf["bufferViews"][a["bufferView"]]
    width = {"VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
    values = struct.unpack_from(f"<{a['count'] * width}f", bin_, view["byteOffset"])
    return [values[i * width:(i + 1) * width] for i in range(a["count"])]


def check_blender(blender, standard, custom, failures):
    script = os.path.join(os.path.dirname(standard), "blender_check.py")
    open(script, "w").write(BLENDER_SCRIPT)
    result = os.path.join(os.path.dirname(standard), "blender.json")
    # Blender's own Python finds Debian's numpy unless the caller's interpreter (a pyenv build, a
    # virtual environment) leaks its settings in: a bare environment.
    env = {k: os.environ[k] for k in ("HOME", "TMPDIR", "LANG") if k in os.environ}
    env["PATH"] = os.pathsep.join([os.path.dirname(blender), "/usr/bin", "/bin"])
    done = subprocess.run([blender, "-b", "--factory-startup", "--python", script, "--", result,
                           standard, custom], capture_output=True, text=True, timeout=600, env=env)
    if not os.path.exists(result):
        failures.append(f"blender: no result ({(done.stdout + done.stderr).strip()[-300:]})")
        return
    seen = json.load(open(result))
    gltf, bin_ = read_glb(standard)
    names = gltf["meshes"][0]["primitives"][0]["extras"]["shprt"]["attributes"]["standard"]
    texcoords = [n for n in names if n.startswith("TEXCOORD_")]
    got = seen[standard]
    if got["uv_layers"] != len(texcoords):
        failures.append(f"blender: {got['uv_layers']} UV maps, {len(texcoords)} TEXCOORD_n written")
    # Each loop's UV values are the coefficients of a vertex at its position (Blender is Z up:
    # (x, y, z) in glTF is (x, -z, y) there; V is flipped).
    positions = accessor(gltf, bin_, gltf["meshes"][0]["primitives"][0]["attributes"]["POSITION"])
    coefficients = [accessor(gltf, bin_, gltf["meshes"][0]["primitives"][0]["attributes"][n])
                    for n in texcoords]
    by_position = {}
    for v, p in enumerate(positions):
        key = tuple(round(c, 4) for c in (p[0], -p[2], p[1]))
        by_position.setdefault(key, []).append([x for c in coefficients for x in c[v]])
    worst = 0.0
    for loop, co in enumerate(got["co"]):
        values = [x for layer in got["uv"] for x in (layer[loop][0], 1 - layer[loop][1])]
        candidates = by_position.get(tuple(round(c, 4) for c in co), [])
        if not candidates:
            failures.append(f"blender: loop {loop} at {co} has no vertex there")
            break
        worst = max(worst, min(max(abs(a - b) for a, b in zip(values, c)) for c in candidates))
    if worst > 1e-6:
        failures.append(f"blender: UV maps differ from the coefficients by up to {worst}")
    for path in (standard, custom):
        if not (seen[path]["mesh_shprt"] and seen[path]["object_shprt"]):
            failures.append(f"blender: {path}: no 'shprt' custom property on the mesh and object")
    if any(a.lower().startswith("_shprt_t") for a in seen[custom]["attributes"]):
        failures.append("blender kept a custom _SHPRT_T attribute: update docs/web.md")
    print(f"blender: {got['uv_layers']} UV maps hold {2 * len(texcoords)} coefficients "
          f"(largest difference {worst:.2g}); the convention block is the mesh's and object's "
          f"custom property; custom attributes dropped")


def check_gltfpack(gltfpack, standard, custom, failures):
    for path in (standard, custom):
        packed = path.replace(".glb", "_packed.glb")
        subprocess.run([gltfpack, "-noq", "-i", path, "-o", packed], check=True,
                       capture_output=True, timeout=300)
        gltf, _ = read_glb(packed)
        kept = sorted(n for p in gltf["meshes"][0]["primitives"] for n in p["attributes"]
                      if n.startswith(("TEXCOORD_", "_SHPRT_T")))
        if kept:
            failures.append(f"gltfpack now keeps {kept} of {os.path.basename(path)}: "
                            "update docs/web.md")
    print("gltfpack: drops the TEXCOORD_n (no texture samples them) and the custom attributes "
          "alike, with or without -noq")


def main():
    shprt, work = sys.argv[1], sys.argv[2]
    blender, gltfpack = shutil.which("blender"), shutil.which("gltfpack")
    if not blender and not gltfpack:
        print("SKIP: neither blender nor gltfpack is installed (apt-get install gltfpack)")
        return 77
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    run = lambda *a: subprocess.run([shprt, *a], check=True, capture_output=True, cwd=work)
    run("bake", "builtin:sphere", "--bands", "4", "--samples", "64", "-o", "s.shprt")
    run("export", "s.shprt", "-o", "standard.glb", "--attributes", "standard")
    run("export", "s.shprt", "-o", "custom.glb")
    standard, custom = os.path.join(work, "standard.glb"), os.path.join(work, "custom.glb")
    failures = []
    if blender:
        check_blender(blender, standard, custom, failures)
    else:
        print("blender: not installed (apt-get install blender), skipped")
    if gltfpack:
        check_gltfpack(gltfpack, standard, custom, failures)
    else:
        print("gltfpack: not installed (apt-get install gltfpack), skipped")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
