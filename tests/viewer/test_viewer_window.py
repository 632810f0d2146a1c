"""The real viewer window under Xvfb, driven by scripted keys and mouse events that go through the
same handlers GLUT calls. Screenshots are checked for what a person would see."""
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import unittest

from PIL import Image, ImageChops

SOLUTIONS = os.environ.get("GPL_VIEWER_SOLUTIONS")
ASSIGNMENTS = os.environ.get("GPL_VIEWER_ASSIGNMENTS")
ROOT = pathlib.Path(__file__).resolve().parents[2]
# Runs a command on a virtual display of its own (tools/headless.py); the status is the command's.
HEADLESS = [sys.executable, str(ROOT / "tools" / "headless.py")]
sys.path.insert(0, str(ROOT / "tools"))
import headless  # noqa: E402  (DISPLAY, below: the display the viewer's windows open on one after another)
# Libraries to preload into the viewer, set by CTest in a sanitizer build (tests/CMakeLists.txt says why).
PRELOAD = os.environ.get("GPL_VIEWER_PRELOAD")
START = ["env", f"LD_PRELOAD={PRELOAD}"] if PRELOAD else []
SKY = (204, 217, 230)  # the background colour (0.80, 0.85, 0.90)



DISPLAY = None


def setUpModule():
    global DISPLAY
    if SOLUTIONS and ASSIGNMENTS:
        DISPLAY = headless.Display().__enter__()


def tearDownModule():
    if DISPLAY:
        DISPLAY.__exit__(None, None, None)


def viewer(binary, *args, timeout=120):
    """Runs the viewer on the module's Xvfb display; returns (exit status, state dumps, output)."""
    cmd = [*START, binary, *map(str, args)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=DISPLAY.environment())
    states = [json.loads(line[len("state "):]) for line in proc.stdout.splitlines() if line.startswith("state ")]
    return proc.returncode, states, proc.stdout + proc.stderr


def colours(path, box=None):
    """[(how many pixels, (r, g, b))] of a picture, within box (x0, y0, x1, y1) when given. A frame has
    a few thousand distinct colours among its 921,600 pixels: a test on colours is asked once per
    colour and its count taken: the same sum as asking it for every pixel, in a tenth of the time."""
    with Image.open(path) as img:
        rgb = img.convert("RGB")
    if box:
        x0, y0, x1, y1 = box
        rgb = rgb.crop((max(x0, 0), max(y0, 0), min(x1, rgb.width), min(y1, rgb.height)))
    return rgb.getcolors(rgb.width * rgb.height)


def not_sky_fraction(path):
    counted = colours(path)
    off = sum(n for n, p in counted if max(abs(a - b) for a, b in zip(p, SKY)) > 12)
    return off / sum(n for n, _ in counted)


def count_pixels(path, test, box=None):
    """Pixels for which test((r, g, b)) holds, within box (x0, y0, x1, y1) when given."""
    return sum(n for n, p in colours(path, box) if test(p))


def contact_coloured(p):
    """The magenta of contact points and normals (no body or wall has it)."""
    r, g, b = p
    return r > 200 and g < 90 and b > 150


def changed_pixels(path_a, path_b, box=None):
    """Pixels that differ between two pictures within box (x0, y0, x1, y1), or in the whole picture."""
    with Image.open(path_a) as a, Image.open(path_b) as b:
        box = box or (0, 0, *a.size)
        r, g, b_ = ImageChops.difference(a.convert("RGB").crop(box), b.convert("RGB").crop(box)).split()
        return sum(ImageChops.lighter(ImageChops.lighter(r, g), b_).histogram()[1:])


def above(band, threshold):
    """A mask of a band: 255 where its value is above threshold, 0 elsewhere."""
    return band.point(lambda v: 255 if v > threshold else 0)


def orange_centroid(path):
    """Centre (x, y) of the pixels of the first movable body's colour (orange), or None."""
    with Image.open(path) as img:
        r, g, b = img.convert("RGB").split()
    # Orange is r > 120 and r > g + 45 and g > b + 30: masks of 0 and 255 multiplied, one per condition
    # (subtract stops at 0, so r - g is above 45 exactly where r > g + 45).
    mask = ImageChops.multiply(ImageChops.multiply(above(r, 120), above(ImageChops.subtract(r, g), 45)),
                               above(ImageChops.subtract(g, b), 30))
    w, h = mask.size
    rows, columns = mask.tobytes(), mask.transpose(Image.Transpose.TRANSPOSE).tobytes()
    per_row = [rows[y * w:(y + 1) * w].count(255) for y in range(h)]
    per_column = [columns[x * h:(x + 1) * h].count(255) for x in range(w)]
    n = sum(per_row)
    xs = sum(x * count for x, count in enumerate(per_column))
    ys = sum(y * count for y, count in enumerate(per_row))
    return (xs / n, ys / n) if n > 30 else None


@unittest.skipUnless(SOLUTIONS and ASSIGNMENTS, "set GPL_VIEWER_SOLUTIONS and GPL_VIEWER_ASSIGNMENTS (CTest does)")
class Window(unittest.TestCase):
    def setUp(self):
        self.tmp = pathlib.Path(tempfile.mkdtemp(prefix="gpl-viewer-"))

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def test_headless_frames_show_the_scene(self):
        out = self.tmp / "frames"
        rc, _, log = viewer(SOLUTIONS, "static-and-movable", "--frames", 12, "--out", out)
        self.assertEqual(rc, 0, log)
        frames = sorted(out.glob("frame_*.png"))
        self.assertEqual(len(frames), 12)
        with Image.open(frames[0]) as first:
            self.assertEqual(first.size, (1280, 720))
        self.assertGreater(not_sky_fraction(frames[-1]), 0.2, "the floor, the bodies and the panel are drawn")

    def test_a_falling_sphere_moves_down_the_image(self):
        out = self.tmp / "fall"
        rc, _, log = viewer(SOLUTIONS, "falling-sphere", "--frames", 40, "--out", out, "--no-panel")
        self.assertEqual(rc, 0, log)
        first, last = orange_centroid(out / "frame_00001.png"), orange_centroid(out / "frame_00040.png")
        self.assertIsNotNone(first, "the ball is visible in the first frame")
        self.assertIsNotNone(last, "the ball is visible in the last frame")
        # 40 frames are 0.67 s: the ball falls 2.2 m, far more than a few pixels on screen.
        self.assertGreater(last[1] - first[1], 20, f"from {first} to {last}")
        self.assertAlmostEqual(last[0], first[0], delta=3, msg="straight down")
        # The scene has no floor: below the overlay only the ball is drawn (about 1800 pixels), no
        # ground or shadow.
        below = colours(out / "frame_00040.png", (0, 150, 1280, 720))
        drawn = sum(n for n, p in below if max(abs(a - b) for a, b in zip(p, SKY)) > 12)
        self.assertLess(drawn, 4000, "a scene without a floor draws nothing under its bodies")

    def test_the_untouched_stubs_leave_the_ball_where_it_is(self):
        out = self.tmp / "stub"
        rc, states, log = viewer(ASSIGNMENTS, "falling-sphere", "--frames", 20, "--out", out, "--no-panel")
        self.assertEqual(rc, 0, log)
        self.assertIn("not implemented: integrator()", log)
        first, last = orange_centroid(out / "frame_00001.png"), orange_centroid(out / "frame_00020.png")
        self.assertAlmostEqual(first[1], last[1], delta=0.5)

    def test_scene_keys_switch_the_scene(self):
        a, b = self.tmp / "a.png", self.tmp / "b.png"
        rc, states, log = viewer(SOLUTIONS, "--paused", "--script",
                                 f"wait 2; shot {a}; key 2; wait 2; shot {b}; dump; key F11; dump; key F12; dump; quit")
        self.assertEqual(rc, 0, log)
        self.assertEqual([s["scene"] for s in states], ["masses", "my-scene", "my-scene"])
        self.assertIn("no scene on key F12", log)
        diff = changed_pixels(a, b)
        self.assertGreater(diff, 1280 * 720 * 0.01, "switching scenes changes the picture")

    def test_pause_step_step_back_speed(self):
        rc, states, log = viewer(SOLUTIONS, "static-and-movable", "--script",
                                 "wait 5; key space; dump; wait 10; dump; key n; dump; key n; key b; dump;"
                                 " key b; key b; dump; key plus; dump; key minus; key minus; dump; key space; wait 5; dump; quit")
        self.assertEqual(rc, 0, log)
        paused, later, stepped, back, back2, fast, slow, running = states
        self.assertTrue(paused["paused"])
        self.assertEqual(later["steps"], paused["steps"], "nothing moves while paused")
        self.assertEqual(stepped["steps"], paused["steps"] + 1)
        self.assertEqual(back["steps"], stepped["steps"])
        self.assertEqual(back2["steps"], paused["steps"] - 1)
        self.assertEqual(back2["positions"]["ball"][1] > stepped["positions"]["ball"][1], True, "stepping back raises the ball")
        self.assertEqual((fast["speed"], slow["speed"]), (2.0, 0.5))
        self.assertFalse(running["paused"])
        self.assertGreater(running["steps"], back2["steps"])
        # The panel's speed slider, as a script sets it: a frame of 1/60 s is 0.1 s of simulated time
        # (ten of the scene's steps of 0.01 s).
        rc, states, log = viewer(SOLUTIONS, "static-and-movable", "--script", "set speed 6; dump; wait 0; dump; quit")
        self.assertEqual(rc, 0, log)
        before, after = states
        self.assertEqual(after["speed"], 6.0)
        self.assertEqual(after["steps"] - before["steps"], 10)
        self.assertAlmostEqual(after["time"] - before["time"], 0.1, delta=1e-9)

    def test_pick_and_drag_a_body_with_the_mouse(self):
        shot = self.tmp / "drag.png"
        rc, states, log = viewer(SOLUTIONS, "static-and-movable", "--script",
                                 "key space; move @ball; wait 1; dump; down left @ball; move 900 150; dump; key space;"
                                 f" wait 60; dump; shot {shot}; wait 1; up left 900 150; dump; quit")
        self.assertEqual(rc, 0, log)
        hover, grabbed, pulled, released = states
        self.assertEqual(hover["hovered"], "ball")
        self.assertEqual(grabbed["selected"], "ball")
        self.assertTrue(grabbed["dragging"])
        self.assertFalse(released["dragging"])
        start, end = grabbed["positions"]["ball"], pulled["positions"]["ball"]
        self.assertGreater(end[0], start[0] + 1.0, "pulled to the right, toward the cursor")
        self.assertGreater(end[1], start[1], "held up against gravity")
        self.assertGreater(not_sky_fraction(shot), 0.2)

    def test_click_on_nothing_clears_the_selection_and_orbits(self):
        rc, states, log = viewer(SOLUTIONS, "static-and-movable", "--paused", "--script",
                                 "down left @ball; up left @ball; dump; down left 100 650; move 300 600; up left 300 600; dump; quit")
        self.assertEqual(rc, 0, log)
        self.assertEqual(states[0]["selected"], "ball")
        self.assertIsNone(states[1]["selected"])
        self.assertNotEqual(states[0]["camera_eye"], states[1]["camera_eye"], "the drag orbited the camera")

    def test_interaction_keys(self):
        rc, states, log = viewer(SOLUTIONS, "static-and-movable", "--paused", "--script",
                                 "dump; key g; dump; key x; key i; dump; down left @crate; up left @crate; key del; dump;"
                                 " key f; key h; key tab; wheel up 640 360; dump; key r; key esc; dump; quit")
        self.assertEqual(rc, 0, log)
        start, gravity, added, removed, toggles, reset = states
        self.assertTrue(start["gravity"])
        self.assertFalse(gravity["gravity"])
        self.assertEqual(added["bodies"], start["bodies"] + 2, "a shot sphere and an inserted box")
        self.assertEqual(removed["bodies"], added["bodies"] - 1)
        self.assertNotIn("crate", removed["positions"])
        self.assertTrue(toggles["fly"])
        self.assertTrue(toggles["help"])
        self.assertFalse(toggles["panel"])
        self.assertLess(toggles["camera_distance"], start["camera_distance"])
        self.assertEqual(reset["bodies"], start["bodies"])
        self.assertTrue(reset["gravity"], "a reset restores the scene's gravity")
        self.assertFalse(reset["help"], "Esc closes the help first")

    def test_reference_ghost_shows_where_the_stubs_diverge(self):
        rc, states, log = viewer(ASSIGNMENTS, "falling-sphere", "--script", "key o; wait 60; dump; quit")
        self.assertEqual(rc, 0, log)
        self.assertTrue(states[0]["ghost"])
        # The stubbed ball stays at 10 m while the reference falls 4.9 t^2 (about 1.4 m after 0.53 s).
        self.assertGreater(states[0]["ghost_difference"], 0.5)
        rc, states, log = viewer(SOLUTIONS, "falling-sphere", "--ghost", "--script", "wait 60; dump; quit")
        self.assertEqual(states[0]["ghost_difference"], 0.0, "the reference agrees with itself")

    def test_contacts_are_drawn_on_request(self):
        off, on = self.tmp / "off.png", self.tmp / "on.png"
        rc, states, log = viewer(SOLUTIONS, "balls-in-a-box", "--paused", "--steps", 150, "--script",
                                 f"wait 2; shot {off}; wait 1; dump; key k; wait 2; shot {on}; wait 1; dump; key k; dump; quit")
        self.assertEqual(rc, 0, log)
        hidden, shown, hidden_again = states
        self.assertFalse(hidden["contacts_shown"])
        self.assertTrue(shown["contacts_shown"])
        self.assertFalse(hidden_again["contacts_shown"])
        self.assertGreater(shown["contacts"], 20, "balls resting on the floor and on each other")
        self.assertEqual(count_pixels(off, contact_coloured), 0)
        self.assertGreater(count_pixels(on, contact_coloured), 20 * 20, "a dot and a normal for every contact")

    def test_the_restitution_of_the_selected_body_and_the_stages_can_be_changed(self):
        # The ball of restitution 0.9 bounces back up from the floor; made plastic (the panel's
        # slider, or the script's 'set'), it stays down, as it does with the impulse stage off.
        script = "down left @e=0.9; up left @e=0.9; {}; dump; key space; wait 90; dump; quit"
        rc, states, log = viewer(SOLUTIONS, "bouncing-balls", "--paused", "--script", script.format("wait 1"))
        self.assertEqual(rc, 0, log)
        self.assertEqual(states[0]["selected_restitution"], 0.9)
        self.assertGreater(states[1]["positions"]["e=0.9"][1], 1.0, "bounced back up")
        rc, states, log = viewer(SOLUTIONS, "bouncing-balls", "--paused", "--script", script.format("set restitution 0"))
        self.assertEqual(rc, 0, log)
        self.assertEqual(states[0]["selected"], "e=0.9")
        self.assertEqual(states[0]["selected_restitution"], 0.0)
        self.assertLess(states[1]["positions"]["e=0.9"][1], 0.35, "plastic: it stays on the floor")
        self.assertGreater(states[1]["positions"]["e=0.7"][1], 0.5, "the others still bounce")
        rc, states, log = viewer(SOLUTIONS, "bouncing-balls", "--paused", "--script",
                                 script.format("set stage impulses off; set contact-iterations 3"))
        self.assertEqual(rc, 0, log)
        self.assertFalse(states[0]["stages"]["impulses"])
        self.assertTrue(states[0]["stages"]["interpenetration"])
        self.assertEqual(states[0]["contact_iterations"], 3)
        self.assertLess(states[1]["positions"]["e=0.9"][1], 0.35, "without impulses every landing is plastic")

    def test_the_contact_scenes_show_moving_bodies_and_the_ghost_agrees(self):
        # Worksheets 3 to 5, one after the other by key, with the reference ghost: in each, the
        # picture changes where the scene is drawn (left of the panel, below the overlay), the
        # bodies move, and the reference solution agrees with itself.
        keys = ["9", "F1", "F2", "F3", "F4", "F5", "F6", "F7", "F8"]
        script = "".join(f"key {k}; wait 2; shot {self.tmp / k}-a.png; wait 24; shot {self.tmp / k}-b.png; wait 1; dump; "
                         for k in keys)
        rc, states, log = viewer(SOLUTIONS, "--ghost", "--script", script + "quit", timeout=300)
        self.assertEqual(rc, 0, log)
        self.assertEqual([s["key"] for s in states], keys)
        for key, state in zip(keys, states):
            with self.subTest(scene=state["scene"]):
                self.assertEqual(state["error"], "")
                self.assertGreater(state["kinetic_energy"], 0.1, "bodies move")
                self.assertTrue(state["ghost"])
                self.assertEqual(state["ghost_difference"], 0.0)
                a, b = self.tmp / f"{key}-a.png", self.tmp / f"{key}-b.png"
                self.assertGreater(not_sky_fraction(b), 0.2)
                self.assertGreater(changed_pixels(a, b, (0, 150, 920, 720)), 500, "the bodies move on screen")
                if key in ("9", "F3"):  # a floor that walls enclose: the box's, the table's cloth
                    cloth = count_pixels(b, lambda p: p[0] < 90 and p[1] > p[0] + 40 and p[2] > p[0] + 15)
                    self.assertGreater(cloth, 20000, "the enclosed floor is drawn in the walls' green")

    def test_every_soft_body_scene_draws_its_meshes_and_the_ghost_agrees(self):
        # Worksheet 8's scenes by name, each a moment after its start: the meshes drawn in their
        # colours; then from the start again with the reference ghost ('o'), after as long: the
        # panel's rows, the reference agreeing with itself.
        scenes = {"flag": ["flag"], "cloth-on-sphere": ["cloth"], "cloth-on-table": ["cloth"], "soft-cube": ["cube"],
                  "soft-ball": ["ball"], "rope-pbd-xpbd": ["rope-pbd", "rope-xpbd"],
                  "cloth-stretchy-stiff": ["stretchy", "stiff"]}
        for scene, meshes in scenes.items():
            with self.subTest(scene=scene):
                shot = self.tmp / f"{scene}.png"
                rc, states, log = viewer(SOLUTIONS, scene, "--script", f"wait 40; shot {shot}; wait 1; key o; wait 40; dump; quit")
                self.assertEqual(rc, 0, log)
                state = states[0]
                self.assertEqual(state["error"], "")
                self.assertEqual([m["name"] for m in state["soft"]], meshes)
                for m in state["soft"]:
                    self.assertIn(m["method"], ("PBD", "XPBD"))
                    self.assertGreater(m["particles"], 50)
                    self.assertGreater(m["constraints"], m["particles"] // 2, "a rope has one per segment")
                    self.assertEqual(m["volume_ratio"] is None, m["kind"] != "soft body")
                self.assertTrue(state["ghost"])
                self.assertEqual(state["ghost_difference"], 0.0, "the reference agrees with itself")
                # The first mesh's colour, crimson, lit (its back paler).
                # (A rope, the thinnest, covers about 1500 pixels; nothing else in these scenes is red.)
                drawn = count_pixels(shot, lambda p: p[0] > max(p[1], p[2]) + 35, (0, 0, 920, 720))
                self.assertGreater(drawn, 1000, "the first mesh is drawn")

    def test_drag_a_particle_with_the_mouse(self):
        # The flag, flat at its start, facing the camera: its free top corner (particle 29 of 30 x 20)
        # grabbed and pulled to where its bottom row's particle 590 is: it follows, held, and the
        # cloth with it; let go, it is no longer held.
        shot = self.tmp / "drag.png"
        rc, states, log = viewer(SOLUTIONS, "flag", "--paused", "--script",
                                 "move @flag#29; wait 1; dump; down left @flag#29; move @flag#590; dump;"
                                 f" key space; wait 40; dump; shot {shot}; wait 1; up left @flag#590; wait 5; dump; quit")
        self.assertEqual(rc, 0, log)
        hover, grabbed, pulled, released = states
        self.assertEqual(hover["hovered_particle"], "flag#29")
        self.assertEqual(grabbed["selected_particle"], "flag#29")
        self.assertIsNone(grabbed["selected"], "a particle, not a body")
        self.assertTrue(grabbed["dragging"])
        self.assertFalse(released["dragging"])
        start, end = grabbed["selected_particle_position"], pulled["selected_particle_position"]
        self.assertLess(end[1], start[1] - 0.5, "pulled down the flag's 0.95 m towards the cursor")
        self.assertEqual(released["selected_particle"], "flag#29")
        self.assertGreater(not_sky_fraction(shot), 0.2)

    def test_the_soft_body_panel_sets_the_iterations_and_shows_the_links(self):
        plain, links = self.tmp / "plain.png", self.tmp / "links.png"
        rc, states, log = viewer(SOLUTIONS, "cloth-stretchy-stiff", "--paused", "--steps", 200, "--script",
                                 f"dump; set constraint-iterations 4; wait 1; shot {plain}; wait 1; set links on; wait 1;"
                                 f" shot {links}; wait 1; dump; set constraint-iterations 0; dump; quit")
        self.assertEqual(rc, 0, log)
        scene, four, clamped = states
        self.assertEqual(scene["constraint_iterations"], 15, "the scene's own sweeps")
        self.assertEqual(four["constraint_iterations"], 4)
        self.assertEqual(clamped["constraint_iterations"], 1, "at least one sweep")
        self.assertFalse(scene["links_shown"])
        self.assertTrue(four["links_shown"])
        stretchy, stiff = scene["soft"]
        self.assertGreater(stretchy["largest_stretch"], 5 * stiff["largest_stretch"], "the stretchy cloth sags long")
        # The links over the cloths: shear blue and bending green lines where the surfaces were.
        blue = lambda p: p[2] > 200 and p[0] < 90 and p[1] < 140
        self.assertEqual(count_pixels(plain, blue, (0, 150, 920, 720)), 0)
        self.assertGreater(count_pixels(links, blue, (0, 150, 920, 720)), 2000)
        rc, _, log = viewer(SOLUTIONS, "flag", "--script", "set links maybe; quit")
        self.assertEqual(rc, 2)
        self.assertIn("got 'set links maybe'", log)

    def test_every_fluid_scene_draws_its_particles_in_the_container(self):
        # Worksheet 9's scenes by name, a moment after their start: the fluid in its tank, coloured by
        # density error (the diverging map: blue at a free surface, red where compressed), then by speed
        # (the sequential map, no red); the panel's figures in the dump, none of the particles outside.
        methods = {"dam-break": "PBF", "dam-break-sph": "WCSPH", "drop-into-pool": "PBF", "pour-onto-sphere": "PBF",
                   "tank-slosh": "PBF"}
        for scene, method in methods.items():
            with self.subTest(scene=scene):
                density, speed = self.tmp / f"{scene}-density.png", self.tmp / f"{scene}-speed.png"
                rc, states, log = viewer(SOLUTIONS, scene, "--paused", "--steps", 40, "--script",
                                         f"dump; shot {density}; wait 1; set fluid-colour speed; wait 1; shot {speed};"
                                         " wait 1; set fluid-iterations 7; dump; quit")
                self.assertEqual(rc, 0, log)
                before, after = states
                self.assertEqual(before["error"], "")
                fluid = before["fluid"]
                self.assertEqual(fluid["method"], method)
                self.assertGreater(fluid["particles"], 500)
                self.assertEqual(fluid["outside"], 0, "the fluid stays in its closed tank")
                self.assertEqual(fluid["colouring"], "density error")
                self.assertEqual(after["fluid"]["colouring"], "speed")
                if method == "PBF":
                    self.assertEqual(after["fluid"]["iterations"], 7)
                # A free surface's particles read less dense than rho0: blue under the density map.
                blue = lambda p: p[2] > p[0] + 80 and p[2] > 120
                red = lambda p: p[0] > p[1] + 60 and p[0] > p[2] + 60  # the map's yellow end is not red
                self.assertGreater(count_pixels(density, blue, (0, 130, 920, 720)), 500, "the surface in blue")
                self.assertEqual(count_pixels(speed, red, (0, 130, 920, 720)), 0, "no red in the speed map")
                self.assertGreater(changed_pixels(density, speed, (0, 130, 920, 720)), 2000, "the colouring changed")

    def test_a_fluid_particle_is_dragged_through_the_tanks_front(self):
        # The dam break's column seen through the tank's glass front: a particle at the column's front
        # grabbed and led to the right; the fluid lets it through and it stays in the tank.
        rc, states, log = viewer(SOLUTIONS, "dam-break", "--paused", "--script",
                                 "down left 300 420; dump; move 420 420; key space; wait 30; dump; up left 420 420;"
                                 " wait 2; dump; quit")
        self.assertEqual(rc, 0, log)
        grabbed, led, released = states
        self.assertIsNotNone(grabbed["fluid"]["selected"], log)
        self.assertIsNone(grabbed["selected"], "a particle, not the tank's wall")
        self.assertTrue(grabbed["dragging"])
        self.assertGreater(led["fluid"]["selected_position"][0], grabbed["fluid"]["selected_position"][0] + 0.1,
                           "led to the right")
        self.assertFalse(released["dragging"])
        self.assertEqual(released["fluid"]["outside"], 0)

    def test_the_fluid_drawing_is_timed_apart_from_the_physics(self):
        # --fluid-particles fills the container for the drawing's benchmark (the time is reported, not
        # tested: the machine's load decides it).
        rc, _, log = viewer(SOLUTIONS, "pour-onto-sphere", "--fluid-particles", 20000, "--paused", "--frames", 5,
                            "--benchmark")
        self.assertEqual(rc, 0, log)
        self.assertIn("fluid particles: 20000, drawing the scene:", log)
        rc, _, log = viewer(SOLUTIONS, "dam-break", "--fluid-particles", 0, "--frames", 1, "--benchmark")
        self.assertEqual(rc, 2)
        self.assertIn("--fluid-particles", log)

    def test_the_benchmarks_block_of_fluid_shows_as_shaded_spheres(self):
        # The 20 000 particles --fluid-particles lays on a lattice, most of them hidden behind the
        # block's outer layers (and left out of the drawing): what shows in the fluid's box on screen is
        # a wall of spheres, white (the rest density's colour) where lit and darker towards their rims.
        shot = self.tmp / "block.png"
        rc, states, log = viewer(SOLUTIONS, "pour-onto-sphere", "--fluid-particles", 20000, "--paused", "--script",
                                 f"dump; shot {shot}; quit")
        self.assertEqual(rc, 0, log)
        view = states[0]["view"]
        left, top, right, bottom = view["bodies"][-1]  # the fluid's, after the bodies'
        counted = colours(shot, tuple(int(v) for v in (left, max(top, view["overlay"][3]), right, bottom)))
        total = sum(n for n, _ in counted)
        sky = sum(n for n, p in counted if max(abs(a - b) for a, b in zip(p, SKY)) <= 12)
        lit = sum(n for n, p in counted if min(p) > 225)
        shaded = sum(n for n, p in counted if max(p) < 170)
        # The box is the block's on screen but for the corners that perspective leaves (a few per cent).
        self.assertLess(sky, 0.15 * total, "the block fills its box")
        self.assertGreater(lit, 0.1 * total, "the spheres' lit sides")
        self.assertGreater(shaded, 0.1 * total, "the spheres' shaded rims: spheres, not flat discs")

    def test_recording_writes_frames(self):
        rec = self.tmp / "rec"
        rc, states, log = viewer(SOLUTIONS, "projectile", "--script", "wait 1; key v; wait 10; key v; dump; quit",
                                 "--out", rec)
        self.assertEqual(rc, 0, log)
        folders = [p for p in rec.iterdir() if p.is_dir()]
        self.assertEqual(len(folders), 1, log)
        self.assertGreaterEqual(len(list(folders[0].glob("frame_*.png"))), 10)
        self.assertFalse(states[0]["recording"])
        # ./lab installs ffmpeg, so stopping a recording also makes a video of the frames.
        video = folders[0] / "video.mp4"
        self.assertTrue(video.is_file(), log)
        probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-show_entries", "stream=width,height,nb_read_frames",
                                "-of", "csv=p=0", str(video)], capture_output=True, text=True)
        width, height, frames = map(int, probe.stdout.strip().split(","))
        self.assertEqual((width, height), (1280, 720))
        self.assertEqual(frames, len(list(folders[0].glob("frame_*.png"))))

    def test_bad_input_is_an_error_not_a_crash(self):
        rc, _, log = viewer(SOLUTIONS, "no-such-scene", "--frames", 1)
        self.assertEqual(rc, 2)
        self.assertIn("scene: expects a scene name or key such as falling-sphere or 1", log)
        self.assertIn("got 'no-such-scene'", log)
        rc, _, log = viewer(SOLUTIONS, "--script", "key 1; frobnicate; quit")
        self.assertEqual(rc, 2)
        self.assertIn("--script: expects commands such as", log)
        self.assertIn("got 'frobnicate'", log)
        for speed in ("9", "0", "fast", "nan"):  # the panel's slider goes from 1/64 to 8
            rc, _, log = viewer(SOLUTIONS, "--script", f"set speed {speed}; quit")
            self.assertEqual(rc, 2, speed)
            self.assertIn(f"got 'set speed {speed}'", log)
        rc, _, log = viewer(SOLUTIONS, "--frames", 1, "--out", "/proc/no-such-folder")
        self.assertEqual(rc, 2)
        self.assertIn("--out: expects a folder that exists or can be made, and is writable", log)

    def test_real_x_events_reach_the_handlers(self):
        # xdotool sends real key, button, motion and wheel events through the X server to the window.
        script = self.tmp / "events.sh"
        script.write_text(f"""#!/bin/sh
{" ".join(f'"{a}"' for a in START)} "{SOLUTIONS}" static-and-movable --script "dump; wait 900; dump; quit" &
viewer=$!
window=$(xdotool search --sync --name "Game Physics Lab" | head -1)
xdotool mousemove --window "$window" 560 650
xdotool windowfocus --sync "$window" 2>/dev/null
xdotool key --window "$window" g
xdotool key --window "$window" space
xdotool click 4
xdotool mousedown 1 mousemove 620 600 mouseup 1
wait $viewer
""")
        script.chmod(0o755)
        proc = subprocess.run([*HEADLESS, str(script)],
                              capture_output=True, text=True, timeout=120)
        self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)
        states = [json.loads(l[len("state "):]) for l in proc.stdout.splitlines() if l.startswith("state ")]
        start, end = states
        self.assertFalse(end["gravity"], "key g")
        self.assertTrue(end["paused"], "key space")
        self.assertLess(end["camera_distance"], start["camera_distance"], "wheel up zooms in")
        self.assertNotEqual(end["camera_eye"], start["camera_eye"], "a left drag on the floor orbits")

    def test_escape_quits_cleanly(self):
        rc, states, log = viewer(SOLUTIONS, "--script", "wait 3; key esc")
        self.assertEqual(rc, 0, log)


@unittest.skipUnless(SOLUTIONS and ASSIGNMENTS, "run by CTest after the build")
class LabCommands(unittest.TestCase):
    """The commands a newcomer types, without a display."""

    def lab(self, *args):
        env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
        return subprocess.run([str(ROOT / "lab"), *map(str, args)], capture_output=True, text=True, env=env,
                              cwd=ROOT, timeout=300)

    def test_viewer_headless_writes_frames(self):
        with tempfile.TemporaryDirectory() as tmp:
            proc = self.lab("viewer", "--solutions", "--headless", "projectile", "--frames", 3, "--out", tmp)
            self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)
            self.assertEqual(sorted(p.name for p in pathlib.Path(tmp).iterdir()),
                             ["frame_00001.png", "frame_00002.png", "frame_00003.png", "video.mp4"])

    def test_viewer_without_a_display_says_what_to_do(self):
        proc = self.lab("viewer")
        self.assertEqual(proc.returncode, 2)
        self.assertIn("--headless", proc.stderr)

    def test_run_without_a_display_prints_the_summary_and_a_snapshot(self):
        proc = self.lab("run", "--solutions", "--scene", "2", "--steps", 50)
        self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)
        self.assertIn("total energy:", proc.stdout)
        snapshot = ROOT / "build" / "snapshots" / "masses.png"
        self.assertIn(str(snapshot.relative_to(ROOT)), proc.stdout)
        self.assertFalse((snapshot.parent / "video.mp4").exists(), "one frame makes no video")
        self.assertGreater(not_sky_fraction(snapshot), 0.2)


if __name__ == "__main__":
    unittest.main()
