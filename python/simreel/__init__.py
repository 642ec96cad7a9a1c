"""simreel from Python: build, step, read, render and record rigid-body scenes.

A thin layer over the C++ core (the extension module ``simreel._simreel``): the scene parser, the
physics, the renderer and the encoders are the command line's. A scene built in code is written as
YAML and read by the same parser, so it is checked, and runs, exactly as the same scene written by
hand. Units: metres, kilograms, seconds, radians; quaternions w x y z. Reference: docs/python.md.

    import simreel
    scene = simreel.Scene.from_yaml("scenes/projectile.yaml")
    sim = scene.build()
    sim.step(240)                      # 1 s at the scene's 1/240 s step
    print(sim.time, sim.positions[0])  # s, m
"""
import json
import os

from ._simreel import InputError, Renderer, Simulation, StateError, VideoWriter, _Scene

__all__ = ["Scene", "Simulation", "Renderer", "VideoWriter", "InputError", "StateError"]


def _vec(v, n, what):
    try:
        out = [float(x) for x in v]
    except TypeError:
        raise ValueError(f"{what} must be a list of {n} numbers, not {v!r}") from None
    if len(out) != n:
        raise ValueError(f"{what} must have {n} numbers, not {len(out)}")
    return out


def _put(d, **keys):
    """d[key] = convert(value) for each key=(value, convert) whose value is given (None: not)."""
    for key, (value, convert) in keys.items():
        if value is not None:
            d[key] = convert(value) if convert else value


class Scene:
    """A scene: read from a YAML file or text, or built in code.

    Built in code, each ``add_*``/``set_*`` call adds the keys the scene format (scenes/README.md)
    gives that thing; the scene is checked when it is built (``build()``) or written (``to_yaml()``
    then ``from_string``), with the command line's messages. Errors are ``InputError``, a
    ``ValueError`` with ``.file``, ``.line``, ``.column`` and ``.key``.
    """

    def __init__(self, name="scene"):
        self._doc = {"simulation": {}, "video": {}, "bodies": []}
        self._name = name
        self._loaded = None  # a _Scene, for scenes read from a file or text
        self._base = os.getcwd()

    # ---- Reading.
    @staticmethod
    def from_yaml(path):
        """The scene in a YAML file (or a URDF / MJCF file); mesh paths relative to its folder."""
        s = Scene()
        s._loaded = _Scene.from_yaml(os.fspath(path))
        return s

    @staticmethod
    def from_string(text, path="<string>.yaml"):
        """A scene from its YAML text; `path` names it in messages, meshes are looked up beside it."""
        s = Scene()
        s._loaded = _Scene.from_string(text, os.fspath(path))
        return s

    # ---- Building in code.
    def _builder(self):
        if self._loaded is not None:
            raise ValueError("this scene was read from YAML: build a new Scene() to add to it in code")
        return self._doc

    def set_simulation(self, duration=None, timestep=None, integrator=None, gravity=None, **more):
        """The `simulation:` block: duration (s), timestep (s), integrator, gravity (m/s^2), ..."""
        sim = self._builder()["simulation"]
        _put(sim, duration=(duration, float), timestep=(timestep, float), integrator=(integrator, str),
             gravity=(gravity, lambda v: _vec(v, 3, "gravity")))
        sim.update(more)
        return self

    def set_video(self, width=None, height=None, fps=None):
        """The `video:` block: width and height (px), fps (frames per second of simulated time)."""
        _put(self._builder()["video"], width=(width, int), height=(height, int), fps=(fps, float))
        return self

    def set_camera(self, position=None, look_at=None, up=None, fov=None, auto=None, follow=None, **more):
        """The `camera:` block: position and look_at (m), up, fov (degrees), auto, follow, ..."""
        c = self._builder().setdefault("camera", {})
        _put(c, position=(position, lambda v: _vec(v, 3, "camera position")),
             look_at=(look_at, lambda v: _vec(v, 3, "camera look_at")), up=(up, lambda v: _vec(v, 3, "camera up")),
             fov=(fov, float), auto=(auto, bool), follow=(follow, None))
        c.update(more)
        return self

    def add_ground(self, size=None, friction=None, restitution=None, **more):
        """A static ground plane at z = 0, drawn (size: m, the drawn square's side)."""
        g = {}
        _put(g, size=(size, float), friction=(friction, float), restitution=(restitution, float))
        g.update(more)
        self._builder()["ground"] = g
        return self

    def add_body(self, name, shape=None, size=None, radius=None, height=None, mesh=None, density=None,
                 mass=None, position=None, orientation=None, linear_velocity=None, angular_velocity=None,
                 color=None, friction=None, restitution=None, type=None, colliders=None, show=None, **more):
        """A body. One collider from `shape` ("box" with size [x, y, z] m; "sphere" with radius;
        "capsule", "cylinder" with radius and height; "mesh" with mesh=path) and `density` (kg/m^3,
        default 1000) or `mass` (kg); or `colliders`, a list of collider dicts as in the scene format.
        position (m, world), orientation (w, x, y, z), linear_velocity (m/s), angular_velocity
        (rad/s, world), color (linear RGB 0-1), type ("dynamic", "static", "kinematic")."""
        def vec(n, what):
            return lambda v: _vec(v, n, f"body {name}: {what}")

        b = {"name": str(name)}
        _put(b, position=(position, vec(3, "position")), orientation=(orientation, vec(4, "orientation")),
             linear_velocity=(linear_velocity, vec(3, "linear_velocity")),
             angular_velocity=(angular_velocity, vec(3, "angular_velocity")), color=(color, vec(3, "color")),
             type=(type, str), show=(show, None))
        if colliders is None:
            if shape is None and mesh is None:
                raise ValueError(f"body {name}: give a shape (box, sphere, capsule, cylinder, mesh) or colliders")
            c = {"shape": "mesh" if shape is None else str(shape)}
            _put(c, size=(size, vec(3, "size")), radius=(radius, float), height=(height, float),
                 file=(mesh, lambda m: os.path.abspath(os.fspath(m))), friction=(friction, float),
                 restitution=(restitution, float))
            if mass is not None:
                c["mass"] = float(mass)
            else:
                c["density"] = float(1000 if density is None else density)
            colliders = [c]
        b["colliders"] = list(colliders)
        b.update(more)
        self._builder()["bodies"].append(b)
        return self

    def add_joint(self, type, bodies, **keys):
        """A joint: type ("revolute", "prismatic", "spherical", "fixed", "distance", ...), bodies
        [parent, child] by name ("world" for the ground), and its keys: anchor (m), axis, limits, ..."""
        j = {"type": str(type), "bodies": [str(b) for b in bodies]}
        j.update(keys)
        self._builder().setdefault("joints", []).append(j)
        return self

    def add_force(self, **keys):
        """A `forces:` entry (force, torque, impulse, spring, drag) with its keys."""
        self._builder().setdefault("forces", []).append(dict(keys))
        return self

    def set_overlays(self, **keys):
        """The `overlays:` block: title, hud, captions, labels, plots, legend."""
        self._builder().setdefault("overlays", {}).update(keys)
        return self

    def to_yaml(self):
        """The scene built in code as YAML text (JSON, YAML's flow style, one key a line)."""
        doc = {k: v for k, v in self._builder().items() if v or k == "bodies"}
        return "# " + self._name + ": built in Python\n" + json.dumps(doc, indent=2) + "\n"

    def _scene(self):
        if self._loaded is None:
            self._loaded = _Scene.from_string(self.to_yaml(), os.path.join(self._base, self._name + ".yaml"))
        return self._loaded

    # ---- Running.
    def build(self, threads=1):
        """A Simulation at the scene's start. `threads`: integration threads (results identical)."""
        return Simulation(self._scene(), threads)

    @property
    def name(self):
        return self._scene().name

    @property
    def duration(self):
        """s, the scene's duration (what the command line renders)."""
        return self._scene().duration

    @property
    def fps(self):
        return self._scene().fps

    @property
    def notes(self):
        return list(self._scene().notes)

    @property
    def warnings(self):
        return list(self._scene().warnings)
