"""The indirect light of an interreflected bake with its later bounces in all K coefficients and
in the default --bounce-coeffs, against a reference with 8x the final gather and all
coefficients, shaded under several lights (docs/interreflection.md, "Coefficients of the
bounces"). Prints a Markdown table: the RMS error over receivers and RGB divided by the RMS of the
total light.

    PYTHONPATH=build/python /usr/bin/python3 bench/bounce_coeffs_accuracy.py [K] [S]
"""
import sys

import numpy as np
import shprt

K = int(sys.argv[1]) if len(sys.argv) > 1 else 256
S = int(sys.argv[2]) if len(sys.argv) > 2 else 1024
mesh = shprt.load_scene("builtin:room")
common = dict(coeffs=K, samples=S)
T0 = shprt.bake(mesh, **common)[:, None, :]
ir = dict(common, transfer="interreflected", bounces=3)
ref = shprt.bake(mesh, indirect_samples=S, bounce_coeffs=K, **ir) - T0
every = shprt.bake(mesh, bounce_coeffs=K, **ir) - T0
default = shprt.bake(mesh, **ir) - T0
lights = {
    "gradient sky + 2° sun": ["gradient", "sun:0.4,0.8,-0.3,2"],
    "2° sun alone": ["sun:0.4,0.8,-0.3,2"],
    "1° low sun": ["sun:0.9,0.25,0.3,1"],
    "4° sun": ["sun:-0.3,0.9,0.2,4"],
    "gradient sky": ["gradient"],
    "built-in light": ["builtin"],
}
print(f"| light | K2 = {K} | K2 = default |\n|---|---:|---:|")
for name, spec in lights.items():
    L = shprt.light(spec, K=K)[None]
    total = np.sqrt(((((T0 + ref) * L).sum(-1)) ** 2).mean())
    truth = (ref * L).sum(-1)

    def error(a):
        return 100 * np.sqrt((((a * L).sum(-1) - truth) ** 2).mean()) / total

    print(f"| {name} | {error(every):.2f} % | {error(default):.2f} % |")
