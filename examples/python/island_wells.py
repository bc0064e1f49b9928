"""The distance-like field of an island, at wells and on a grid, from Python.

A GIS analyst's day with `import sage`: the island of
examples/models/island_with_lake.geojson (longitude/latitude; sage
projects it to metres), its normalized field omega on a 100 m grid, and
omega with its gradient at a few wells given in longitude/latitude, which
`sage sample` brings into the field's plane as it did the polygons. With
matplotlib (Debian: python3-matplotlib), the map is saved as
island_wells.png.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/island_wells.py [OUT_DIR]

It checks its own results: omega > 0 on the island, < 0 in its lake and
at sea, and |grad omega| = 1 on the coast (a normalized field).
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

import sage

here = os.path.dirname(os.path.abspath(__file__))
island = sage.load(os.path.join(here, "..", "models", "island_with_lake.geojson"))
print(f"{island!r}: {island.dimension}D, bounds {island.bounds}")

# 1. The field on a grid of 100 m pixels, in the island's plane (metres).
grid = island.sample(resolution=100.0)
omega = grid["omega"]
print(f"grid {omega.shape[1]} x {omega.shape[0]} pixels of 100 m; {grid['evaluation']}")

# 2. Normalized: |grad omega| = 1 on the coast. Where the coast crosses the
# grid's middle row, bisection between the two pixels finds it.
row = grid["y"].size // 2
y, x = grid["y"][row], grid["x"]
for i in np.nonzero(np.sign(omega[row, :-1]) != np.sign(omega[row, 1:]))[0]:
    a, b = x[i], x[i + 1]
    for _ in range(60):
        middle = 0.5 * (a + b)
        same_side = np.sign(island.evaluate(np.array([[middle, y]]), order=0)["omega"][0]) == np.sign(omega[row, i])
        a, b = (middle, b) if same_side else (a, middle)
    coast = island.evaluate(np.array([[a, y]]))
    print(f"coast at x = {a:.2f} m: omega {coast['omega'][0]:.1e}, |grad omega| {coast['grad_norm'][0]:.9f}")
    assert abs(coast["grad_norm"][0] - 1.0) < 1e-6, "a normalized field has |grad omega| = 1 on the coast"

# 3. Wells in longitude/latitude: `sage sample` projects them like the polygons.
wells = {"farm": (11.004, 57.030), "lake": (11.030, 57.030), "sea": (11.100, 57.100)}
with tempfile.TemporaryDirectory() as folder:
    given = os.path.join(folder, "wells.csv")
    with open(given, "w") as f:
        f.write("name,lon,lat\n" + "".join(f"{n},{lon},{lat}\n" for n, (lon, lat) in wells.items()))
    sampled = os.path.join(folder, "wells_omega.csv")
    program = os.environ.get("SAGE_EXECUTABLE", os.path.join(here, "..", "..", "build", "cli", "sage"))
    subprocess.run([program, "sample", island.source, given, "-o", sampled, "--points-crs", "EPSG:4326", "-q"],
                   check=True)
    rows = np.genfromtxt(sampled, delimiter=",", names=True, dtype=None, encoding="utf-8")
for row in rows:
    print(f"well {row['name']}: omega {row['omega']:.1f} m, gradient ({row['grad_x']:.3f}, {row['grad_y']:.3f})")
omega_at = {row["name"]: row["omega"] for row in rows}
assert omega_at["farm"] > 0 > omega_at["lake"] and omega_at["sea"] < 0, "the farm on land, the lake and the sea not"

# 4. The same field at points of the plane, straight from numpy (here the grid's centre row).
row = grid["y"].size // 2
points = np.column_stack([grid["x"], np.full(grid["x"].size, grid["y"][row])])
at = island.evaluate(points, order=1)
assert np.allclose(at["omega"], omega[row], atol=1e-6), "evaluate() and sample() agree"

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("no matplotlib: no picture (Debian: python3-matplotlib)")
    sys.exit(0)
out = os.path.join(sys.argv[1] if len(sys.argv) > 1 else ".", "island_wells.png")
x, y = grid["x"], grid["y"]
plt.contourf(x, y, omega, levels=30, cmap="RdBu")
plt.contour(x, y, omega, levels=[0.0], colors="k")
plt.gca().set_aspect("equal")
plt.colorbar(label="omega (m)")
plt.savefig(out, dpi=120)
print(f"wrote {out}")
