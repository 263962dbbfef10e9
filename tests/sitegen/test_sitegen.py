#!/usr/bin/python3
"""Tests of scripts/sitegen (the seeded barn generator). Run by hand, no build needed:

  /usr/bin/python3 -m unittest discover -s tests/sitegen -v
"""
import copy
import importlib.machinery
import importlib.util
import os
import subprocess
import sys
import tempfile
import unittest

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "sitegen")


def load_sitegen():
    loader = importlib.machinery.SourceFileLoader("sitegen", SCRIPT)
    spec = importlib.util.spec_from_loader("sitegen", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


sg = load_sitegen()


def run(*args):
    return subprocess.run([sys.executable, SCRIPT] + list(args), capture_output=True, text=True)


def same_bytes(test, kind, seed, *options):
    """Two runs of `sitegen KIND --seed SEED OPTIONS` write byte-identical files."""
    with tempfile.TemporaryDirectory() as tmp:
        for d in ("a", "b"):
            r = run(kind, "--seed", str(seed), "--out", os.path.join(tmp, d), *options)
            test.assertEqual(r.returncode, 0, r.stderr)
            test.assertEqual(r.stderr.count("sitegen: wrote"), 3, r.stderr)
        for name in ("world.yaml", "route.yaml", "scenario.yaml"):
            with open(os.path.join(tmp, "a", name), "rb") as fa, \
                    open(os.path.join(tmp, "b", name), "rb") as fb:
                test.assertEqual(fa.read(), fb.read(), name)


def expect_usage_errors(test, cases):
    """Each (args, needle): sitegen exits 2 with the needle in its message."""
    for args, needle in cases:
        with test.subTest(args=args):
            r = run(*args)
            test.assertEqual(r.returncode, 2, r.stderr)
            test.assertIn(needle, r.stderr)


class SitegenTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.sites = {(seed, err): sg.generate(seed, err) for seed in (1, 2, 3) for err in
                     (False, True)}

    def test_same_seed_gives_the_same_bytes(self):
        same_bytes(self, "barn", 11, "--error-cases")

    def test_seeds_differ(self):
        self.assertNotEqual(self.sites[(1, False)][0], self.sites[(2, False)][0])

    def test_generated_sites_pass_their_checks_and_use_every_action(self):
        for (seed, err), (world_text, route_text, scenario_text, summary) in self.sites.items():
            with self.subTest(seed=seed, error_cases=err):
                chk, problems = sg.check_texts(world_text, route_text)
                self.assertEqual(problems, [])
                self.assertGreaterEqual(chk.stripe_end_cases, 1)
                route = yaml.safe_load(route_text)
                kinds = {next(iter(a)) for a in route["actions"] if a != "until"}
                self.assertEqual(kinds, {"free_navigation", "fence_navigation", "turn",
                                         "straight", "stripe_navigation", "dock"})
                ends = {str(a.get("until")) for a in route["actions"]}
                self.assertTrue({"stripe_end", "charger_contact"} <= ends)
                self.assertTrue(any(e.startswith("{'marker'") for e in ends))
                sides = {a["fence_navigation"]["side"] for a in route["actions"]
                         if "fence_navigation" in a}
                self.assertEqual(sides, {"left", "right"})
                world = yaml.safe_load(world_text)
                scenario = yaml.safe_load(scenario_text)
                self.assertEqual(world["name"], route["map"])
                self.assertEqual(scenario["world"], "world.yaml")
                self.assertEqual(scenario["routes"], ["route.yaml"])
                self.assertEqual(scenario["jobs"][0]["route"], route["name"])
                self.assertEqual(scenario["expect"]["contacts"], 0)
                self.assertGreater(scenario["expect"]["deadline_s"], summary["nominal_s"])
                faults = {f["type"] for f in world.get("faults", [])}
                if err:
                    self.assertEqual(faults, {"wheel_slip", "hide_ultrasonic", "remove_fence",
                                              "remove_stripe"})
                else:
                    self.assertEqual(faults, set())
                    self.assertEqual(scenario["robots"][0]["initial_pose"],
                                     world["robots"][0]["pose"])

    def test_the_checks_find_a_post_in_a_fence_leg(self):
        world_text, route_text, _, _ = self.sites[(1, False)]
        chk, _ = sg.check_texts(world_text, route_text)
        # The middle of the first fence leg's path.
        a, b, i, _, _ = next(bp for bp in chk.base_paths
                             if "fence_navigation" in yaml.safe_load(route_text)["actions"][bp[2]])
        world = yaml.safe_load(world_text)
        world["cylinders"].append({"center": [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2],
                                   "radius": 0.12, "kind": "post"})
        problems = sg.Check(world, yaml.safe_load(route_text), sg.start_pose_of(world)).run()
        self.assertTrue(any("actions[%d]" % i in p and "cylinders" in p for p in problems),
                        problems)

    def test_the_checks_find_a_marker_off_its_leg(self):
        world_text, route_text, _, _ = self.sites[(2, False)]
        world = yaml.safe_load(world_text)
        m2 = next(m for m in world["markers"] if m["id"] == 2)
        yaw = m2["yaw_deg"]
        # Along the marker (across the leg) by 0.3 m.
        import math
        m2["at"] = [m2["at"][0] + 0.3 * math.cos(math.radians(yaw)),
                    m2["at"][1] + 0.3 * math.sin(math.radians(yaw))]
        problems = sg.Check(world, yaml.safe_load(route_text), sg.start_pose_of(world)).run()
        self.assertTrue(any("marker 2 lies" in p for p in problems), problems)

    def test_the_checks_find_a_missing_stripe_and_charger(self):
        world_text, route_text, _, _ = self.sites[(3, False)]
        world = yaml.safe_load(world_text)
        no_stripe = copy.deepcopy(world)
        no_stripe["stripes"] = [s for s in no_stripe["stripes"] if s["id"] != 1]
        problems = sg.Check(no_stripe, yaml.safe_load(route_text),
                            sg.start_pose_of(world)).run()
        self.assertTrue(any("stripe 1 is not a follow stripe" in p for p in problems), problems)
        no_pole = copy.deepcopy(world)
        no_pole["cylinders"] = [c for c in no_pole["cylinders"] if c["kind"] != "charging_pole"]
        problems = sg.Check(no_pole, yaml.safe_load(route_text), sg.start_pose_of(world)).run()
        self.assertTrue(any("no charging pole" in p for p in problems), problems)

    def test_bad_usage_exits_2_with_a_message(self):
        expect_usage_errors(self, (
            (["barn", "--out", "/tmp/x"], "--seed"),
            (["barn", "--seed", "1", "--out", "/tmp/x", "--robots", "2"], "only 1 robot"),
            (["barn", "--seed", "-3", "--out", "/tmp/x"], "--seed"),
            (["barns", "--count", "0", "--first-seed", "1", "--out", "/tmp/x"], "--count"),
            (["farm", "--seed", "1"], "invalid choice")))

    def test_barns_writes_a_folder_per_seed_and_a_summary(self):
        with tempfile.TemporaryDirectory() as tmp:
            r = run("barns", "--count", "2", "--first-seed", "5", "--out", tmp)
            self.assertEqual(r.returncode, 0, r.stderr)
            for seed in (5, 6):
                for name in ("world.yaml", "route.yaml", "scenario.yaml"):
                    self.assertTrue(os.path.isfile(os.path.join(tmp, "barn-%d" % seed, name)))
            self.assertIn("2 barns written", r.stdout)


if __name__ == "__main__":
    unittest.main()
