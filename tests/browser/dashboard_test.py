#!/usr/bin/python3
"""The web dashboard in a real browser (headless Chromium driven over WebDriver by chromedriver).

Starts fleetnav-sim with the two-Lely barn, fleetnavd with --http-listen, one fleetnav-agent per
robot, loads the barn's map, markers and routes with fleetnavctl and submits a job per robot.
Then it opens the dashboard and checks, against the server's own answers (fleetnavctl --json) and
the simulator's ground truth:
  * the robots and unfinished jobs shown are the server's;
  * the page receives pushed updates at >= 4 per second (5 Hz nominal);
  * clicking a running job's pause button pauses the job at the server and its robot stops in
    the simulator (true position still within 2 cm over 3 s), and resume lets it go on;
  * the map's zones are drawn and listed; a zone's stop button stops that zone at the server
    (the page shows it stopped) and its resume button clears it; "stop all" stops the whole
    fleet at the server and both robots stand in the simulator (within 2 cm over 3 s), and
    "resume all" clears it;
and saves a screenshot. Prints the time to interactive (first state drawn) and the update rate.

Usage: dashboard_test.py BUILD_DIR ARTIFACT_DIR. Exit 0 when every check held, 1 otherwise,
77 when chromium or chromedriver is missing (ctest: skipped).
"""
import base64
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ELEMENT = "element-6066-11e4-a52e-4f735466cecf"


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for_file(path, seconds=20.0):
    deadline = time.time() + seconds
    while time.time() < deadline:
        if os.path.exists(path) and os.path.getsize(path) > 0:
            with open(path) as f:
                return f.read().strip()
        time.sleep(0.05)
    raise RuntimeError(f"{path} did not appear within {seconds} s")


class Check:
    def __init__(self):
        self.failures = []

    def that(self, condition, what):
        print(("  ok   " if condition else "  FAIL ") + what, flush=True)
        if not condition:
            self.failures.append(what)


class WebDriver:
    """The few W3C WebDriver commands the test needs, over plain HTTP."""

    def __init__(self, port):
        self.base = f"http://127.0.0.1:{port}"
        self.session = None

    def call(self, method, path, body=None):
        data = None if body is None else json.dumps(body).encode()
        request = urllib.request.Request(self.base + path, data=data, method=method,
                                         headers={"Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(request, timeout=60) as response:
                return json.loads(response.read() or b"{}").get("value")
        except urllib.error.HTTPError as e:
            raise RuntimeError(f"webdriver {method} {path}: {e.read().decode()[:500]}")

    def start(self, chromium):
        args = ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                "--window-size=1400,900"]
        value = self.call("POST", "/session", {"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": {"binary": chromium, "args": args}}}})
        self.session = value["sessionId"]

    def go(self, url):
        self.call("POST", f"/session/{self.session}/url", {"url": url})

    def script(self, source, *args):
        return self.call("POST", f"/session/{self.session}/execute/sync",
                         {"script": source, "args": list(args)})

    def click(self, css):
        """Clicks the element like a user (pointer events at its centre). The tables are redrawn
        with every update, so a reference that went stale in between is looked up again."""
        last = None
        for _ in range(20):
            try:
                element = self.call("POST", f"/session/{self.session}/element",
                                    {"using": "css selector", "value": css})
                self.call("POST", f"/session/{self.session}/element/{element[ELEMENT]}/click",
                          {})
                return
            except (RuntimeError, KeyError, TypeError) as e:
                last = e
                time.sleep(0.05)
        raise RuntimeError(f"cannot click {css}: {last}")

    def screenshot(self, path):
        with open(path, "wb") as f:
            f.write(base64.b64decode(self.call("GET", f"/session/{self.session}/screenshot")))

    def quit(self):
        if self.session:
            try:
                self.call("DELETE", f"/session/{self.session}")
            except Exception:
                pass


def main():
    build, artifacts = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    chromium = shutil.which("chromium")
    chromedriver = shutil.which("chromedriver")
    if not chromium or not chromedriver:
        print("chromium or chromedriver missing: skipped")
        return 77
    os.makedirs(artifacts, exist_ok=True)
    work = tempfile.mkdtemp(prefix="fleetnav-dashboard-")
    processes = []

    def start(argv, name):
        log = open(os.path.join(work, name + ".log"), "w")
        processes.append(subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT,
                                          start_new_session=True))
        return processes[-1]

    check = Check()
    driver = None
    try:
        world = os.path.join(ROOT, "sim/worlds/barn_two_lely.yaml")
        subprocess.run([f"{build}/sim/fleetnav-sim", "--world", world, "--export-map",
                        os.path.join(work, "map")], check=True, capture_output=True)
        start([f"{build}/sim/fleetnav-sim", "--world", world, "--listen", "127.0.0.1:0",
               "--port-file", f"{work}/sim.port", "--real-time-factor", "1",
               "--min-agents", "2"], "sim")
        start([f"{build}/server/fleetnavd", "--insecure", "--listen", "127.0.0.1:0",
               "--db", f"{work}/fleet.db", "--port-file", f"{work}/server.port",
               "--http-listen", "127.0.0.1:0", "--http-port-file", f"{work}/http.port"],
              "fleetnavd")
        sim = "127.0.0.1:" + wait_for_file(f"{work}/sim.port")
        server = "127.0.0.1:" + wait_for_file(f"{work}/server.port")
        http = "127.0.0.1:" + wait_for_file(f"{work}/http.port")

        def ctl(*args):
            result = subprocess.run([f"{build}/tools/fleetnavctl", "--server", server, "--json",
                                     *args], capture_output=True, text=True, timeout=30)
            if result.returncode != 0:
                raise RuntimeError(f"fleetnavctl {' '.join(args)}: {result.stderr}")
            return json.loads(result.stdout)

        ctl("map", "import", "--id", "barn", f"{work}/map/barn.yaml")
        ctl("markers", "put", f"{work}/map/barn.markers.yaml")
        for route in ("barn_feeding.yaml", "barn_north_fence.yaml"):
            ctl("routes", "put", os.path.join(ROOT, "deploy/routes", route))
        # A zone in the barn's south-east corner, away from both robots' work.
        with open(f"{work}/barn.zones.yaml", "w") as f:
            f.write("map: barn\nzones:\n  - {name: corner, kind: speed_limit, speed_limit: 1.0,"
                    " polygon: [[8, -11], [11, -11], [11, -8], [8, -8]]}\n")
        ctl("zones", "put", "--map", "barn", f"{work}/barn.zones.yaml")
        for robot, pose in (("lely1", ("-5.5", "0", "0")), ("lely2", ("-7.0", "4.15", "0"))):
            start([f"{build}/robot_agent/fleetnav-agent", "--robot-id", robot, "--kind",
                   "lely-vector", "--sim", sim, "--server", server, "--initial-pose", *pose],
                  "agent-" + robot)
        deadline = time.time() + 60
        while time.time() < deadline and sorted(
                r["robot_id"] for r in ctl("robots") if r["connection"] == "online") != [
                "lely1", "lely2"]:
            time.sleep(0.2)
        feeding = ctl("job", "submit", "--route", "barn-feeding", "--robot", "lely1")["job_id"]
        fence = ctl("job", "submit", "--route", "barn-north-fence", "--robot", "lely2")["job_id"]

        driver_port = free_port()
        start([chromedriver, f"--port={driver_port}"], "chromedriver")
        driver = WebDriver(driver_port)
        for _ in range(100):
            try:
                driver.call("GET", "/status")
                break
            except Exception:
                time.sleep(0.1)
        driver.start(chromium)
        opened = time.time()
        driver.go(f"http://{http}/")
        ready_ms = None
        while time.time() - opened < 20:
            ready_ms = driver.script("return window.fleetnavReadyMs || null;")
            robots = driver.script("return document.querySelectorAll('#robots tbody tr').length;")
            if ready_ms and robots == 2:
                break
            time.sleep(0.1)
        paint = driver.script(
            "const p = performance.getEntriesByName('first-contentful-paint')[0];"
            "return p ? p.startTime : null;")
        print(f"[ dashboard ] first contentful paint {paint} ms, first state drawn (interactive) "
              f"{ready_ms} ms after navigation start", flush=True)
        check.that(ready_ms is not None, "the page drew the fleet's state")

        # What the page shows is what the server holds.
        time.sleep(2.5)
        shown_robots = driver.script(
            "return [...document.querySelectorAll('#robots tbody tr')].map(r => "
            "[r.dataset.robotId, r.children[2].textContent]);")
        server_robots = ctl("robots")
        check.that(sorted(r[0] for r in shown_robots) ==
                   sorted(r["robot_id"] for r in server_robots),
                   f"robots shown {shown_robots} are the server's")
        check.that(all(r[1] == "online" for r in shown_robots), "both robots shown online")
        shown_jobs = driver.script(
            "return [...document.querySelectorAll('#jobs tbody tr')].map(r => r.dataset.jobId);")
        unfinished = [j["job_id"] for j in ctl("job", "list")
                      if j["state"] in ("queued", "assigned", "running", "paused")]
        check.that(sorted(shown_jobs) == sorted(unfinished),
                   f"jobs shown {shown_jobs} are the server's unfinished jobs {unfinished}")
        rate = driver.script("return window.fleetnav.ratePerS;")
        print(f"[ dashboard ] pushed updates received: {rate} per second", flush=True)
        check.that(rate is not None and rate >= 4, f"updates arrive at >= 4/s (got {rate})")

        # Wait for lely2 to drive, then pause its job from the page.
        def truth(robot):
            result = subprocess.run([f"{build}/tools/fleetnavctl", "sim", "--sim", sim, "truth",
                                     "--json"], capture_output=True, text=True, timeout=30)
            for r in json.loads(result.stdout)["robots"]:
                if r["robot_id"] == robot:
                    return r["x_m"], r["y_m"]
            raise RuntimeError(f"{robot} not in the simulator's truth")

        def moved(a, b):
            return ((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2) ** 0.5

        start_pose = truth("lely2")
        deadline = time.time() + 60
        while time.time() < deadline and moved(truth("lely2"), start_pose) < 0.2:
            time.sleep(0.5)
        check.that(moved(truth("lely2"), start_pose) >= 0.2, "lely2 drives its job")
        job_state = lambda: ctl("job", "get", fence)["state"]
        check.that(job_state() == "running", f"{fence} is running")
        driver.click(f"#jobs tr[data-job-id='{fence}'] button[data-action='pause']")
        time.sleep(1.5)  # the robot brakes
        check.that(job_state() == "paused", f"the pause button paused {fence} at the server")
        before = truth("lely2")
        time.sleep(3.0)
        after = truth("lely2")
        check.that(moved(before, after) < 0.02,
                   f"lely2 stands still while paused (moved {moved(before, after):.3f} m in 3 s)")
        shown_state = driver.script(
            f"return document.querySelector(\"#jobs tr[data-job-id='{fence}']\").dataset.state;")
        check.that(shown_state == "paused", "the page shows the job paused")
        driver.screenshot(os.path.join(artifacts, "dashboard.png"))
        print(f"[ dashboard ] screenshot {os.path.join(artifacts, 'dashboard.png')}", flush=True)
        driver.click(f"#jobs tr[data-job-id='{fence}'] button[data-action='resume']")
        time.sleep(4.0)
        check.that(job_state() == "running", "the resume button let the job go on")
        check.that(moved(after, truth("lely2")) > 0.05, "lely2 drives again after resume")
        check.that(ctl("job", "get", feeding)["state"] in ("assigned", "running", "succeeded"),
                   "lely1's job went on undisturbed")

        # Zones and stops.
        zones_shown = driver.script(
            "return [(window.fleetnav.map.zones || {zones: []}).zones.length, "
            "[...document.querySelectorAll('#zones tbody tr')].map(r => r.dataset.zone)];")
        check.that(zones_shown == [1, ["corner"]], f"the map's zone is drawn and listed "
                   f"({zones_shown})")

        def stops():
            return [(s["map_id"], s["zone"]) for s in ctl("stops")]

        def row_stopped():
            return driver.script(
                "const r = document.querySelector(\"#zones tr[data-zone='corner']\");"
                "return r ? r.dataset.stopped : null;")

        driver.click("#zones tr[data-zone='corner'] button[data-action='stop']")
        time.sleep(1.0)
        check.that(stops() == [("barn", "corner")], f"the zone's stop button stopped it ({stops()})")
        check.that(row_stopped() == "yes", "the page shows the zone stopped")
        driver.screenshot(os.path.join(artifacts, "dashboard-zone-stopped.png"))
        driver.click("#zones tr[data-zone='corner'] button[data-action='resume']")
        time.sleep(1.0)
        check.that(stops() == [], f"its resume button cleared the stop ({stops()})")
        driver.click("#stop-all")
        time.sleep(1.5)  # the robots brake
        check.that(stops() == [("", "")], f"stop all stopped the whole fleet ({stops()})")
        before = {r: truth(r) for r in ("lely1", "lely2")}
        time.sleep(3.0)
        stood = {r: moved(before[r], truth(r)) for r in before}
        check.that(all(m < 0.02 for m in stood.values()),
                   f"both robots stand while the fleet is stopped (moved {stood} m in 3 s)")
        driver.click("#resume-all")
        time.sleep(1.0)
        check.that(stops() == [], f"resume all cleared the stop ({stops()})")
    except Exception as e:  # a broken setup is a failure, with the reason
        check.that(False, f"run: {e}")
    finally:
        if driver:
            driver.quit()
        for p in reversed(processes):
            try:
                os.killpg(p.pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
        for p in processes:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
        if check.failures:
            keep = os.path.join(artifacts, "dashboard-logs")
            shutil.rmtree(keep, ignore_errors=True)
            shutil.copytree(work, keep)
            print(f"logs kept in {keep}")
        shutil.rmtree(work, ignore_errors=True)
    print(f"{len(check.failures)} check(s) failed" if check.failures else "all checks held")
    return 1 if check.failures else 0


if __name__ == "__main__":
    sys.exit(main())
