#!/usr/bin/python3
"""Tests of scripts/sitegen's stores (mecanum platform, trolleys) and yards (Ackermann robot,
box fields). Run by hand, no build needed:

  /usr/bin/python3 -m unittest discover -s tests/sitegen -v
"""
import math
import os
import re
import subprocess
import sys
import tempfile
import unittest

import yaml

from test_sitegen import SCRIPT, expect_usage_errors, same_bytes, sg


def run(*args):
    return subprocess.run([sys.executable, SCRIPT] + list(args), capture_output=True, text=True)


def check_scenario(test, world, route, scenario, summary, robot, kind):
    test.assertEqual(world["name"], route["map"])
    test.assertEqual(world["robots"][0]["id"], robot)
    test.assertEqual(world["robots"][0]["kind"], kind)
    test.assertEqual(scenario["world"], "world.yaml")
    test.assertEqual(scenario["routes"], ["route.yaml"])
    test.assertEqual(scenario["jobs"][0]["route"], route["name"])
    test.assertEqual(scenario["jobs"][0]["robot"], robot)
    test.assertEqual(scenario["robots"][0]["initial_pose"], world["robots"][0]["pose"])
    test.assertEqual(scenario["expect"]["jobs"], "succeeded")
    test.assertEqual(scenario["expect"]["contacts"], 0)
    test.assertGreater(scenario["expect"]["deadline_s"], 2 * summary["nominal_s"])


def kinds_of(route):
    return {next(iter(a)) for a in route["actions"]}


class GeneratedSites:
    """What stores and yards share: the sites of a few seeds, parsed, and determinism. A
    subclass sets KIND, SEEDS (1 and 2 among them), BYTES_SEED and generate()."""

    @classmethod
    def setUpClass(cls):
        cls.sites = {seed: cls.generate(seed) for seed in cls.SEEDS}

    def parsed(self, seed):
        w, r, s, summary = self.sites[seed]
        return yaml.safe_load(w), yaml.safe_load(r), yaml.safe_load(s), summary

    def test_same_seed_gives_the_same_bytes(self):
        same_bytes(self, self.KIND, self.BYTES_SEED)

    def test_seeds_differ(self):
        self.assertNotEqual(self.sites[1][0], self.sites[2][0])


class StoreTest(GeneratedSites, unittest.TestCase):
    KIND, SEEDS, BYTES_SEED = "store", (1, 2, 3, 11), 4

    @staticmethod
    def generate(seed):
        return sg.generate_store(seed)

    def test_generated_stores_pass_their_checks_and_use_every_action(self):
        for seed in self.sites:
            with self.subTest(seed=seed):
                world_text, route_text, _, _ = self.sites[seed]
                _, problems = sg.check_store_texts(world_text, route_text)
                self.assertEqual(problems, [])
                world, route, scenario, summary = self.parsed(seed)
                self.assertEqual(kinds_of(route), set(sg.STORE_KINDS))
                self.assertEqual({"name", "extent", "walls", "boxes", "trolleys", "robots"},
                                 set(world) - {"cylinders"})
                ids = {t["id"] for t in world["trolleys"]}
                docks = [a["dock"] for a in route["actions"] if "dock" in a]
                self.assertTrue(docks)
                for d in docks:
                    self.assertEqual(d["target"], "trolley")
                    self.assertIn(d["target_id"], ids)
                self.assertGreater(len(ids), len(docks))      # trolleys in the way too
                order = [next(iter(a)) for a in route["actions"]]
                for k, a in enumerate(order):
                    if a == "dock":
                        self.assertEqual(order[k + 1:k + 5], ["free_navigation", "undock",
                                                              "move", order[k + 4]])
                check_scenario(self, world, route, scenario, summary, "omni1",
                               "mecanum-platform")

    def test_rows_run_both_ways_over_seeds(self):
        ways = {sg.generate_store(seed)[3]["rows"].split()[1] for seed in range(1, 9)}
        self.assertEqual(ways, {"N-S", "E-W"})

    def test_the_checks_find_a_goal_inside_a_shelf(self):
        world, route, _, _ = self.parsed(1)
        shelf = next(b for b in world["boxes"] if b["kind"] == "shelf")
        goal = route["actions"][0]["free_navigation"]["goal"]
        goal["x"], goal["y"] = shelf["center"]
        problems = sg.StoreCheck(world, route).run()
        self.assertTrue(any("actions[0]" in p and "the goal" in p and "shelf" in p
                            for p in problems), problems)

    def test_the_checks_find_a_trolley_off_the_dock_axis(self):
        world, route, _, _ = self.parsed(2)
        tid = route["actions"][1]["dock"]["target_id"]
        t = next(t for t in world["trolleys"] if t["id"] == tid)
        t["yaw_deg"] += 40.0
        problems = sg.StoreCheck(world, route).run()
        self.assertTrue(any("actions[1]" in p and "does not face trolley" in p
                            for p in problems), problems)

    def test_the_checks_find_a_blocked_way(self):
        world, route, _, _ = self.parsed(3)
        # A wall round the first trolley and the pose its dock starts from: no way to that pose.
        g = route["actions"][0]["free_navigation"]["goal"]
        tid = route["actions"][1]["dock"]["target_id"]
        t = next(t for t in world["trolleys"] if t["id"] == tid)["center"]
        x0, x1 = min(g["x"], t[0]) - 0.9, max(g["x"], t[0]) + 0.9
        y0, y1 = min(g["y"], t[1]) - 0.9, max(g["y"], t[1]) + 0.9
        for a, b in (((x0, y0), (x1, y0)), ((x1, y0), (x1, y1)), ((x1, y1), (x0, y1)),
                     ((x0, y1), (x0, y0))):
            world["walls"].append({"from": list(a), "to": list(b), "thickness": 0.05})
        problems = sg.StoreCheck(world, route).run()
        self.assertTrue(any("actions[0]" in p and "no way" in p for p in problems), problems)

    def test_the_checks_want_every_action_and_home(self):
        world, route, _, _ = self.parsed(1)
        route["actions"] = [a for a in route["actions"] if "straight" not in a]
        problems = sg.StoreCheck(world, route).run()
        self.assertTrue(any("does not use straight" in p for p in problems), problems)
        self.assertTrue(any("not at home" in p for p in problems), problems)


class YardTest(GeneratedSites, unittest.TestCase):
    KIND, SEEDS, BYTES_SEED = "yard", (1, 2, 6), 3

    @staticmethod
    def generate(seed):
        return sg.generate_yard(seed)

    def test_generated_yards_pass_their_checks(self):
        for seed in self.sites:
            with self.subTest(seed=seed):
                world_text, route_text, _, _ = self.sites[seed]
                chk, problems = sg.check_yard_texts(world_text, route_text)
                self.assertEqual(problems, [])
                world, route, scenario, summary = self.parsed(seed)
                self.assertEqual(kinds_of(route), set(sg.YARD_KINDS))
                self.assertEqual(set(world), {"name", "extent", "fences", "boxes", "cylinders",
                                              "robots"})
                kinds = {b["kind"] for b in world["boxes"]}
                self.assertEqual(kinds, {"building", "loading_dock", "parcel"})
                self.assertTrue(chk.gaps)
                for _, w in chk.gaps:
                    self.assertGreaterEqual(w, 0.6 + 0.5 - 1e-6)
                # The narrowest gap is visible in the world file and the summary.
                m = re.search(r"Narrowest gap: ([0-9.]+) m", world_text)
                self.assertIsNotNone(m)
                self.assertAlmostEqual(float(m.group(1)), summary["narrowest_m"], places=2)
                self.assertGreaterEqual(summary["narrowest_m"], 1.1)
                check_scenario(self, world, route, scenario, summary, "delivery1",
                               "ackermann-delivery")

    def test_the_body_width_comes_from_the_robot_model(self):
        with open(os.path.join(os.path.dirname(SCRIPT), "..", "core", "src",
                               "robot_model.cpp")) as f:
            text = f.read()
        ack = text[text.index("RobotModel AckermannDeliveryModel()"):]
        m = re.search(r"Rectangle\(([-0-9.]+), ([-0-9.]+), ([-0-9.]+)\)", ack)
        self.assertEqual((float(m.group(1)), float(m.group(2)), float(m.group(3))),
                         (sg.ACK_BACK, sg.ACK_FRONT, sg.ACK_HALF_W))

    def test_the_checks_find_a_goal_inside_a_box(self):
        world, route, _, _ = self.parsed(1)
        dock = next(b for b in world["boxes"] if b["kind"] == "loading_dock")
        goal = route["actions"][0]["free_navigation"]["goal"]
        goal["x"], goal["y"] = dock["center"]
        problems = sg.YardCheck(world, route).run()
        self.assertTrue(any("actions[0]" in p and "the goal" in p for p in problems), problems)

    def test_the_checks_find_a_gap_narrower_than_the_limit(self):
        world, route, _, _ = self.parsed(2)
        a, b = route["actions"][0]["free_navigation"]["waypoints"][:2]
        mid = ((a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0)
        # The parcel nearest the gap's middle, moved 0.45 m into it: narrower than 1.1 m.
        parcels = [p for p in world["boxes"] if p["kind"] == "parcel"]
        p = min(parcels, key=lambda q: math.hypot(q["center"][0] - mid[0],
                                                   q["center"][1] - mid[1]))
        d = math.hypot(mid[0] - p["center"][0], mid[1] - p["center"][1])
        p["center"] = [p["center"][0] + 0.45 * (mid[0] - p["center"][0]) / d,
                       p["center"][1] + 0.45 * (mid[1] - p["center"][1]) / d]
        problems = sg.YardCheck(world, route).run()
        self.assertTrue(any("actions[0]" in p and "wide (needs" in p for p in problems),
                        problems)

    def test_the_checks_find_a_way_round_the_field(self):
        world, route, _, _ = self.parsed(1)
        world["fences"] = world["fences"][:4]       # the line across the yard removed
        problems = sg.YardCheck(world, route).run()
        self.assertTrue(any("without a gap narrower" in p for p in problems), problems)

    def test_the_reachability_search_knows_the_turning_radius(self):
        # A corridor 1.2 m wide: the robot can drive along it, not turn round in it.
        world = {"extent": {"min": [-6, -3], "max": [6, 3]},
                 "boxes": [{"center": [0, 1.1], "size": [12, 1.0]},
                           {"center": [0, -1.1], "size": [12, 1.0]}]}
        field = sg.DistField(world["extent"], sg.world_obstacles(world))
        self.assertTrue(sg.ackermann_reachable(field, (-3.0, 0.0, 0.0), (3.0, 0.0, 0.0)))
        self.assertFalse(sg.ackermann_reachable(field, (-3.0, 0.0, 0.0),
                                                (3.0, 0.0, math.pi), max_expansions=4000))
        open_field = sg.DistField(world["extent"], [])
        self.assertTrue(sg.ackermann_reachable(open_field, (-3.0, 0.0, 0.0),
                                               (3.0, 0.0, math.pi)))


class SiteUsageTest(unittest.TestCase):
    def test_bad_usage_exits_2_with_a_message(self):
        expect_usage_errors(self, (
            (["store", "--out", "/tmp/x"], "--seed"),
            (["yard", "--seed", "-1", "--out", "/tmp/x"], "--seed"),
            (["stores", "--count", "0", "--first-seed", "1", "--out", "/tmp/x"], "--count"),
            (["yards", "--count", "1", "--first-seed", "-2", "--out", "/tmp/x"], "--first-seed"),
            (["yard", "--seed", "1", "--out", "/tmp/x", "--robots", "2"], "unrecognized")))

    def test_plural_commands_write_a_folder_per_seed_and_a_summary(self):
        with tempfile.TemporaryDirectory() as tmp:
            for kind, plural, column in (("store", "stores", "aisles_m"),
                                         ("yard", "yards", "narrowest_m")):
                r = run(plural, "--count", "2", "--first-seed", "5", "--out", tmp)
                self.assertEqual(r.returncode, 0, r.stderr)
                for seed in (5, 6):
                    for name in ("world.yaml", "route.yaml", "scenario.yaml"):
                        self.assertTrue(os.path.isfile(os.path.join(tmp, "%s-%d" % (kind, seed),
                                                                    name)))
                self.assertIn("2 %ss written" % kind, r.stdout)
                self.assertIn(column, r.stdout)


if __name__ == "__main__":
    unittest.main()
