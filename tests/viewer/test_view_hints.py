"""Every course scene's view hint frames its whole motion in the part of the window the side panel
leaves free, clear of the overlay at its top left: each scene runs in the real viewer under Xvfb, at
the default window size with the panel open, and every 0.1 s of its viewSeconds the viewer reports where each moving body is drawn (its bounding sphere projected by the
camera the renderer uses; a cloth, rope or soft body as the spheres of its particles) and where the
overlay is."""
import contextlib
import json
import os
import pathlib
import queue
import subprocess
import sys
import unittest
from concurrent.futures import ThreadPoolExecutor

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import headless  # noqa: E402  (the virtual displays the viewer runs on)

# Scenes tracked at once, each worker on a display of its own.
WORKERS = 2
VIEWER = os.environ.get("GPL_VIEWER_SOLUTIONS")
RUNNER = os.environ.get("GPL_RUN_SOLUTIONS")
# Lists each scene's viewSeconds (tests/viewer/view_seconds.cpp): each scene's script is written
# before its viewer starts, so that each scene starts the viewer once.
VIEW_SECONDS = os.environ.get("GPL_VIEW_SECONDS")
# Libraries to preload into the viewer in a sanitizer build (tests/CMakeLists.txt says why).
PRELOAD = ["env", f"LD_PRELOAD={os.environ['GPL_VIEWER_PRELOAD']}"] if os.environ.get("GPL_VIEWER_PRELOAD") else []
# The viewer runs at speed 6 (the panel's slider): each frame it draws is 0.1 s of simulated time, so
# every frame is a report, and it draws a sixth of the frames it would at speed 1.
SPEED = 6
DUMP_SECONDS = 0.1



def viewer(display, *args, timeout=300):
    cmd = [*PRELOAD, VIEWER, *map(str, args)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=display.environment())
    states = [json.loads(line[len("state "):]) for line in proc.stdout.splitlines() if line.startswith("state ")]
    return proc.returncode, states, proc.stdout[-2000:] + proc.stderr[-2000:]


def course_scenes():
    """(key, name) of the course's scenes (the student's own, F11 and F12, frame themselves)."""
    listed = subprocess.run([RUNNER, "--list"], capture_output=True, text=True, check=True).stdout
    rows = [line.split("\t") for line in listed.splitlines()]
    return [(key, name) for key, name, _ in rows if key not in ("F11", "F12")]


def view_seconds():
    """{name: viewSeconds} of every scene."""
    listed = subprocess.run([VIEW_SECONDS], capture_output=True, text=True, check=True).stdout
    return {name: float(seconds) for _, name, seconds in (line.split("\t") for line in listed.splitlines())}


def track(scene, seconds, displays):
    """The view reports of one scene over its viewSeconds (seconds), one every 0.1 s, on a display
    taken from the queue displays (and given back)."""
    display = displays.get()
    try:
        return track_on(display, scene, seconds)
    finally:
        displays.put(display)


def track_on(display, scene, seconds):
    dumps = int(round(seconds / DUMP_SECONDS))
    # "wait 0" lets the frame it is read in pass: one frame, 0.1 s, between reports.
    script = f"set speed {SPEED}; dump; " + "wait 0; dump; " * dumps + "quit"
    code, states, out = viewer(display, scene, "--script", script)
    return scene, (code, states), out


@unittest.skipUnless(VIEWER and RUNNER and VIEW_SECONDS,
                     "GPL_VIEWER_SOLUTIONS, GPL_RUN_SOLUTIONS and GPL_VIEW_SECONDS name the programs")
class ViewHints(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.scenes = course_scenes()
        cls.seconds = view_seconds()
        with contextlib.ExitStack() as stack, ThreadPoolExecutor(max_workers=WORKERS) as pool:
            displays = queue.Queue()
            for _ in range(WORKERS):
                displays.put(stack.enter_context(headless.Display()))
            names = [n for _, n in cls.scenes]
            seconds = [cls.seconds.get(n, 0.0) for n in names]
            cls.tracks = {name: result for name, *result in pool.map(track, names, seconds, [displays] * len(names))}

    def test_there_are_course_scenes(self):
        self.assertGreaterEqual(len(self.scenes), 16)
        self.assertIn("chain", self.tracks)

    def test_moving_bodies_stay_in_the_free_part(self):
        for _, name in self.scenes:
            with self.subTest(scene=name):
                (result, out) = self.tracks[name]
                self.assertIsNotNone(result, out)
                code, states = result
                self.assertEqual(code, 0, out)
                self.assertTrue(states, out)
                seconds = states[0]["view"]["seconds"]
                # The script was written for the seconds the viewer shows the scene for.
                self.assertEqual(seconds, self.seconds.get(name), "gpl-view-seconds and the viewer disagree")
                self.assertGreater(seconds, 0.5)
                # The last report lies within one frame's step of viewSeconds.
                self.assertAlmostEqual(states[-1]["time"], seconds, delta=0.1 + 1e-9)
                _, _, width, height = states[0]["view"]["free"]
                self.assertLess(width, 1280, "the panel is open and takes its part of the window")
                for s in states:
                    self.assertFalse(s["view"]["behind_eye"], f"a body behind the camera at t = {s['time']:.2f} s")
                    self.assertTrue(s["view"]["bodies"], f"no moving body at t = {s['time']:.2f} s")
                    # A student's overlay has up to two lines more than this one: the hooks still
                    # open, and the reference ghost's difference (the ghost on).
                    left, top, right, bottom = s["view"]["overlay"]
                    overlay = (left, top, right, bottom + 2 * s["view"]["line_height"])
                    for box in s["view"]["bodies"]:
                        where = f"at t = {s['time']:.2f} s a body covers x {box[0]:.0f}..{box[2]:.0f}, " \
                                f"y {box[1]:.0f}..{box[3]:.0f}"
                        self.assertTrue(box[0] >= 0 and box[1] >= 0 and box[2] <= width and box[3] <= height,
                                        f"{where}; the free part is {width} x {height} pixels")
                        self.assertFalse(box[0] < overlay[2] and box[2] > overlay[0] and box[1] < overlay[3]
                                         and box[3] > overlay[1], f"{where}, under the overlay {overlay}")

    def test_the_motion_is_not_lost_in_the_distance(self):
        # A hint that frames the motion from far away passes the test above trivially: over the
        # scene's time the moving bodies must cover at least a third of the free part's width or
        # height. As framed now every scene covers half or more in one of them (the pendulum, the
        # smallest, 0.51 of the width; the falling sphere 0.82 of the height).
        for _, name in self.scenes:
            with self.subTest(scene=name):
                (result, out) = self.tracks[name]
                self.assertIsNotNone(result, out)
                _, states = result
                _, _, width, height = states[0]["view"]["free"]
                boxes = [box for s in states for box in s["view"]["bodies"]]
                span_x = max(b[2] for b in boxes) - min(b[0] for b in boxes)
                span_y = max(b[3] for b in boxes) - min(b[1] for b in boxes)
                self.assertGreater(max(span_x / width, span_y / height), 1 / 3,
                                   f"the motion covers {span_x:.0f} x {span_y:.0f} of {width} x {height} pixels")


if __name__ == "__main__":
    unittest.main()
