"""What a scene run is made of below its runner: the records of written files and the scene's damper.

The producers of :mod:`acoustiviz.app.pipeline` (and those of the maps, levels, forced and sweep
outputs) return :class:`Product` records and draw on the figure helpers here; the scene's damper
model, initial state and solver choice are built here once for the runner and for scene sweeps.
Nothing here imports the runner, so the producers' modules and the runner import one way.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from . import damper as _damper

__all__ = ["Product", "new_figure", "save", "scene_damper_model", "damper_initial", "damper_solver"]


@dataclass(frozen=True)
class Product:
    """One file written by a run, with the figures worth reading in the summary."""

    kind: str
    path: Path
    figures: dict = field(default_factory=dict)


def new_figure():
    """A matplotlib Figure of the runner's size (7 x 4.2 in), laid out by constraints."""
    from matplotlib.figure import Figure

    return Figure(figsize=(7.0, 4.2), layout="constrained")


def save(fig, path: Path) -> Path:
    """Save ``fig`` atomically to ``path`` in the house style (:func:`acoustiviz.output.plot.style.save_figure`)."""
    from ..output.plot.style import save_figure

    return save_figure(fig, path)


def scene_damper_model(scene):
    """The scene's :class:`~acoustiviz.dynamics.DamperModel` (K_HZ for the damper sphere's radius)."""
    d = scene.section("damper")
    return _damper.damper_model(M=d["main_mass_kg"], K=d["stiffness_n_m"], C=d["damping_n_s_m"],
                                m=d["impact_mass_kg"], gap=d["gap_m"],
                                k_hertz=scene.k_hertz(scene.damper_sphere_radius()),
                                c1=d["contact_damping_n_s_m"], clip_tensile=d["clip_tensile"])


def damper_initial(scene):
    """The scene's initial damper state (main mass displaced and moving, impact mass centred at rest)."""
    from ..dynamics import InitialState

    d = scene.section("damper")
    return InitialState(x=d["initial_displacement_m"], v=d["initial_velocity_m_s"])


def damper_solver(scene, progress=None) -> str:
    """The scene's damper solver; ``"auto"`` is the cheapest whose error suits ``damper.tolerance``."""
    d = scene.section("damper")
    name, reason = _damper.choose_solver(d["solver"], scene_damper_model(scene), damper_initial(scene), d["tolerance"])
    if reason and progress is not None:
        progress(f"solver auto -> {name}: {reason}")
    return name
