"""The Python module `sage` against the command line and the mathematics.

Run by CTest (python.module) with PYTHONPATH at the built module,
SAGE_EXECUTABLE the `sage` program and SAGE_SOURCE_DIR the checkout.
"""
import math
import os
import subprocess
import tempfile
import unittest

import numpy as np

import sage

SOURCE = os.environ.get("SAGE_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
SAGE = os.environ.get("SAGE_EXECUTABLE", "sage")
PLATE = os.path.join(SOURCE, "examples", "models", "plate_with_holes.json")
ISLAND = os.path.join(SOURCE, "examples", "models", "island_with_lake.geojson")
DISK = os.path.join(SOURCE, "examples", "problems", "disk.json")
BRACKET_STEP = os.path.join(SOURCE, "examples", "models", "l_bracket.step")


class ModelTest(unittest.TestCase):
    def test_evaluate_equals_the_command_line(self):
        """Model.evaluate and `sage sample` at the same points: the same bits, exact or not.

        The GeoPackage that `sage sample` writes keeps doubles whole; sqlite3 reads them back.
        """
        import sqlite3
        model = sage.load(PLATE)
        self.assertEqual(model.dimension, 2)
        rng = np.random.default_rng(7)
        points = rng.uniform([-2.2, -1.2], [2.2, 1.2], size=(2000, 2))
        for flags, exact in (([], False), (["--exact"], True)):
            ours = model.evaluate(points, order=2, exact=exact)
            self.assertIn("exact" if exact else "far-field", ours["evaluation"])
            with tempfile.TemporaryDirectory() as folder:
                given = os.path.join(folder, "points.csv")
                with open(given, "w") as f:
                    f.write("x,y\n")
                    for x, y in points:
                        f.write(f"{x!r},{y!r}\n")
                written = os.path.join(folder, "out.gpkg")
                subprocess.run([SAGE, "sample", PLATE, given, "-o", written, "--order", "2", "-q"] + flags,
                               check=True)
                with sqlite3.connect(written) as db:
                    rows = db.execute("SELECT omega, grad_x, grad_norm, d2_xy FROM points ORDER BY fid").fetchall()
            theirs = np.array(rows)
            self.assertEqual(theirs.shape, (2000, 4))
            for k, column in enumerate((ours["omega"], ours["grad"][:, 0], ours["grad_norm"], ours["d2_xy"])):
                np.testing.assert_array_equal(column, theirs[:, k], err_msg=f"column {k}, exact={exact}")

    def test_gradient_is_the_derivative(self):
        model = sage.load(PLATE)
        points = np.array([[0.3, -0.5], [-1.7, 0.8], [1.9, 0.1]])
        step = 1e-6
        r = model.evaluate(points)
        for axis in range(2):
            shift = np.zeros(2)
            shift[axis] = step
            plus = model.evaluate(points + shift, order=0)["omega"]
            minus = model.evaluate(points - shift, order=0)["omega"]
            np.testing.assert_allclose(r["grad"][:, axis], (plus - minus) / (2 * step), atol=1e-6)

    def test_sample_grid_matches_evaluate(self):
        """sample(): arrays (ny, nx), row 0 at the smallest y, axes and a geotransform."""
        model = sage.load(PLATE)
        g = model.sample(grid=(41, 23), exact=True)
        self.assertEqual(g["omega"].shape, (23, 41))
        self.assertEqual(g["grad"].shape, (23, 41, 2))
        x, y = g["x"], g["y"]
        self.assertAlmostEqual(x[0], -2.2)
        self.assertAlmostEqual(y[-1], 1.2)
        xx, yy = np.meshgrid(x, y)
        at = model.evaluate(np.column_stack([xx.ravel(), yy.ravel()]))
        np.testing.assert_allclose(g["omega"].ravel(), at["omega"], rtol=0, atol=1e-12)
        origin_x, dx, _, origin_y, _, dy = g["geotransform"]
        self.assertAlmostEqual(origin_x + 0.5 * dx, x[0])
        self.assertAlmostEqual(origin_y + 0.5 * dy, y[0])
        self.assertIn("exact", g["evaluation"])
        by_spacing = model.sample(resolution=0.1, order=0)
        self.assertAlmostEqual(by_spacing["x"][1] - by_spacing["x"][0], 0.1)
        self.assertNotIn("grad", by_spacing)

    def test_gis_polygons_are_projected(self):
        """Longitude/latitude polygons: a plane in metres, its CRS as WKT, unit gradient on the coast."""
        island = sage.load(ISLAND)
        self.assertIn("azimuthal", island.crs_wkt.lower())
        (xmin, ymin), (xmax, ymax) = island.bounds
        self.assertGreater(xmax - xmin, 1000.0)
        g = island.sample(grid=(200, 200))
        # Where the coast crosses the middle row: found by bisection, |grad omega| = 1 there.
        row = 100
        y, x, omega = g["y"][row], g["x"], g["omega"][row]
        crossings = np.nonzero(np.sign(omega[:-1]) != np.sign(omega[1:]))[0]
        self.assertGreaterEqual(len(crossings), 2)
        for i in crossings:
            a, b = x[i], x[i + 1]
            side = np.sign(omega[i])
            for _ in range(60):
                middle = 0.5 * (a + b)
                if np.sign(island.evaluate(np.array([[middle, y]]), order=0)["omega"][0]) == side:
                    a = middle
                else:
                    b = middle
            at = island.evaluate(np.array([[a, y]]))
            self.assertLess(abs(at["omega"][0]), 1e-6)
            self.assertAlmostEqual(at["grad_norm"][0], 1.0, places=6)

    def test_errors_are_exceptions_with_the_message(self):
        with self.assertRaises(sage.ModelError) as caught:
            sage.load(os.path.join(SOURCE, "no_such_model.json"))
        self.assertIn("no_such_model.json", str(caught.exception))
        self.assertTrue(issubclass(sage.ModelError, ValueError))
        model = sage.load(PLATE)
        with self.assertRaises(ValueError):
            model.evaluate(np.zeros((4, 3)))
        with self.assertRaises(ValueError):
            model.evaluate(np.zeros((4, 2)), order=9)
        with self.assertRaises(ValueError):
            model.sample(grid=(10, 10), resolution=0.1)

    def test_help_documents_the_methods(self):
        self.assertIn("exact: bool = False", sage.Model.evaluate.__doc__)
        self.assertIn("geotransform", sage.Model.sample.__doc__)
        self.assertIn("load(path", sage.load.__doc__)


def polygon_wkb(rings, multi=None):
    """WKB of a Polygon (a list of rings, each a list of (x, y)), or of a MultiPolygon of such."""
    import struct

    def one(rings):
        data = struct.pack("<BII", 1, 3, len(rings))
        for ring in rings:
            data += struct.pack("<I", len(ring)) + b"".join(struct.pack("<dd", x, y) for x, y in ring)
        return data

    if multi is None:
        return one(rings)
    return struct.pack("<BII", 1, 6, len(multi)) + b"".join(one(p) for p in multi)


def square(x0, y0, side):
    return [(x0, y0), (x0 + side, y0), (x0 + side, y0 + side), (x0, y0 + side), (x0, y0)]


class MemorySourceTest(unittest.TestCase):
    def test_geojson_dict_is_the_file(self):
        import json
        with open(ISLAND) as f:
            data = json.load(f)
        from_dict, from_file = sage.from_geojson(data), sage.load(ISLAND)
        points = np.array([[0.0, 0.0], [-1500.0, 800.0], [4000.0, 4000.0]])
        np.testing.assert_array_equal(from_dict.evaluate(points)["omega"], from_file.evaluate(points)["omega"])
        self.assertEqual(from_dict.crs_wkt, from_file.crs_wkt)

    def test_wkb_polygon_with_a_hole_and_a_multipolygon(self):
        """Planar WKB (shapely's .wkb): a square with a square hole; two squares."""
        holed = sage.from_wkb(polygon_wkb([square(0, 0, 10), square(4, 4, 2)[::-1]]))
        self.assertEqual(holed.crs_wkt, "")
        r = holed.evaluate(np.array([[1.0, 5.0], [5.0, 5.0], [5.0, 0.0], [12.0, 5.0]]))
        self.assertGreater(r["omega"][0], 0.0)  # in the frame
        self.assertLess(r["omega"][1], 0.0)     # in the hole
        self.assertAlmostEqual(r["omega"][2], 0.0, places=12)  # on the outer edge
        self.assertAlmostEqual(r["grad_norm"][2], 1.0, places=9)
        self.assertLess(r["omega"][3], 0.0)
        two = sage.from_wkb(polygon_wkb(None, multi=[[square(0, 0, 1)], [square(3, 0, 1)]]))
        omega = two.evaluate(np.array([[0.5, 0.5], [3.5, 0.5], [2.0, 0.5]]), order=0)["omega"]
        self.assertTrue(omega[0] > 0 and omega[1] > 0 and omega[2] < 0)
        with self.assertRaises(ValueError):
            sage.from_wkb(b"not wkb")

    def test_mesh_from_arrays(self):
        """A unit cube from numpy arrays; an open one is refused with the mesh's message."""
        vertices = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=float)
        triangles = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                              [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
        cube = sage.from_mesh(vertices, triangles)
        self.assertEqual(cube.dimension, 3)
        omega = cube.evaluate(np.array([[0.5, 0.5, 0.5], [2.0, 0.5, 0.5], [0.5, 0.5, 0.0]]), order=0)["omega"]
        self.assertGreater(omega[0], 0.0)
        self.assertLess(omega[1], 0.0)
        self.assertAlmostEqual(omega[2], 0.0, places=12)
        with self.assertRaises(sage.ModelError) as caught:
            sage.from_mesh(vertices, triangles[:-1])
        self.assertIn("mesh from Python", str(caught.exception))


@unittest.skipUnless("OpenCASCADE" in subprocess.run([SAGE, "--version"], capture_output=True, text=True).stdout,
                     "sage built without OpenCASCADE")
class CadTest(unittest.TestCase):
    def test_cad_part_and_its_faces(self):
        """The bundled STEP bracket: its faces as the command line lists them, and its field's signs."""
        bracket = sage.load(BRACKET_STEP)
        self.assertEqual(bracket.unit, "millimetre")
        faces = bracket.faces
        self.assertEqual(len(faces), 15)
        bolts = [f for f in faces if f["surface"] == "cylinder" and abs(f["radius"] - 4) < 1e-9]
        self.assertEqual(len(bolts), 2)
        self.assertAlmostEqual(bolts[0]["area"], 2 * math.pi * 4 * 8, places=6)
        self.assertEqual(bolts[0]["colour"], "")  # the bracket's file gives no colours
        info = subprocess.run([SAGE, "info", BRACKET_STEP], capture_output=True, text=True, check=True).stdout
        self.assertIn("%d  cylinder  radius 4" % bolts[0]["number"], info)
        omega = bracket.evaluate(np.array([[40.0, 20.0, 4.0], [45.0, 20.0, 4.0], [40.0, 20.0, 30.0]]), order=0)["omega"]
        self.assertGreater(omega[0], 0.0)  # in the base
        self.assertLess(omega[1], 0.0)  # in a bolt hole
        self.assertLess(omega[2], 0.0)  # above the base, beside the upright
        # The field is exact on the faces: zero on a bolt hole's cylinder (radius 4 about x = 45, y = 20).
        on_hole = bracket.evaluate(np.array([[45.0 + 4.0 * math.cos(0.3), 20.0 + 4.0 * math.sin(0.3), 4.0]]), order=0)
        self.assertLess(abs(on_hole["omega"][0]), 1e-12)
        self.assertTrue(any(n.startswith("exact field") for n in bracket.notes))
        coarse = sage.load(BRACKET_STEP, deflection=0.5)
        self.assertTrue(any("chordal deflection 0.5 millimetre" in n for n in coarse.notes))
        with self.assertRaises(ValueError):
            sage.load(BRACKET_STEP, solid=0)
        with self.assertRaises(sage.ModelError) as caught:
            sage.load(BRACKET_STEP, solid=2)
        self.assertIn("the file has 1 solid(s)", str(caught.exception))


def available(module):
    import importlib.util
    return importlib.util.find_spec(module) is not None


@unittest.skipUnless(available("shapely") and available("geopandas"), "needs python3-shapely and python3-geopandas")
class ShapelyGeopandasTest(unittest.TestCase):
    def test_shapely_polygon_with_a_hole_and_a_multipolygon(self):
        from shapely.geometry import MultiPolygon, Polygon
        frame = Polygon([(0, 0), (10, 0), (10, 10), (0, 10)], [[(4, 4), (4, 6), (6, 6), (6, 4)]])
        model = sage.from_wkb(frame.wkb)
        r = model.evaluate(np.array([[1.0, 5.0], [5.0, 5.0], [5.0, 0.0]]), exact=True)
        self.assertGreater(r["omega"][0], 0.0)
        self.assertLess(r["omega"][1], 0.0)
        self.assertEqual(r["omega"][2], 0.0)
        two = sage.from_wkb(MultiPolygon([frame, Polygon([(20, 0), (21, 0), (21, 1), (20, 1)])]).wkb)
        self.assertGreater(two.evaluate(np.array([[20.5, 0.5]]), order=0)["omega"][0], 0.0)

    def test_self_intersecting_polygon_names_its_ring_and_vertex(self):
        """A bow tie: the same message as the command line's for the same polygon in a file."""
        from shapely.geometry import Polygon, mapping
        import json
        bowtie = Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
        with self.assertRaises(sage.ModelError) as caught:
            sage.from_wkb(bowtie.wkb)
        message = str(caught.exception)
        self.assertIn("ring 0 (exterior), vertex", message)
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "bowtie.geojson")
            with open(path, "w") as f:
                json.dump({"type": "Feature", "properties": {}, "geometry": mapping(bowtie)}, f)
            cli = subprocess.run([SAGE, "info", path, "--crs", "EPSG:32633"], capture_output=True, text=True)
        self.assertEqual(cli.returncode, 1)
        self.assertIn(message.split(": ", 1)[1], cli.stderr)

    def test_geopandas_round_trip(self):
        """Points of a GeoDataFrame in lon/lat, to the field's plane with geopandas, evaluated, saved, read back."""
        import geopandas as gpd
        island = sage.load(ISLAND)
        wells = gpd.GeoDataFrame({"name": ["farm", "lake", "sea"]},
                                 geometry=gpd.points_from_xy([11.004, 11.030, 11.100], [57.030, 57.030, 57.100]),
                                 crs="EPSG:4326")
        planar = wells.to_crs(island.crs_wkt)
        at = island.evaluate(np.column_stack([planar.geometry.x, planar.geometry.y]))
        with tempfile.TemporaryDirectory() as folder:
            # The wells through `sage sample`, which projects them itself.
            given, sampled = os.path.join(folder, "wells.gpkg"), os.path.join(folder, "sampled.gpkg")
            wells.to_file(given, driver="GPKG")
            subprocess.run([SAGE, "sample", ISLAND, given, "-o", sampled, "-q"], check=True)
            theirs = gpd.read_file(sampled)
            # And ours, saved and read back.
            wells["omega"] = at["omega"]
            path = os.path.join(folder, "evaluated.gpkg")
            wells.to_file(path, driver="GPKG")
            back = gpd.read_file(path)
        self.assertEqual(list(theirs["name"]), ["farm", "lake", "sea"])
        np.testing.assert_array_equal(back["omega"].to_numpy(), at["omega"])
        np.testing.assert_allclose(theirs["omega"].to_numpy(), at["omega"], rtol=1e-9, atol=1e-6)
        self.assertTrue(at["omega"][0] > 0 > at["omega"][1] and at["omega"][2] < 0)


@unittest.skipUnless(available("osgeo"), "needs python3-gdal")
class GeoTiffTest(unittest.TestCase):
    def test_geotiff_read_back_with_gdal(self):
        """`sage field -o .tif`: CRS, geotransform, band names, values of Model.sample, the coast on omega = 0."""
        from osgeo import gdal, osr
        island = sage.load(ISLAND)
        with tempfile.TemporaryDirectory() as folder:
            tif = os.path.join(folder, "island.tif")
            subprocess.run([SAGE, "field", ISLAND, "-o", tif, "--resolution", "25", "-q"], check=True)
            raster = gdal.Open(tif)
            names = [raster.GetRasterBand(b + 1).GetDescription() for b in range(raster.RasterCount)]
            omega = raster.GetRasterBand(1).ReadAsArray().astype(np.float64)
            transform = raster.GetGeoTransform()
            wkt = raster.GetProjection()
        self.assertEqual(names[:4], ["omega", "grad_omega_x", "grad_omega_y", "grad_norm"])
        self.assertTrue(osr.SpatialReference(wkt).IsSame(osr.SpatialReference(island.crs_wkt)))
        g = island.sample(resolution=25.0)
        self.assertAlmostEqual(transform[1], 25.0)
        self.assertAlmostEqual(transform[5], -25.0)  # north-up
        self.assertAlmostEqual(transform[0], g["geotransform"][0])
        expected = np.flipud(g["omega"])
        self.assertEqual(omega.shape, expected.shape)
        np.testing.assert_allclose(omega, expected.astype(np.float32), rtol=1e-6, atol=1e-3)
        # The polygons' vertices (lon/lat, projected as sage projects them) lie on omega's zero
        # contour to a pixel: omega changes sign among the pixels around each.
        import json
        with open(ISLAND) as f:
            rings = [ring for feature in json.load(f)["features"]
                     for polygon in feature["geometry"]["coordinates"] for ring in polygon]
        source = osr.SpatialReference()
        source.ImportFromEPSG(4326)
        source.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
        target = osr.SpatialReference(island.crs_wkt)
        target.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
        project = osr.CoordinateTransformation(source, target)
        for ring in rings:
            for lon, lat in ring:
                x, y, _ = project.TransformPoint(lon, lat)
                column = int((x - transform[0]) / transform[1])
                row = int((y - transform[3]) / transform[5])
                around = omega[row - 1:row + 2, column - 1:column + 2]
                self.assertTrue(around.min() < 0.0 < around.max(), f"vertex {lon}, {lat}")


class SolveTest(unittest.TestCase):
    def test_disk_from_a_file_and_from_a_dict(self):
        """The disk's manufactured solution u = sin(pi (x^2 + y^2)): the report's error and u at points."""
        points = np.array([[0.5, 0.0], [0.0, -0.3], [0.6, 0.6]])
        r = sage.solve(DISK, points, degree=3, cells=64)
        self.assertLess(r["report"]["l2_error"], 1e-5)
        with tempfile.TemporaryDirectory() as folder:
            printed = subprocess.run([SAGE, "solve", DISK, "-o", os.path.join(folder, "disk.vtu"), "--degree", "3",
                                      "--cells", "64"], check=True, capture_output=True, text=True).stdout
        cli_l2 = float(printed.split("L2 ")[1].split(",")[0])
        self.assertAlmostEqual(r["report"]["l2_error"] / cli_l2, 1.0, places=3)
        exact = np.sin(math.pi * (points ** 2).sum(axis=1))
        np.testing.assert_allclose(r["u"], exact, atol=1e-4)
        self.assertGreater(r["omega"][0], 0.0)
        import json
        with open(DISK) as f:
            problem = json.load(f)
        again = sage.solve(problem, points, degree=3, cells=64)
        np.testing.assert_array_equal(again["u"], r["u"])

    def test_solution_on_a_grid(self):
        """grid=(nx, ny): arrays (ny, nx) over the problem's box, NaN outside the disk, the same as at points."""
        r = sage.solve(DISK, degree=3, cells=32, grid=(41, 31))
        u, x, y = r["u"], r["x"], r["y"]
        self.assertEqual(u.shape, (31, 41))
        self.assertEqual(r["grad_u"].shape, (31, 41, 2))
        inside = x[None, :] ** 2 + y[:, None] ** 2 < 0.95 ** 2
        outside = x[None, :] ** 2 + y[:, None] ** 2 > 1.05 ** 2
        self.assertTrue(np.isfinite(u[inside]).all())
        self.assertTrue(np.isnan(u[outside]).all())
        at = sage.solve(DISK, np.array([[x[30], y[20]]]), degree=3, cells=32)
        self.assertEqual(at["u"][0], u[20, 30])
        with self.assertRaises(ValueError):
            sage.solve(DISK, np.zeros((1, 2)), grid=(10, 10))

    def test_elasticity_gives_stresses(self):
        bracket = os.path.join(SOURCE, "examples", "problems", "bracket.json")
        r = sage.solve(bracket, np.array([[0.0, 0.0]]), cells=48)
        self.assertGreater(r["report"]["strain_energy"], 0.0)
        self.assertEqual(r["stress"].shape, (1, 6))
        self.assertEqual(r["displacement"].shape, (1, 2))

    def test_bad_problem_is_a_problem_error(self):
        with self.assertRaises(sage.ProblemError) as caught:
            sage.solve({"domain": PLATE, "source": "x +"})
        self.assertIn("the problem dict", str(caught.exception))
        self.assertNotIn("sage-problem-", str(caught.exception))


if __name__ == "__main__":
    unittest.main()
