"""Loading scenes: a validated :class:`Scene` with every default filled in."""

from __future__ import annotations

import copy
import math
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from types import MappingProxyType

from ..core.geometry import geometry
from ..errors import ParameterError
from .schema import _OUT, DEFAULT_LISTENER, OUTPUT_KINDS, SCHEMA
from .validate import (
    _GEOMETRY_KEYS,
    SceneError,
    _geometry_settings,
    _unknown,
    _validate_table,
    check_configuration,
    check_damper_physics,
    check_window,
    scene_frequencies,
)

__all__ = [
    "Scene",
    "load_scene",
    "scene_from_dict",
    "scene_from_text",
    "default_scene",
    "shipped_scenes",
]


# --------------------------------------------------------------------------- the scene
@dataclass(frozen=True)
class Scene:
    """A validated scene: every section filled with its defaults. Build it with :func:`load_scene`."""

    data: MappingProxyType
    source: str = "<scene>"
    outputs: tuple = field(default=())

    def section(self, name: str) -> dict:
        """A deep copy of one validated section (``"sphere"``, ``"damper"``, ...)."""
        return copy.deepcopy(self.data[name])

    @property
    def name(self) -> str:
        """The scene's short name."""
        return self.data["scene"]["name"]

    def wants(self, kind: str) -> bool:
        """Whether the scene asks for output ``kind``."""
        return kind in self.outputs

    def output(self, kind: str) -> dict:
        """Options of one requested output."""
        return copy.deepcopy(self.data["outputs"][kind])

    def output_or_defaults(self, kind: str) -> dict:
        """Options of output ``kind``: the scene's when it asks for it, else the schema's defaults."""
        if kind in self.outputs:
            return self.output(kind)
        return {k: copy.deepcopy(key.default) for k, key in SCHEMA["outputs"].keys[kind].keys.items()}

    # -- physics objects: the rules live in the application layer, shared with the command line
    def geometry_settings(self) -> dict:
        """The ``[configuration]`` settings that apply to its ``kind`` (:func:`~acoustiviz.core.geometry.geometry`).

        A room's come as ``{"room": settings}`` (the ``room`` argument of
        :func:`~acoustiviz.app.impacts.impact_setup` and :func:`~acoustiviz.app.wav.cavity`).
        """
        settings = _geometry_settings(self.data["configuration"])
        return {"room": settings} if _enclosed(self.data) else settings

    def room_sound(self):
        """The :class:`~acoustiviz.sound.RoomSound` of ``[outputs.wav]`` in a room (None: the exact render)."""
        from ..app.settings.auralize import ROOM_SOUND_SCENE_KEYS
        from ..app.wav import room_sound

        if not _enclosed(self.data):
            return None
        o = self.output_or_defaults("wav")
        try:
            rs = room_sound(late_tail=o["late_tail"], seed=o["tail_seed"], decay=o["tail_decay"],
                            transition=o["transition_s"], absorption_bands=o["absorption_bands"],
                            names=ROOM_SOUND_SCENE_KEYS)
            if rs is not None:
                settings = _geometry_settings(self.data["configuration"])
                geom = geometry("room", self.data["sphere"]["radius_m"], **settings)
                try:
                    rs.check_room(geom)
                except ParameterError as exc:
                    key = {**ROOM_SOUND_SCENE_KEYS, "order": "configuration.image_order"}[exc.name]
                    raise ParameterError(key, exc.detail) from None
            return rs
        except SceneError:
            raise
        except ParameterError as exc:
            raise SceneError(self.source, exc.name, exc.detail) from None

    def _impact_settings(self, radius: float | None = None) -> dict:
        s, c, table = self.data["sphere"], self.data["contact"], self.data["configuration"]
        return dict(radius=s["radius_m"] if radius is None else radius, k_hertz=c["k_hertz_n_m1_5"],
                    sphere_material=s["material"], surface_material=c["surface"], c=self.data["medium"]["c_m_s"],
                    rho=self.data["medium"]["rho_kg_m3"], config=table["kind"], **self.geometry_settings())

    def sphere_mass(self) -> float:
        """Sphere mass in kg: ``mass_kg``, else density (or the material's) times volume."""
        from ..app.impacts import sphere_mass
        from ..app.names import SCENE_IMPACT_KEYS

        s = self.data["sphere"]
        return sphere_mass(s["radius_m"], s["mass_kg"], s["density_kg_m3"], s["material"], names=SCENE_IMPACT_KEYS)

    def sphere_density(self) -> float:
        """Sphere density in kg/m³ (given, the material's, or 7800)."""
        from ..app.impacts import sphere_mass

        s = self.data["sphere"]
        if s["density_kg_m3"] is not None:
            return s["density_kg_m3"]
        return sphere_mass(1.0, None, None, s["material"]) / (4.0 / 3.0 * math.pi)

    def k_hertz(self, radius: float | None = None) -> float:
        """Hertz stiffness in N/m^1.5: given, else from the materials (sphere of ``radius``), else 5.6e8."""
        from ..app.impacts import k_hertz_from

        c, s = self.data["contact"], self.data["sphere"]
        return k_hertz_from(s["radius_m"] if radius is None else radius, c["k_hertz_n_m1_5"], s["material"],
                            c["surface"])[0]

    def damper_sphere_radius(self) -> float:
        """Radius in m of the sphere used for damper impacts (see ``sphere.damper_radius``)."""
        s = self.data["sphere"]
        if s["damper_radius"] == "given":
            return s["radius_m"]
        from ..core.materials import sphere_radius

        return sphere_radius(self.data["damper"]["impact_mass_kg"], self.sphere_density())

    def setup(self, velocity: float | None = None, kind: str | None = None, radius: float | None = None):
        """The single impact and its surroundings (:func:`acoustiviz.app.impacts.impact_setup`)."""
        from ..app.impacts import impact_setup
        from ..app.names import SCENE_IMPACT_KEYS

        partner = math.inf
        if self.data["contact"]["pulse_mass"] == "effective":
            partner = self.data["damper"]["main_mass_kg"]
        return impact_setup(velocity=self.data["impact"]["velocity_m_s"] if velocity is None else velocity,
                            mass=self.sphere_mass(), pulse=kind or self.data["contact"]["pulse"],
                            partner_mass=partner, **self._impact_settings(radius), names=SCENE_IMPACT_KEYS)

    def view_settings(self, view: str):
        """The settings object of a 3-D view: ``"balloon"``, ``"snapshot"`` or ``"animation"``.

        The keys of ``[grids]`` and ``[outputs.<view>]`` read through the view's records
        (:func:`acoustiviz.app.render_job.view_values`) onto :mod:`acoustiviz.app.settings.render`;
        errors name the scene keys.
        """
        from ..app.render_job import view_values
        from ..app.settings.render import SETTINGS_OF_VIEW

        return SETTINGS_OF_VIEW[view].from_values(view_values(self, view), scene=True, names=view_names(view))

    def medium(self):
        """The fluid as a :class:`~acoustiviz.core.medium.Medium`."""
        return self.setup().medium

    def geometry(self, radius: float | None = None):
        """The surfaces and image sources (:mod:`acoustiviz.core.geometry`) for a sphere of ``radius``."""
        return self.setup(radius=radius).geometry

    def impact(self, velocity: float | None = None):
        """The single impact (or one at ``velocity`` m/s) as an :class:`~acoustiviz.core.contact.Impact`."""
        return self.setup(velocity).impact

    def pulse(self, velocity: float | None = None, kind: str | None = None):
        """The acceleration pulse of :meth:`impact`."""
        return self.setup(velocity, kind).pulse

    def listeners(self, radius: float | None = None):
        """Listener names and positions: a list of ``(name, (3,) ndarray in m)``.

        Listeners given by distance and angle are placed from the centre of a sphere of
        ``radius`` (default ``sphere.radius_m``) touching the struck surface.
        """
        import numpy as np

        from ..core.geometry import observer_points

        geometry = self.geometry(radius)
        out = []
        for i, lst in enumerate(self.data["listeners"]):
            name = lst["name"] or f"listener{i + 1}"
            if lst["position_m"] is not None:
                pos = np.asarray(lst["position_m"], dtype=float)
            else:
                pos = observer_points(geometry, lst["distance_m"], math.radians(lst["angle_deg"]))[0]
            out.append((name, pos))
        return out


def _validate_listeners(raw, src, radius):
    if raw is None:
        return [dict(DEFAULT_LISTENER, position_m=None)]
    if not isinstance(raw, list) or not raw:
        raise SceneError(src, "listeners", "expected one or more [[listeners]] tables")
    from ..files import label_problem

    out = []
    seen = {}
    for i, item in enumerate(raw):
        path = f"listeners[{i}]"
        lst = _validate_table(item, SCHEMA["listeners"], src, path)
        name = lst["name"] or f"listener{i + 1}"  # the name that becomes part of file names
        problem = label_problem(name)
        if problem is not None:
            raise SceneError(src, f"{path}.name", f"becomes part of file names, so it {problem}")
        if name.lower() in seen:  # case-insensitive file systems would make them one file
            raise SceneError(src, f"{path}.name", f"{name!r} is already the name of listeners[{seen[name.lower()]}]; "
                                                  "each listener needs its own name (it names their files)")
        seen[name.lower()] = i
        polar = lst["distance_m"] is not None or lst["angle_deg"] is not None
        if lst["position_m"] is not None and polar:
            raise SceneError(src, path, "give either position_m or distance_m with angle_deg, not both")
        if lst["position_m"] is None:
            if lst["distance_m"] is None or lst["angle_deg"] is None:
                raise SceneError(src, path, "needs distance_m and angle_deg, or position_m")
            if lst["distance_m"] <= radius:
                raise SceneError(src, f"{path}.distance_m", f"listener inside the sphere: must be > radius = "
                                                            f"{radius:g} m, got {lst['distance_m']:g} m")
        out.append(lst)
    return out


def scene_from_dict(raw: dict, source: str = "<scene>") -> Scene:
    """Validate a parsed scene mapping and fill in every default.

    Parameters
    ----------
    raw : dict
        The parsed TOML document.
    source : str
        Name of the file (for messages).

    Raises
    ------
    SceneError
        On the first invalid entry, naming ``source``, the key path and the allowed values.
    """
    if not isinstance(raw, dict):
        raise SceneError(source, "<root>", "expected a TOML table")
    if "geometry" in raw:  # [geometry] is another name of [configuration]
        if "configuration" in raw:
            raise SceneError(source, "geometry", "give either [geometry] or [configuration], not both")
        raw = {("configuration" if k == "geometry" else k): v for k, v in raw.items()}
    conf_raw = raw.get("configuration")
    if isinstance(conf_raw, dict) and isinstance(conf_raw.get("absorption"), (int, float)) \
            and not isinstance(conf_raw.get("absorption"), bool):  # one value for every surface
        raw = {**raw, "configuration": {**conf_raw, "absorption": [conf_raw["absorption"]]}}
    for key in raw:
        if key not in SCHEMA:
            _unknown(source, "", key, SCHEMA)
    data = {}
    for name, table in SCHEMA.items():
        if name in ("listeners", "outputs"):
            continue
        data[name] = _validate_table(raw.get(name, {}), table, source, name)
    radius = data["sphere"]["radius_m"]
    _check_materials(data, source)
    _band_absorption(raw, data, source)
    check_window(data, raw, source, lambda free: Scene(MappingProxyType(free), source, ()).setup())
    check_configuration(data, source)
    data["listeners"] = _validate_listeners(raw.get("listeners"), source, radius)
    outputs = _validate_outputs(raw.get("outputs", {}), data, source)
    data["outputs"] = outputs
    order = tuple(k for k in OUTPUT_KINDS if k in outputs)
    scene = Scene(MappingProxyType(data), source, order)
    _check_geometry(scene)
    check_damper_physics(scene)  # the damper's limits at load, not at its first simulation
    if "wav" in outputs:
        scene.room_sound()  # the tail's and the bands' settings, refused here rather than mid-run
    return scene


def _check_materials(data: dict, source: str) -> None:
    """The sphere's mass or density and the contact's stiffness or surface: one of each, named materials."""
    s = data["sphere"]
    if s["mass_kg"] is not None and s["density_kg_m3"] is not None:
        raise SceneError(source, "sphere.mass_kg", "give either mass_kg or density_kg_m3, not both")
    from ..core.materials import material

    for path, name in (("sphere.material", s["material"]), ("contact.surface", data["contact"]["surface"])):
        if name is not None:
            try:
                material(name)
            except ParameterError as exc:
                raise SceneError(source, path, exc.detail) from None
    if data["contact"]["k_hertz_n_m1_5"] is not None and data["contact"]["surface"] is not None:
        raise SceneError(source, "contact.k_hertz_n_m1_5", "give either k_hertz_n_m1_5 or surface, not both")


def _band_absorption(raw: dict, data: dict, source: str) -> None:
    """``outputs.wav.absorption_bands``: checked, and each surface's least absorbing band as the room's absorption."""
    wav = raw.get("outputs", {}).get("wav") if isinstance(raw.get("outputs"), dict) else None
    text = wav.get("absorption_bands") if isinstance(wav, dict) else None
    if text is None:
        return
    key = "outputs.wav.absorption_bands"
    if not isinstance(text, str):
        raise SceneError(source, key, f"expected a string 'F:A,F:A,...', got {text!r}")
    if not _enclosed(data):
        raise SceneError(source, key, "only for a room ([geometry] kind = \"room\")")
    if data["configuration"]["absorption"] is not None:
        raise SceneError(source, key, "give either configuration.absorption or outputs.wav.absorption_bands, not both")
    from ..app.wav import least_absorbing
    from ..sound import parse_absorption_bands

    try:
        _, alpha = parse_absorption_bands(text, key)
    except ParameterError as exc:
        raise SceneError(source, key, exc.detail) from None
    data["configuration"]["absorption"] = least_absorbing(alpha)


def _validate_outputs(outs_raw, data: dict, source: str) -> dict:
    """The ``[outputs]`` tables, validated, with the checks that need the rest of the scene."""
    if not isinstance(outs_raw, dict):
        raise SceneError(source, "outputs", f"expected a table, got {outs_raw!r}")
    outputs = {}
    for kind, value in outs_raw.items():
        if kind not in _OUT:
            _unknown(source, "outputs", kind, _OUT)
        if value is False:
            continue
        if value is True:
            value = {}
        outputs[kind] = _validate_table(value, _OUT[kind], source, f"outputs.{kind}")
    for kind in ("sweep", "optimize"):
        if outputs.get(kind, {}).get("fill") is not None:  # the fill sets the gap: the gap's default is not taken
            if "gap_m" in outs_raw[kind]:
                raise SceneError(source, f"outputs.{kind}.fill", f"give either outputs.{kind}.gap_m (the free "
                                                                 f"travel) or outputs.{kind}.fill (the balls' "
                                                                 "fraction of the cavity), not both")
            outputs[kind]["gap_m"] = None
    _check_output_needs(outputs, data, source)
    return outputs


def _check_output_needs(outputs: dict, data: dict, source: str) -> None:
    """What some outputs need of the rest of the scene: listeners, a sweep, forcing frequencies."""
    if "wav" in outputs:
        wav = outputs["wav"]
        if (wav["late_tail"] or wav["absorption_bands"] is not None) and not _enclosed(data):
            key = "late_tail" if wav["late_tail"] else "absorption_bands"
            raise SceneError(source, f"outputs.wav.{key}", "only for a room ([geometry] kind = \"room\")")
        if wav["struck_wall"] not in (-1, 1):
            raise SceneError(source, "outputs.wav.struck_wall",
                             f"must be -1 or +1, got {outputs['wav']['struck_wall']}")
        if outputs["wav"]["stereo"] and len(data["listeners"]) < 2:
            raise SceneError(source, "outputs.wav.stereo", "needs two [[listeners]] (left, right)")
    if "design_table" in outputs and "sweep" not in outputs:
        raise SceneError(source, "outputs.design_table", "needs [outputs.sweep] in the same scene")
    if {"frequency_response", "bifurcation", "operating_noise"} & set(outputs):
        from ..core.limits import check_forcing_frequencies

        key = "excitation.frequencies_hz"
        try:
            check_forcing_frequencies(scene_frequencies(data["excitation"]["frequencies_hz"], key, source),
                                      M=data["damper"]["main_mass_kg"], K=data["damper"]["stiffness_n_m"])
        except SceneError:
            raise
        except ParameterError as exc:
            raise SceneError(source, key, exc.detail) from None


def _enclosed(data: dict) -> bool:
    """Whether the scene's ``[configuration] kind`` is a geometry that closes the fluid (a room)."""
    from ..core.geometry import geometry_class

    return geometry_class(data["configuration"]["kind"]).enclosed


#: :func:`acoustiviz.app.impacts.impact_setup` parameter -> scene key.
_SETUP_KEYS = {"radius": "sphere.radius_m", "mass": "sphere.mass_kg", "density": "sphere.density_kg_m3",
               "velocity": "impact.velocity_m_s", "k_hertz": "contact.k_hertz_n_m1_5"}


def _check_geometry(scene: Scene) -> None:
    """Listeners in the fluid; grids within the memory cap."""
    src = scene.source
    try:
        geometry = scene.geometry()
    except ParameterError as exc:
        key = {**{k: f"configuration.{v}" for k, v in _GEOMETRY_KEYS.items()}, **_SETUP_KEYS}.get(exc.name)
        if key is None:
            raise
        raise SceneError(src, key, exc.detail) from None
    import numpy as np

    for i, (_name, pos) in enumerate(scene.listeners()):
        if not bool(geometry.in_fluid(np.asarray(pos)[None, :])[0]):
            key = f"listeners[{i}]"
            lst = scene.data["listeners"][i]
            key += ".position_m" if lst["position_m"] is not None else ".angle_deg"
            raise SceneError(src, key, "listener inside the sphere, below the floor or behind the wall "
                                       f"(configuration {geometry.name!r}; the fluid is {geometry.fluid_text()})")
    grids = scene.data["grids"]
    _check_circles(scene, geometry)
    if scene.wants("level_map"):  # settings, memory and output size of the map, before any output is made
        from ..app.maps import SCENE_NAMES, plan_map

        m = scene.data["outputs"]["level_map"]
        try:
            plan_map(scene.pulse(), geometry, medium=scene.medium(), plane=m["plane"], height=m["height_m"],
                     extent=m["extent_m"], resolution=m["resolution"], max_memory_mb=grids["memory_limit_mb"],
                     names=SCENE_NAMES)
        except ParameterError as exc:
            raise SceneError(src, exc.name, exc.detail) from None
    _check_views(scene, geometry)


def view_names(view: str) -> dict:
    """API name of a 3-D view's setting -> its scene key."""
    from ..app.settings.render_job import JOB_OF_VIEW

    return JOB_OF_VIEW[view].scene_names()


def _check_views(scene: Scene, geometry) -> None:
    """The memory and output size of the scene's estimates within ``grids.memory_limit_mb``.

    The estimates are the command line's (:mod:`acoustiviz.app.budget`). The 3-D views' budgets and
    the directivity's angles are their jobs' own checks, made when the run builds every output's
    settings before the first (:func:`acoustiviz.app.scene_outputs.preflight`).
    """
    from ..app.budget import check_budget, scene_estimates

    cap = scene.data["grids"]["memory_limit_mb"]
    for estimate in scene_estimates(scene, geometry):  # the waveform's tables, a weighted directivity's sound
        try:
            check_budget(estimate(), cap, cap_name="grids.memory_limit_mb")
        except ParameterError as exc:
            raise SceneError(scene.source, exc.name, exc.detail) from None


def _check_circles(scene: Scene, geometry) -> None:
    """The directivity's circle (the first listener's distance) fits in the fluid.

    Checked at load time, before any output is made: in a room the circle must stay inside its walls,
    and the sound must reach the circle within the room's window; the message says the circle is the
    directivity's. The balloon's sphere is its job's own check (the view against the fluid), made
    before the first output (:func:`acoustiviz.app.scene_outputs.preflight`).
    """
    import numpy as np

    from ..field.directivity import circle_points, room_window

    src = scene.source
    if scene.wants("directivity"):
        lst = scene.data["listeners"][0]
        key = "listeners[0]." + ("position_m" if lst["position_m"] is not None else "distance_m")
        (_, pos), *_ = scene.listeners()
        try:
            pts = circle_points(geometry, float(np.linalg.norm(np.asarray(pos) - geometry.centre)), [0.0, math.pi / 2])
            room_window(geometry, pts, scene.medium())
        except ParameterError as exc:
            raise SceneError(src, key, f"the directivity's circle (its radius the first listener's distance "
                                       f"from the sphere's centre): {exc.detail}") from None


def scene_from_text(text: str, source: str = "<scene>") -> Scene:
    """Parse TOML text and validate it (see :func:`scene_from_dict`)."""
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(source, "<toml>", f"not valid TOML: {exc}") from None
    return scene_from_dict(raw, source)


def load_scene(path) -> Scene:
    r"""Load and validate a scene file (TOML).

    Raises
    ------
    SceneError
        If the file cannot be read or anything in it is invalid.

    Examples
    --------
    A scene naming only the paper's Figure 2 sphere and its waveform; every other key takes its
    default (K = 5.6e8 N/m^1.5, 1.4 m/s, a reflecting plane):

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder) / "fig2.toml"
    ...     _ = path.write_text('[sphere]\nradius_m = 0.01905\ndensity_kg_m3 = 7800.0\n[outputs.waveform]\n')
    ...     scene = load_scene(path)
    >>> scene.outputs, scene.geometry().name
    (('waveform',), 'plane')
    >>> round(scene.sphere_mass(), 4), round(scene.impact().duration * 1e6, 1)  # kg, µs
    (0.2259, 525.6)

    A value out of range is refused before any work, naming the key:

    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder) / "bad.toml"
    ...     _ = path.write_text("[sphere]\nradius_m = -0.01\n")
    ...     try:
    ...         load_scene(path)
    ...     except SceneError as err:
    ...         print(err.key, "|", err.detail)
    sphere.radius_m | must lie in (0, 1] m, got -0.01
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise SceneError(str(p), "<file>", f"cannot read the scene: {exc.strerror or exc}") from None
    except UnicodeDecodeError as exc:
        raise SceneError(str(p), "<file>", f"not a scene (TOML is UTF-8 text): {exc.reason} at byte {exc.start}") \
            from None
    except ValueError as exc:  # a NUL byte in the file name
        raise SceneError(repr(str(p)), "<file>", f"cannot read the scene: {exc}") from None
    return scene_from_text(text, str(p))


def shipped_scenes() -> dict:
    """Names and texts of the scenes shipped in ``assets/scenes`` (installed with the package)."""
    folder = resources.files("acoustiviz").joinpath("assets/scenes")
    return {f.name.removesuffix(".toml"): f.read_text("utf-8")
            for f in sorted(folder.iterdir(), key=lambda f: f.name) if f.name.endswith(".toml")}


def default_scene() -> Scene:
    """The built-in default scene: the paper's Table 1 damper striking a plane, listener at 0.7 m, 45°."""
    return scene_from_text(shipped_scenes()["default"], "<built-in default scene>")
