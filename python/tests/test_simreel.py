"""simreel from Python, held to the command line: the same numbers, frames and errors.

Run by ctest (python_tests) with PYTHONPATH=build/python and SIMREEL_BIN set to the command.
"""
import csv
import os
import resource
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import simreel

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get("SIMREEL_BIN", os.path.join(ROOT, "build", "simreel"))
BOXES = os.path.join(ROOT, "tests", "data", "chunks", "boxes.yaml")
PENDULUM = os.path.join(ROOT, "tests", "data", "chunks", "pendulum_plot.yaml")


def cli(*args):
    r = subprocess.run([BIN, *args], capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stdout + r.stderr
    return r


def test_stepping_equals_the_command_lines_csv_bit_for_bit(tmp_path):
    out = tmp_path / "boxes.csv"
    cli("simulate", BOXES, "--csv", str(out), "--quiet")
    rows = list(csv.DictReader(open(out)))
    sim = simreel.Scene.from_yaml(BOXES).build()
    names = sim.body_names
    steps_per_frame = round(1 / (sim.timestep * 10))  # the scene's 10 fps
    by_time = {}
    for r in rows:
        by_time.setdefault(float(r["t"]), []).append(r)
    checked = 0
    for t in sorted(by_time)[:30]:
        target = round(t / sim.timestep)
        sim.step(target - sim.steps)
        assert sim.time == t
        pos, q, v, w = sim.positions, sim.orientations, sim.velocities, sim.angular_velocities
        for r in by_time[t]:
            i = names.index(r["body"])
            assert list(pos[i]) == [float(r["px"]), float(r["py"]), float(r["pz"])]
            assert list(q[i]) == [float(r["qw"]), float(r["qx"]), float(r["qy"]), float(r["qz"])]
            assert list(v[i]) == [float(r["vx"]), float(r["vy"]), float(r["vz"])]
            assert list(w[i]) == [float(r["wx"]), float(r["wy"]), float(r["wz"])]
            checked += 1
    assert steps_per_frame == 20 and checked == 30 * len(names)


def test_state_round_trip_and_determinism():
    scene = simreel.Scene.from_yaml(BOXES)
    a, b = scene.build(), scene.build(threads=2)
    a.step(150)
    saved = a.state()
    assert isinstance(saved, bytes) and len(saved) > 0
    a.step(200)
    end = a.positions.copy(), a.orientations.copy()
    a.set_state(saved)
    assert a.steps == 150
    a.step(200)
    assert np.array_equal(a.positions, end[0]) and np.array_equal(a.orientations, end[1])
    b.step(350)  # two threads: the same bits
    assert np.array_equal(b.positions, end[0]) and np.array_equal(b.angular_velocities, a.angular_velocities)


def test_state_is_the_command_lines_saved_state(tmp_path):
    cli("simulate", BOXES, "--duration", "1", "--save-state", str(tmp_path / "s.bin"), "--quiet")
    sim = simreel.Scene.from_yaml(BOXES).build()
    sim.set_state((tmp_path / "s.bin").read_bytes())
    other = simreel.Scene.from_yaml(BOXES).build()
    other.step(200)  # 1 s at 1/200 s
    assert sim.time == other.time == 1.0
    assert np.array_equal(sim.positions, other.positions)
    assert sim.state() == other.state()


def boxes_in_code():
    s = simreel.Scene("boxes")
    s.set_simulation(duration=5.0, timestep=0.005)
    s.set_video(width=160, height=120, fps=10)
    s.set_camera(position=[3, -4, 2.5], look_at=[0, 0, 0.5], up=[0, 0, 1], fov=40)
    s.add_ground(size=6)
    s.add_body("a", shape="box", size=[0.4, 0.3, 0.2], density=500, position=[0, 0, 0.6],
               color=[0.85, 0.35, 0.2], linear_velocity=[0.5, 0, 2], angular_velocity=[1, 2, 0])
    s.add_body("b", shape="box", size=[0.3, 0.3, 0.3], density=500, position=[0.2, 0.1, 1.6],
               color=[0.2, 0.45, 0.85], angular_velocity=[0, 3, 1])
    s.add_body("c", shape="sphere", radius=0.15, density=500, position=[-0.5, 0.3, 2.4],
               color=[0.3, 0.7, 0.3], linear_velocity=[0.4, -0.2, 0])
    return s


def test_a_scene_built_in_code_equals_the_same_scene_in_yaml():
    a = boxes_in_code().build()
    b = simreel.Scene.from_yaml(BOXES).build()
    assert a.body_names == b.body_names
    for i in range(len(a.body_names)):
        ma, mb = a.mass_properties(i), b.mass_properties(i)
        assert ma["mass"] == mb["mass"] and np.array_equal(ma["inertia_world"], mb["inertia_world"])
    a.step(1000)
    b.step(1000)
    assert a.state() == b.state()
    assert a.contacts() and len(a.contacts()) == len(b.contacts())


def test_mass_properties_and_contacts_are_physical():
    sim = simreel.Scene.from_yaml(BOXES).build()
    m = sim.mass_properties(0)
    assert m["mass"] == pytest.approx(500 * 0.4 * 0.3 * 0.2, rel=1e-12)  # density x volume
    # A box's inertia about its centre: m (b^2 + c^2) / 12 on each axis (at the start, unrotated).
    assert m["inertia_world"][2, 2] == pytest.approx(m["mass"] * (0.4**2 + 0.3**2) / 12, rel=1e-12)
    sim.step(1000)  # 5 s: everything has come to rest on the ground
    weight = sum(sim.mass_properties(i)["mass"] for i in range(3)) * 9.81
    # Resting: the ground's contact forces carry the bodies' weight (to the solver's 1%). A pair's
    # force is the one on body b (on a: its negative).
    ground = sim.body_names.index("ground")
    up = 0.0
    for c in sim.contacts():
        if c["body_a"] == ground:
            up += c["force"][2]
        elif c["body_b"] == ground:
            up -= c["force"][2]
    assert up == pytest.approx(weight, rel=0.01)


def test_render_shape_and_pixels_equal_the_command_lines_png(tmp_path):
    png = tmp_path / "at.png"
    cli("render", BOXES, "--at", "1.5", "-o", str(png), "--quiet")
    sim = simreel.Scene.from_yaml(BOXES).build()
    with simreel.Renderer(sim) as r:
        assert "osmesa" in r.info.lower() or "egl" in r.info.lower()
        sim.step(300)  # 1.5 s
        img = r.render()
        assert img.shape == (120, 160, 3) and img.dtype == np.uint8
        ref = read_png_rgb(png)
        assert ref.shape == img.shape
        assert np.array_equal(ref, img)
        # Top row first: the sky is at the top, the ground at the bottom.
        assert img[0].mean() != img[-1].mean()
        out = np.zeros_like(img)
        assert r.render(out=out) is not None and np.array_equal(out, img)
        with pytest.raises(ValueError, match=r"\(120, 160, 3\)"):
            r.render(out=np.zeros((10, 10, 3), np.uint8))
    with pytest.raises(RuntimeError, match="closed"):
        r.render()


def read_png_rgb(path):
    """An 8-bit RGB or RGBA PNG's pixels as (H, W, 3), through zlib alone (no imaging library)."""
    import struct
    import zlib
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, w, h, ctype = 8, b"", 0, 0, 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and ctype in (2, 6)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    c = 4 if ctype == 6 else 3
    stride = w * c
    out = np.zeros((h, stride), np.int32)
    prev = np.zeros(stride, np.int32)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = np.frombuffer(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)], np.uint8).astype(np.int32)
        cur = np.zeros(stride, np.int32)
        for x in range(stride):
            a = cur[x - c] if x >= c else 0
            b = prev[x]
            d = prev[x - c] if x >= c else 0
            if f == 0:
                p = 0
            elif f == 1:
                p = a
            elif f == 2:
                p = b
            elif f == 3:
                p = (a + b) // 2
            else:
                pa, pb, pc = abs(b - d), abs(a - d), abs(a + b - 2 * d)
                p = a if pa <= pb and pa <= pc else (b if pb <= pc else d)
            cur[x] = (line[x] + p) & 255
        out[y] = cur
        prev = cur
    return out.reshape(h, w, c)[:, :, :3].astype(np.uint8)


def test_a_thousand_renders_keep_memory_bounded():
    sim = simreel.Scene.from_yaml(BOXES).build()
    r = simreel.Renderer(sim, width=64, height=48)
    out = np.zeros((48, 64, 3), np.uint8)
    for _ in range(100):
        r.render(out)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # KiB
    for _ in range(1000):
        sim.step(1)
        r.render(out)
        r.render()  # a new array each time: freed by Python
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    assert after - before < 20 * 1024, f"{after - before} KiB more after 1,000 renders"
    r.close()


def test_stepping_in_a_thread_progresses_while_another_holds_the_gil():
    sim = simreel.Scene.from_yaml(BOXES).build()
    started = threading.Event()

    def work():
        started.set()
        sim.step(200000)

    t = threading.Thread(target=work)
    old = sys.getswitchinterval()
    t.start()
    started.wait()
    time.sleep(0.05)  # (sleeping lets the thread into step())
    sys.setswitchinterval(100.0)  # this thread now keeps the GIL while it runs Python
    try:
        s0 = sim.steps
        end = time.perf_counter() + 0.5
        while time.perf_counter() < end:
            pass
        s1 = sim.steps
    finally:
        sys.setswitchinterval(old)
    assert s1 > s0 + 100, f"the stepping thread made {s1 - s0} steps in 0.5 s while the GIL was held"
    t.join()


def test_bad_yaml_raises_with_file_line_column_and_key(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("simulation: { duration: 1 }\nbodies:\n  - name: a\n    positon: [0, 0, 1]\n"
                   "    colliders: [ { shape: sphere, radius: 0.1 } ]\n")
    with pytest.raises(simreel.InputError) as e:
        simreel.Scene.from_yaml(bad)
    assert isinstance(e.value, ValueError)
    assert e.value.file == str(bad) and e.value.line == 4 and e.value.column == 5
    assert e.value.key == "bodies[0].positon" and "did you mean 'position'" in str(e.value)
    with pytest.raises(simreel.InputError, match="duration"):
        simreel.Scene.from_string("simulation: { duration: -1 }\n")
    s = boxes_in_code()
    s.set_camera(fov=-5)  # validated as the command line validates it
    with pytest.raises(simreel.InputError) as e:
        s.build()
    assert e.value.key == "camera.fov"


def test_video_passes_ffprobe(tmp_path):
    path = tmp_path / "clip.mp4"
    sim = simreel.Scene.from_yaml(BOXES).build()
    with simreel.Renderer(sim) as r, simreel.VideoWriter(str(path), fps=10) as v:
        for _ in range(25):
            v.write(r.render())
            sim.step(20)
        with pytest.raises(ValueError, match="frame of"):
            v.write(np.zeros((10, 10, 3), np.uint8))
    probe = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-count_frames", "-show_entries",
                            "stream=codec_name,width,height,nb_read_frames", "-of", "csv=p=0", str(path)],
                           capture_output=True, text=True)
    assert probe.returncode == 0, probe.stderr
    assert probe.stdout.strip() == "h264,160,120,25"


def test_an_interrupted_with_block_leaves_a_playable_video(tmp_path):
    path = tmp_path / "cut.mp4"
    sim = simreel.Scene.from_yaml(BOXES).build()
    r = simreel.Renderer(sim)
    with pytest.raises(KeyboardInterrupt):
        with simreel.VideoWriter(str(path), fps=10) as v:
            for k in range(10):
                v.write(r.render())
                sim.step(20)
                if k == 6:
                    raise KeyboardInterrupt
    r.close()
    probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-show_entries", "stream=nb_read_frames",
                            "-of", "csv=p=0", str(path)], capture_output=True, text=True)
    assert probe.stdout.strip() == "7", probe.stdout + probe.stderr


def test_the_readmes_example_and_the_examples_script_run(tmp_path):
    readme = open(os.path.join(ROOT, "README.md")).read()
    start = readme.index("```python\n", readme.index("### From Python")) + len("```python\n")
    code = readme[start:readme.index("```", start)]
    assert 15 <= len(code.strip().splitlines()) <= 25  # the README promises a 20-line example
    (tmp_path / "out").mkdir()
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(os.path.abspath(simreel.__file__))))
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    assert "closed form" in r.stdout and (tmp_path / "out" / "drop.mp4").stat().st_size > 0
    # Before the first bounce the printed height is the closed form to the printed digits.
    for line in r.stdout.splitlines()[:10]:
        if line.startswith("t "):
            parts = line.split()
            assert parts[4] == parts[8], line
    r = subprocess.run([sys.executable, os.path.join(ROOT, "examples", "python_drop.py"), str(tmp_path / "ex.mp4")],
                       cwd=tmp_path, capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "ex.mp4").stat().st_size > 0 and "first landing" in r.stdout


def test_egl_draws_the_same_frame_as_osmesa_and_tears_down_cleanly(tmp_path):
    """Both GL backends on llvmpipe draw the same pixels; a script that leaves a renderer open exits
    without an EGL or GL error (the renderer is closed when the simulation goes)."""
    sim = simreel.Scene.from_yaml(BOXES).build()
    sim.step(100)
    try:
        egl = simreel.Renderer(sim, gl="egl")
    except (ValueError, RuntimeError) as e:
        pytest.skip(f"no EGL here: {e}")
    with egl, simreel.Renderer(sim, gl="osmesa") as osm:
        assert "egl" in egl.info.lower() and "osmesa" in osm.info.lower()
        assert np.array_equal(egl.render(), osm.render())
    script = ("import simreel\nsim = simreel.Scene.from_yaml(%r).build()\nr = simreel.Renderer(sim, gl='egl')\n"
              "r.render()\nprint('done')\n" % BOXES)
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(os.path.abspath(simreel.__file__))))
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env)
    assert r.returncode == 0 and r.stdout.strip() == "done", r.stderr
    assert "error" not in r.stderr.lower(), r.stderr
