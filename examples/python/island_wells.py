"""The distance-like field of an island, at wells and on a grid, from Python.

A GIS analyst's session with `import sage`, geopandas and matplotlib:
read the island of examples/models/island_with_lake.geojson (longitude/
latitude) as a GeoDataFrame, build its normalized field omega, take omega
and its gradient at a few wells, save them in a GeoPackage and read it
back, and draw the field with the coast and the wells into
island_wells.png.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/island_wells.py [OUT_DIR]

It checks its own results: omega > 0 on the island, < 0 in its lake and
at sea, and |grad omega| = 1 on the coast (a normalized field). Without
geopandas or matplotlib (Debian: python3-geopandas, python3-matplotlib) it
exits with 77, which CTest reports as skipped.
"""
import os
import sys

import numpy as np

import sage

try:
    import geopandas as gpd
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as missing:
    print(f"skipped: {missing.name} is not installed")
    sys.exit(77)

here = os.path.dirname(os.path.abspath(__file__))
out_dir = sys.argv[1] if len(sys.argv) > 1 else "."

# 1. The island as geopandas reads it, then its field. sage projects
# longitude/latitude to a local azimuthal projection in metres.
land = gpd.read_file(os.path.join(here, "..", "models", "island_with_lake.geojson"))
island = sage.from_wkb(land.unary_union.wkb, crs=land.crs.to_wkt())
print(f"{island!r} in \"{island.crs_wkt.split(chr(34))[1]}\"")

# 2. The field on a grid of 50 m pixels, in the island's plane.
grid = island.sample(resolution=50.0, bounds=(-3000.0, 3000.0, -3500.0, 3500.0))
omega = grid["omega"]
print(f"grid {omega.shape[1]} x {omega.shape[0]} pixels of 50 m; {grid['evaluation']}")

# 3. Normalized: |grad omega| = 1 on the coast. Where the coast crosses the
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

# 4. Wells in longitude/latitude, brought into the field's plane by
# geopandas (its CRS is the one sage reports), then evaluated.
wells = gpd.GeoDataFrame({"name": ["farm", "lake", "sea"]},
                         geometry=gpd.points_from_xy([11.004, 11.030, 11.075], [57.030, 57.030, 57.045]),
                         crs="EPSG:4326")
planar = wells.to_crs(island.crs_wkt)
at = island.evaluate(np.column_stack([planar.geometry.x, planar.geometry.y]))
wells["omega"], wells["grad_x"], wells["grad_y"] = at["omega"], at["grad"][:, 0], at["grad"][:, 1]
saved = os.path.join(out_dir, "island_wells.gpkg")
wells.to_file(saved, layer="wells", driver="GPKG")
back = gpd.read_file(saved, layer="wells")
for _, well in back.iterrows():
    print(f"well {well['name']}: omega {well['omega']:.1f} m, gradient ({well['grad_x']:.3f}, {well['grad_y']:.3f})")
assert np.array_equal(back["omega"].to_numpy(), at["omega"]), "the GeoPackage keeps the values whole"
omega_at = dict(zip(back["name"], back["omega"]))
assert omega_at["farm"] > 0 > omega_at["lake"] and omega_at["sea"] < 0, "the farm on land, the lake and the sea not"

# 5. The picture: omega, the coast (omega = 0) and the wells.
figure, axes = plt.subplots(figsize=(6, 7))
filled = axes.contourf(grid["x"], grid["y"], omega, levels=np.linspace(-600, 600, 25), cmap="RdBu", extend="both")
axes.contour(grid["x"], grid["y"], omega, levels=[0.0], colors="k")
axes.plot(planar.geometry.x, planar.geometry.y, "k^")
axes.set_aspect("equal")
figure.colorbar(filled, label="omega (m)")
picture = os.path.join(out_dir, "island_wells.png")
figure.savefig(picture, dpi=100)
print(f"wrote {saved} and {picture}")
