"""The impact damper's records (paper eq 15; defaults Table 1 with d = 4 cm, started as in Figure 5).

One :class:`~acoustiviz.app.settings.table.Setting` per value of the damper model and its run, with
its command-line option (``acoustiviz damper``, ``auralize`` and ``forced``) and its scene key
(``[damper]``, and ``contact.k_hertz_n_m1_5``): the fixed ranges both front-ends check first. The
limits that follow from the physics (a contact that can be computed, a run long enough to measure
the damping) are checked afterwards by :func:`acoustiviz.core.limits.check_damper`, naming the same
option or key. Masses in kg, stiffnesses in N/m and N/m^1.5, dashpots in N s/m, lengths in m,
speeds in m/s, times in s.
"""

from __future__ import annotations

import dataclasses

from ...constants import (
    AUTO_TOLERANCE_RANGE,
    BALL_STARTS,
    DEFAULT_DURATION,
    DEFAULT_RTOL,
    PAPER_GAP,
    PAPER_V0,
    SCENE_SOLVERS,
    SOLVER_RTOL_RANGE,
    TABLE1_PARAMETERS,
)
from .table import Setting, check_values

__all__ = ["MODEL", "CONTACT_LAW", "RUN", "SOLVER", "DAMPER", "BALLS", "BALL_START", "CAVITY", "check_values"]

_D = "damper"

#: The damper model (paper eq 15).
MODEL = (
    Setting("M", "--M", "main_mass_kg", "float", TABLE1_PARAMETERS["M"], "main mass M", "kg", low=0.0, high=1e6,
            low_open=True, table=_D, metavar="KG"),
    Setting("K", "--K", "stiffness_n_m", "float", TABLE1_PARAMETERS["K"], "main spring stiffness K", "N/m", low=0.0,
            high=1e12, low_open=True, table=_D, metavar="N/M"),
    Setting("C", "--C", "damping_n_s_m", "float", TABLE1_PARAMETERS["C"], "main viscous dashpot C", "N s/m", low=0.0,
            high=1e9, table=_D, metavar="N*S/M"),
    Setting("m", "--m", "impact_mass_kg", "float", TABLE1_PARAMETERS["m"], "impact mass m", "kg", low=0.0, high=1e5,
            low_open=True, table=_D, metavar="KG"),
    Setting("gap", "--gap", "gap_m", "float", PAPER_GAP, "total free travel d of the impact mass", "m", low=0.0,
            high=10.0, low_open=True, table=_D, metavar="M"),
    Setting("k_hertz", "--k-hertz", "k_hertz_n_m1_5", "float", TABLE1_PARAMETERS["k_hertz"],
            "Hertz contact stiffness K_HZ (a scene's default: from sphere.material and contact.surface, else "
            "5.6e8)", "N/m^1.5", low=0.0, high=1e14, low_open=True, scene_default=None, table="contact",
            metavar="N/M^1.5"),
    Setting("c1", "--c1", "contact_damping_n_s_m", "float", TABLE1_PARAMETERS["c1"], "contact damping c1", "N s/m",
            low=0.0, high=1e9, table=_D, metavar="N*S/M"),
)

#: How the contact force behaves as the bodies part (``acoustiviz damper`` and ``auralize``, a scene's [damper]).
CONTACT_LAW = (
    Setting("clip_tensile", "--clip-tensile", "clip_tensile", "bool", False,
            "clip the contact force at zero: no pull as the bodies part (default: the paper's form, which may pull)",
            table=_D),
)

#: The run: the initial state of the main mass, the simulated time and the event solver's tolerance.
RUN = (
    Setting("x0", None, "initial_displacement_m", "float", 0.0, "initial displacement of the main mass", "m",
            low=-10.0, high=10.0, table=_D),
    Setting("v0", "--v0", "initial_velocity_m_s", "float", PAPER_V0, "initial velocity of the main mass", "m/s",
            low=-1e3, high=1e3, table=_D, metavar="M/S"),
    Setting("duration", "--duration", "duration_s", "float", DEFAULT_DURATION, "simulated time", "s", low=0.0,
            high=1e4, low_open=True, table=_D, metavar="S"),
    Setting("rtol", "--rtol", "tolerance", "float", DEFAULT_RTOL,
            "relative accuracy of impact times and speeds (event and impact-map: their contact tolerance, in "
            f"[{SOLVER_RTOL_RANGE[0]:g}, {SOLVER_RTOL_RANGE[1]:g}]; auto: the accuracy wanted, the solver it picks "
            f"running at min(rtol, {SOLVER_RTOL_RANGE[1]:g}); newmark: none, it takes a step)",
            low=min(SOLVER_RTOL_RANGE[0], AUTO_TOLERANCE_RANGE[0]),
            high=max(SOLVER_RTOL_RANGE[1], AUTO_TOLERANCE_RANGE[1]), table=_D, metavar="RTOL"),
)

#: The solver and its fixed step.
SOLVER = (
    Setting("solver", "--solver", "solver", "str", "event",
            "damper solver: event (exact free flight, adaptive contacts), newmark (the paper's fixed-step "
            "scheme), impact-map (instantaneous impacts) or auto (the cheapest whose error suits the tolerance, "
            "acoustiviz.dynamics.cheapest_solver)", choices=SCENE_SOLVERS, scene_default="auto", table=_D),
    Setting("dt", "--dt", None, "float", None, "Newmark step (default: 1/50 of the shortest possible contact)",
            "s", low=0.0, high=1e4, low_open=True, metavar="S"),
)

#: Every damper record (of ``acoustiviz damper`` and ``auralize``, a scene's [damper]).
DAMPER = MODEL + CONTACT_LAW + RUN + SOLVER

#: Several balls in the cavity (``acoustiviz damper`` and a scene's [damper]): N equal spheres of the impact
#: mass m in a column; the gap stays the free travel, the cavity's length less the sum of their diameters.
BALLS = (
    Setting("balls", "--balls", "balls", "int", 1,
            "number of equal spheres of mass m in the cavity, in a column (the gap is the cavity's length less "
            "their diameters; they start at rest, by default the gap split into N+1 equal spaces)", low=1, high=1000,
            table=_D, metavar="N"),
    Setting("k_hertz_ball", "--k-hertz-ball", "k_hertz_ball_n_m1_5", "float", None,
            "Hertz stiffness between two balls (default: paper eq 2 for two spheres of mass m of the balls' "
            "material, steel unless set; --k-hertz "
            "stays the ball-wall stiffness)", "N/m^1.5", low=0.0, high=1e14, low_open=True, table=_D,
            metavar="N/M^1.5"),
    Setting("c1_ball", "--c1-ball", "contact_damping_ball_n_s_m", "float", None,
            "contact damping between two balls (default: --c1)", "N s/m", low=0.0, high=1e9, table=_D,
            metavar="N*S/M"),
)

#: How the balls start and what they are made of (``acoustiviz damper`` and a scene's [damper]; the material
#: also of ``acoustiviz forced``, whose attractors come from its own starts; a cavity may give its own material).
BALL_START = (
    Setting("ball_start", "--ball-start", "ball_start", "str", "spaced",
            "where the balls start, at rest: spaced (the free travel split into N+1 equal spaces), low (packed "
            "touching on wall-, the free travel all above), high (packed on wall+) or random (the free travel "
            "split at N uniform random points, see --ball-seed); with several balls", choices=BALL_STARTS,
            table=_D),
    Setting("ball_seed", "--ball-seed", "ball_seed", "int", None,
            "seed of the random start: the same seed, the same run (default: a fresh one each run)", low=0,
            high=2**63 - 1, table=_D, metavar="S"),
    Setting("ball_material", "--ball-material", "ball_material", "str", "steel",
            "material of the balls from the catalogue (acoustiviz/assets/materials.toml): their radius from the "
            "mass m and its density, the ball-ball stiffness from paper eq 2; with several balls",
            table=_D, metavar="NAME"),
)


def _cavity_record(record: Setting, doc: str) -> Setting:
    """``record`` as a key of a scene's ``[[damper.cavities]]``: its range and unit, no option.

    Its default is None, the ``[damper]`` value, except the number of balls (one).
    """
    return dataclasses.replace(record, option=None, doc=doc, table="damper.cavities",
                               default=record.default if record.name == "balls" else None)


#: One cavity of several on the main mass (a scene's ``[[damper.cavities]]``; the Python API's
#: :class:`acoustiviz.app.settings.damper_job.DamperCavity`): its free travel, its column of equal balls,
#: their mass and the ball-ball contact. The ranges are those of the one-cavity records; a value left out
#: is the ``[damper]`` one (the ball-ball contact: as for ``balls``).
CAVITY = (
    _cavity_record(MODEL[4], "free travel of the cavity: its length less its balls' diameters (default: "
                             "damper.gap_m)"),
    _cavity_record(BALLS[0], "number of equal spheres in the cavity, in a column"),
    _cavity_record(MODEL[3], "mass of each ball of the cavity (default: damper.impact_mass_kg)"),
    _cavity_record(BALLS[1], "Hertz stiffness between two balls of the cavity (default: paper eq 2 for two "
                             "spheres of its ball mass and material)"),
    _cavity_record(BALLS[2], "contact damping between two balls of the cavity (default: "
                             "damper.contact_damping_n_s_m)"),
    dataclasses.replace(BALL_START[0], name="start", option=None, key="start", default=None,
                        table="damper.cavities",
                        doc="where the cavity's balls start, at rest: spaced, low, high or random (default: "
                            "damper.ball_start; random draws from damper.ball_seed, the cavities in order)"),
    dataclasses.replace(BALL_START[2], name="material", option=None, key="material", default=None,
                        table="damper.cavities",
                        doc="material of the cavity's balls from the catalogue (default: damper.ball_material)"),
    Setting("position", None, "position_m", "point", None,
            "where the cavity's sound comes from: the offset [x, y, z] of the cavity from the scene's sphere, the "
            "cavity moved rigidly (at [0, 0, 0] its struck-wall ball touches the struck surface where the scene's "
            "sphere does, the column along its axis); default: cavity k (from 0) k times the longest cavity's "
            "length plus the largest ball's diameter along the horizontal, perpendicular to the axis, with the "
            "most room (acoustiviz.sound.balls_sound.cavity_places). Every ball stays in the fluid, no two "
            "cavities overlap", "m", table="damper.cavities"),
)
