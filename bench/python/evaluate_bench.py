"""Model.evaluate at scattered points against Model.sample on a grid, same run.

    PYTHONPATH=build/python /usr/bin/python3 bench/python/evaluate_bench.py MODEL [N] [--repair]

Evaluates the model's field and gradient at the N x N points of a grid
over its bounds twice: as a grid (Model.sample, what `sage field` runs)
and as a list of points in random order (Model.evaluate, what `sage
sample` runs), both with the default plan (far-field patches for 2D
R-function fields) and then exactly; prints the seconds, the ratio and the
largest difference. The points are shuffled so that the list gains
nothing from the grid's order.
"""
import sys
import time

import numpy as np

import sage

path = sys.argv[1]
n = int(sys.argv[2]) if len(sys.argv) > 2 and sys.argv[2].isdigit() else 1000
model = sage.load(path, repair="--repair" in sys.argv)
print(f"{model!r}, {n} x {n} points, field and gradient")
for exact in (False, True):
    start = time.perf_counter()
    grid = model.sample(grid=(n, n), exact=exact)
    grid_seconds = time.perf_counter() - start
    xx, yy = np.meshgrid(grid["x"], grid["y"])
    points = np.column_stack([xx.ravel(), yy.ravel()])
    order = np.random.default_rng(1).permutation(len(points))
    start = time.perf_counter()
    at = model.evaluate(points[order], exact=exact)
    point_seconds = time.perf_counter() - start
    difference = np.abs(at["omega"] - grid["omega"].ravel()[order]).max()
    print(f"{'exact' if exact else 'default'}: sample {grid_seconds:.2f} s, evaluate {point_seconds:.2f} s, "
          f"ratio {point_seconds / grid_seconds:.2f}; largest difference {difference:.2e}")
    print(f"  sample: {grid['evaluation']}\n  evaluate: {at['evaluation']}")
