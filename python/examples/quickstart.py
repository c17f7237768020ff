#!/usr/bin/env python3
"""The README's Python example, as it is there (python/tests/test_examples.py checks that the two
agree and runs this file): bake a built-in scene, light it, save, load and render it.

    PYTHONPATH=build/python python3 python/examples/quickstart.py   # writes box.shprt here
"""
import shprt                                           # PYTHONPATH=build/python after a build
mesh = shprt.load_scene("builtin:box_on_plane")        # or a file: PLY, OBJ, glTF, ... (Assimp)
T = shprt.bake(mesh, bands=4, samples=1024,            # or bake(vertices, faces, normals, albedo)
               progress=lambda done, total: print(f"{done / total:.0%}"))  # (V, 16) float32
light = shprt.light(["builtin", "sun:0.4,0.8,-0.3"], K=16)   # (3, 16): RGB SH coefficients
E = T @ light.T                                        # per-vertex irradiance, (V, 3)
shprt.save("box.shprt", mesh, T, samples=1024, seed=1)       # `shprt render box.shprt` reads it
f = shprt.load("box.shprt")                            # f.mesh.positions, f.transfer: views
image = shprt.render(f, light, width=640, height=480)  # (480, 640, 3) linear RGB
