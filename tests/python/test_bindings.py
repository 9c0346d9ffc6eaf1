"""The Python module `zbrdf` (python/, docs/python.md) against the `zbrdf` command line.

The bindings call the code the CLI runs, so they are checked against the CLI on the same inputs:
`zbrdf eval` on the same direction pairs (a measured network, an analytic model, MERL, D-BRDF and
SH files, a session), `zbrdf export` byte for byte, `zbrdf fit --json` field for field, and the
CLI's error messages. CTest runs this file with PYTHONPATH=<build>/python and ZBRDF_CLI naming the
binary (python/CMakeLists.txt); by hand:

    PYTHONPATH=build/python ZBRDF_CLI=build/zbrdf /usr/bin/python3 -m unittest -v \
        tests/python/test_bindings.py
"""

import json
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np

import zbrdf

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def cli_path():
    """The zbrdf binary: $ZBRDF_CLI, else the one beside <build>/python on PYTHONPATH."""
    if os.environ.get("ZBRDF_CLI"):
        return os.environ["ZBRDF_CLI"]
    module_dir = os.path.dirname(os.path.abspath(zbrdf.__file__))
    return os.path.join(os.path.dirname(module_dir), "zbrdf")


def run_cli(*args, check=True):
    result = subprocess.run([cli_path(), *args], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise AssertionError("zbrdf %s failed (%d): %s" % (" ".join(args), result.returncode,
                                                          result.stderr))
    return result


def random_pairs(count, seed):
    """(count, 4) angle pairs theta_i phi_i theta_o phi_o in radians; theta up to 100 deg, so
    that some directions lie below the horizon (f_r = 0 there, in both)."""
    rng = np.random.default_rng(seed)
    theta = rng.uniform(0.0, np.radians(100.0), size=(count, 2))
    phi = rng.uniform(0.0, 2.0 * np.pi, size=(count, 2))
    return np.stack([theta[:, 0], phi[:, 0], theta[:, 1], phi[:, 1]], axis=1)


def cli_eval(source, pairs, folder):
    """`zbrdf eval SOURCE` at the pairs: (angles as echoed (N, 4), f_r (N, 3))."""
    pairs_path = os.path.join(folder, "pairs.txt")
    with open(pairs_path, "w") as f:
        # repr() is the shortest text that reads back to the same double (std::from_chars too).
        for row in pairs:
            f.write(" ".join(repr(float(v)) for v in row) + "\n")
    out = run_cli("eval", source, "--pairs", pairs_path, "--format", "csv").stdout
    # %.17g round-trips a double, and float() reads it back exactly.
    table = np.loadtxt(out.splitlines(), delimiter=",", skiprows=1, ndmin=2)
    return table[:, :4], table[:, 4:]


class TempFolderTest(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp(prefix="zbrdf-python-test-")
        self.addCleanup(shutil.rmtree, self.folder, True)


class EvalAgainstCliTest(TempFolderTest):
    """brdf.eval equals `zbrdf eval` exactly: both build directions with the same function
    (zbrdf.direction is basis/vec3.h's SphericalDirection, which `zbrdf eval` applies to its
    input) and evaluate them through Brdf::EvalBatch in the same chunks, and %.17g round-trips
    a double. Any difference is a binding error, not rounding, so the tolerance is zero."""

    def assert_eval_matches_cli(self, source, seed=1, count=300):
        pairs = random_pairs(count, seed)
        angles, expected = cli_eval(source, pairs, self.folder)
        np.testing.assert_array_equal(angles, pairs)  # the CLI read what was written
        brdf = zbrdf.load(source)
        w_i = zbrdf.direction(pairs[:, 0], pairs[:, 1])
        w_o = zbrdf.direction(pairs[:, 2], pairs[:, 3])
        f = brdf.eval(w_i, w_o)
        self.assertEqual(f.shape, (count, 3))
        self.assertEqual(f.dtype, np.float64)
        np.testing.assert_array_equal(f, expected, err_msg=source)
        below = (pairs[:, 0] >= np.pi / 2) | (pairs[:, 2] >= np.pi / 2)
        self.assertTrue(below.any() and (~below).any())
        self.assertTrue((f[below] == 0).all())
        self.assertTrue((f[~below] > 0).any())
        return brdf

    def test_measured_network(self):
        brdf = self.assert_eval_matches_cli("merl:blue-acrylic")
        self.assertEqual(brdf.spec, "merl:blue-acrylic")
        self.assertEqual(brdf.kind, "spec")

    def test_analytic_model(self):
        brdf = self.assert_eval_matches_cli("ggx:alpha=0.2,F0=0.04,kd=0.1,0.2,0.5", seed=2)
        # The canonical spec recreates the same model (brdf/material_spec.h).
        self.assertTrue(brdf.spec.startswith("ggx:"))
        self.assert_eval_matches_cli(brdf.spec, seed=2)

    def test_merl_file_exported_by_the_cli(self):
        path = os.path.join(self.folder, "gold.binary")
        run_cli("export", "merl:gold-metallic-paint", "--format", "merl", "--out", path)
        brdf = self.assert_eval_matches_cli(path, seed=3)
        self.assertEqual(brdf.kind, "merl-file")

    def test_dbrdf_file_and_its_reader(self):
        path = os.path.join(self.folder, "d.exr")
        spec = "dbrdf:c=0.8,0.9,1,F0=0.05,kd=0.1,0.2,0.3,theta_samples=4,p=3,2,1,0.5"
        run_cli("export", spec, "--format", "dbrdf", "--out", path)
        brdf = self.assert_eval_matches_cli(path, seed=4)
        self.assertEqual(brdf.kind, "dbrdf-file")
        d = zbrdf.read_dbrdf(path)
        self.assertEqual(d["p"].shape, (4, 1))
        np.testing.assert_allclose(d["theta_h_rad"], np.linspace(0, np.pi / 2, 4), rtol=0,
                                   atol=1e-15)
        # Stored in float32 (brdf/dbrdf_file.h): the values come back to float precision.
        np.testing.assert_allclose(d["kd"], [0.1, 0.2, 0.3], rtol=1e-7)
        self.assertAlmostEqual(d["f0"], 0.05, delta=1e-7)
        self.assertEqual(d["spec"], brdf.spec)
        # p is normalized: integral p(h) cos(theta_h) dw_h = 1. The table is linear in theta_h
        # between nodes; Simpson's rule on 4001 points integrates it to ~1e-7 (the kinks at the
        # nodes cost O(h^2)).
        theta = np.linspace(0, np.pi / 2, 4001)
        p = np.interp(theta, d["theta_h_rad"], d["p"][:, 0])
        g = p * np.cos(theta) * np.sin(theta) * 2 * np.pi
        h = theta[1] - theta[0]
        simpson = h / 3 * (g[0] + g[-1] + 4 * g[1:-1:2].sum() + 2 * g[2:-1:2].sum())
        self.assertAlmostEqual(simpson, 1.0, delta=1e-6)

    def test_single_directions_and_broadcasting(self):
        brdf = zbrdf.load("lambert:0.5,0.4,0.3")
        w = zbrdf.direction(0.3, 1.0)
        self.assertEqual(w.shape, (3,))
        f = brdf.eval(w, w)
        self.assertEqual(f.shape, (3,))
        # Lambert's closed form: albedo / pi.
        np.testing.assert_allclose(f, np.array([0.5, 0.4, 0.3]) / np.pi, rtol=1e-15)
        many = zbrdf.direction(np.linspace(0.1, 1.2, 7), 0.0)
        self.assertEqual(brdf.eval(many, w).shape, (7, 3))
        self.assertEqual(brdf.eval(w, many).shape, (7, 3))
        theta, phi = zbrdf.angles(many)
        np.testing.assert_allclose(theta, np.linspace(0.1, 1.2, 7), rtol=0, atol=1e-15)
        np.testing.assert_allclose(phi, 0.0, atol=1e-15)
        # No rows give no rows (a mask that selected nothing, say).
        self.assertEqual(brdf.eval(np.zeros((0, 3)), w).shape, (0, 3))
        self.assertEqual(brdf.pdf(w, np.zeros((0, 3))).shape, (0,))
        # Lists and float32 arrays are converted; float32 rounding is within the unit tolerance.
        self.assertEqual(brdf.eval(many.astype(np.float32), [0.0, 0.0, 1.0]).shape, (7, 3))


class SamplingTest(unittest.TestCase):
    SPECS = ["merl:blue-acrylic", "ggx:alpha=0.2,F0=0.04,kd=0.1", "lambert:0.5",
             "ward:rho_d=0.1,rho_s=0.05,alpha_x=0.1,alpha_y=0.3",
             "dbrdf:c=1,F0=0.04,kd=0.1,theta_samples=3,p=2,1,0.5"]

    def view_directions(self, count, rng):
        theta = np.arccos(rng.uniform(0.05, 1.0, count))
        return zbrdf.direction(theta, rng.uniform(0, 2 * np.pi, count))

    def test_the_density_of_a_sample_is_pdf_of_it(self):
        rng = np.random.default_rng(5)
        for spec in self.SPECS:
            brdf = zbrdf.load(spec)
            w_o = self.view_directions(4000, rng)
            w_i, pdf = brdf.sample(w_o, rng.uniform(0, 1, (4000, 3)))
            self.assertEqual(w_i.shape, (4000, 3))
            self.assertEqual(pdf.shape, (4000,))
            self.assertTrue((pdf > 0).all(), spec)
            # Unit vectors to rounding (a few ulps of the normalizations in the samplers).
            np.testing.assert_allclose(np.linalg.norm(w_i, axis=1), 1.0, rtol=0, atol=1e-14)
            # Sample() and Pdf() may evaluate the mixture in another order: a few ulps.
            np.testing.assert_allclose(brdf.pdf(w_o, w_i), pdf, rtol=1e-12, atol=0,
                                       err_msg=spec)

    def test_the_density_integrates_to_one_over_the_sphere(self):
        # Monte Carlo over uniform directions on the sphere, independent of the samplers: the
        # tolerance is 5 standard errors of the estimate.
        rng = np.random.default_rng(6)
        count = 200000
        z = rng.uniform(-1, 1, count)
        phi = rng.uniform(0, 2 * np.pi, count)
        r = np.sqrt(1 - z * z)
        w_i = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
        w_o = zbrdf.direction(0.6, 0.4)
        for spec in ["ggx:alpha=0.3,F0=0.04,kd=0.2", "merl:blue-acrylic"]:
            values = 4 * np.pi * zbrdf.load(spec).pdf(w_o, w_i)
            error = values.std() / np.sqrt(count)
            self.assertLess(abs(values.mean() - 1.0), 5 * error + 1e-3, spec)

    def test_a_mirror_samples_the_reflection(self):
        brdf = zbrdf.load("mirror:0.9")
        self.assertTrue(brdf.is_delta)
        w_o = zbrdf.direction(0.4, 1.1)
        w_i, pdf = brdf.sample(w_o, [0.5, 0.5, 0.5])
        np.testing.assert_allclose(w_i, [-w_o[0], -w_o[1], w_o[2]], atol=1e-15)
        self.assertEqual(float(pdf), 1.0)  # a probability, not a density (brdf/brdf.h)
        self.assertEqual(float(brdf.pdf(w_o, w_i)), 0.0)


class BadInputTest(unittest.TestCase):
    def setUp(self):
        self.brdf = zbrdf.load("ggx:alpha=0.2")
        self.w = zbrdf.direction(np.array([0.1, 0.2, 0.3, 0.4]), 0.0)

    def test_wrong_shapes_name_the_argument_and_the_shape(self):
        with self.assertRaisesRegex(ValueError, r"w_i must be an array of shape \(N, 3\).*"
                                                r"got shape \(4, 2\)"):
            self.brdf.eval(np.zeros((4, 2)), self.w)
        with self.assertRaisesRegex(ValueError, r"w_o must be .*got shape \(2, 2, 3\)"):
            self.brdf.eval(self.w, np.zeros((2, 2, 3)))
        with self.assertRaisesRegex(ValueError, r"w_i has 4 rows and w_o 3"):
            self.brdf.eval(self.w, self.w[:3])
        with self.assertRaisesRegex(ValueError, r"u must be an array of shape \(N, 3\)"):
            self.brdf.sample(self.w, np.zeros(4))
        with self.assertRaisesRegex(ValueError, r"w_i must be .* not numeric"):
            self.brdf.eval("up", self.w)

    def test_bad_values_name_the_row(self):
        w = self.w.copy()
        w[2] *= 2
        with self.assertRaisesRegex(ValueError, r"w_o\[2\] = .* has length 2\.0+; directions "
                                                r"must be unit vectors"):
            self.brdf.eval(self.w, w)
        w[2] = [np.nan, 0, 1]
        with self.assertRaisesRegex(ValueError, r"w_i\[2\] = \(nan, 0, 1\) is not finite"):
            self.brdf.pdf(self.w, w)
        with self.assertRaisesRegex(ValueError, r"u\[0\] = \(0, 0, 1\): uniform numbers must "
                                                r"lie in \[0, 1\)"):
            self.brdf.sample(self.w, [0.0, 0.0, 1.0])

    def test_an_unknown_material_raises_what_the_cli_says(self):
        with self.assertRaises(zbrdf.InputError) as raised:
            zbrdf.load("merl:no-such-material")
        message = str(raised.exception)
        self.assertIn("no-such-material", message)
        self.assertIsInstance(raised.exception, ValueError)
        self.assertIsInstance(raised.exception, zbrdf.Error)
        cli = run_cli("eval", "merl:no-such-material", check=False)
        self.assertNotEqual(cli.returncode, 0)
        self.assertIn(message, cli.stderr)
        with self.assertRaisesRegex(ValueError, "nope"):
            zbrdf.load("nope:alpha=1")
        with self.assertRaises(TypeError):
            zbrdf.load(42)


class FitInputTest(TempFolderTest):
    def test_a_folder_without_zonal_data_raises_what_the_cli_says(self):
        with self.assertRaises(ValueError) as raised:
            zbrdf.fit(self.folder, "ggx", write=False)
        self.assertIn("zonal.exr", str(raised.exception))
        cli = run_cli("fit", self.folder, "--model", "ggx", "--no-write", check=False)
        self.assertIn(str(raised.exception), cli.stderr)
        with self.assertRaisesRegex(ValueError, "table must be auto, 1d or 2d"):
            zbrdf.fit(self.folder, "dbrdf", table="3d")


class ExportTest(TempFolderTest):
    def test_export_writes_what_the_cli_writes(self):
        ours = os.path.join(self.folder, "ours.binary")
        theirs = os.path.join(self.folder, "theirs.binary")
        report = zbrdf.export("merl:gold-metallic-paint", "merl", ours)
        run_cli("export", "merl:gold-metallic-paint", "--format", "merl", "--out", theirs)
        self.assertEqual(report["files"], [ours])
        self.assertEqual(report["format"], "merl")
        with open(ours, "rb") as a, open(theirs, "rb") as b:
            self.assertTrue(a.read() == b.read(), "the two MERL tables differ")
        # A loaded Brdf exports too.
        brdf = zbrdf.load("ggx:alpha=0.2,F0=0.9")
        explorer = os.path.join(self.folder, "ggx.brdf")
        self.assertEqual(zbrdf.export(brdf, "brdf-explorer", explorer)["files"], [explorer])
        self.assertEqual(zbrdf.load(explorer).kind, "brdf-explorer-file")

    def test_export_errors_are_the_cli_errors(self):
        out = os.path.join(self.folder, "x.exr")
        with self.assertRaises(ValueError) as raised:
            zbrdf.export("ggx:alpha=0.2", "dbrdf", out)
        cli = run_cli("export", "ggx:alpha=0.2", "--format", "dbrdf", "--out", out, check=False)
        self.assertIn(str(raised.exception), cli.stderr)
        self.assertFalse(os.path.exists(out))
        with self.assertRaisesRegex(ValueError, "brdf-explorer"):
            zbrdf.export("ggx:alpha=0.2", "png", out)


class SessionTest(unittest.TestCase):
    """A small simulated session (order 2, fast preset: about 1 s with the build tree's cache,
    7 s without), fitted by the bindings once (writing fit-ggx.json), then compared with the
    CLI's fit, evaluation, conversion and files."""

    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="zbrdf-python-session-")
        cls.session = os.path.join(cls.folder, "ggx")
        run_cli("simulate", "--rig", os.path.join(SOURCE_DIR, "rig", "rigs", "thesis.yaml"),
                "--material", "ggx:alpha=0.3,F0=0.04,kd=0.2", "--order", "2", "--preset", "fast",
                "--exposures", "1", "--no-hdr-images", "--truth-samples", "256", "--out",
                cls.session)
        cls.report, cls.fitted = zbrdf.fit(cls.session, "ggx", return_model=True)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.folder, True)

    def test_fit_reports_what_the_cli_reports(self):
        theirs = json.loads(run_cli("fit", self.session, "--model", "ggx", "--no-write",
                                    "--json").stdout)
        self.assertEqual(self.report["model"], "ggx")
        # The same code on the same data: the fits agree to the solver's own reproducibility.
        for key in ["alpha", "F0", "kd"]:
            np.testing.assert_allclose(self.report["params"][key], theirs["params"][key],
                                       rtol=1e-9)
        np.testing.assert_allclose(self.report["error_cosine_l2"], theirs["error_cosine_l2"],
                                   rtol=1e-9)
        # With --no-write the CLI lists no outputs; every other key is the same.
        self.assertIn("outputs", self.report)
        self.assertEqual(sorted(set(self.report) - {"outputs"}), sorted(theirs))
        self.assertEqual(self.fitted.spec, self.report["spec"])
        self.assertEqual(self.fitted.kind, "fit")

    def test_a_fitted_session_evaluates_as_in_the_cli(self):
        self.assertTrue(os.path.exists(os.path.join(self.session, "fit-ggx.json")))
        pairs = random_pairs(200, 7)
        with tempfile.TemporaryDirectory() as folder:
            _, expected = cli_eval(self.session, pairs, folder)
        brdf = zbrdf.load(self.session)
        self.assertEqual(brdf.kind, "session")
        self.assertEqual(brdf.spec, self.report["spec"])
        f = brdf.eval(zbrdf.direction(pairs[:, 0], pairs[:, 1]),
                      zbrdf.direction(pairs[:, 2], pairs[:, 3]))
        np.testing.assert_array_equal(f, expected)

    def test_zonal_and_sh_files(self):
        zonal = zbrdf.read_zonal(os.path.join(self.session, "zonal.exr"))
        self.assertEqual(zonal["order"], 2)
        self.assertEqual(zonal["tensor"].shape, (3, 9, 9))
        self.assertEqual(zonal["tensor_variance"].shape, (3, 9, 9))
        self.assertEqual(zonal["lm"].tolist()[:4], [[0, 0], [1, -1], [1, 0], [1, 1]])
        grid = zonal["grid"]
        self.assertEqual(zonal["value"].shape, (9, 3, grid["n_theta"], grid["n_phi"]))
        self.assertTrue(np.isfinite(zonal["tensor"]).all())
        self.assertTrue((zonal["tensor_variance"] >= 0).all())
        self.assertLess(zonal["theta_min_rad"], zonal["theta_max_rad"])
        # The constant term is the largest: the l = 0 moment of a positive, smooth function.
        self.assertEqual(np.unravel_index(np.abs(zonal["tensor"][0]).argmax(), (9, 9)), (0, 0))

        run_cli("convert", self.session, "--to", "sh", "--target", "hsh")
        path = os.path.join(self.session, "sh-hsh.exr")
        sh = zbrdf.read_sh(path)
        self.assertEqual((sh["target"], sh["order"]), ("hsh", 2))
        n = sh["lm"].shape[0]
        self.assertEqual(sh["coefficients"].shape, (3, n, n))
        self.assertEqual(sh["exitant"].shape[0], 3)
        self.assertEqual(sh["exitant"].shape[3], n)
        pairs = random_pairs(100, 8)
        with tempfile.TemporaryDirectory() as folder:
            _, expected = cli_eval(path, pairs, folder)
        f = zbrdf.load(path).eval(zbrdf.direction(pairs[:, 0], pairs[:, 1]),
                                  zbrdf.direction(pairs[:, 2], pairs[:, 3]))
        np.testing.assert_array_equal(f, expected)


class ModuleTest(unittest.TestCase):
    def test_version_is_the_cli_version(self):
        self.assertEqual(run_cli("version").stdout.split()[1], zbrdf.__version__)


if __name__ == "__main__":
    unittest.main()
