"""The noise of several balls in operation: the steady click train of a multi-ball attractor at a listener.

A multi-ball attractor (:mod:`acoustiviz.dynamics.balls_forced`) keeps its collisions (times, kinds,
approach speeds) but not the motion that places two balls when they meet, so its motion is run again:
:func:`~acoustiviz.dynamics.simulate_balls` with the excitation, from its final state (a section point,
forcing phase 0; inside a contact, the latest section point before it outside every contact, or with
none such its pressed balls moved apart to touch,
:func:`~acoustiviz.dynamics.balls_forced.restart_state`), sampled :data:`SAMPLES_PER_CYCLE` times per
forcing cycle, for one forcing cycle and then its measured cycles. The collisions that begin within the
measured cycles (after the first one, so a contact under way at the section point is met from its start)
are the train of one window: every collision, ball-wall and ball-ball, each cavity from its place, with
the geometry's images (a room's to its order and tolerance), as :func:`acoustiviz.sound.render_balls`
hears a free run. The train is repeated and its levels taken as for one ball
(:func:`acoustiviz.sound.operating.train_window`, :func:`~acoustiviz.sound.operating.train_noise`): the
same interval, lead-in and level columns.

A non-periodic motion is not the measured stretch: run again for a lead-in and at least ``seconds`` s
(:func:`~acoustiviz.sound.operating.rerun_cycles`, at most its measured cycles), it is another, shorter
stretch of the same motion (its rendering says so). One ball in one cavity radiates as the one ball of
:func:`acoustiviz.sound.operating.operating_noise` (the scene's sphere), so the two paths agree to the
difference of their solvers' runs.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import PAPER_RADIUS
from ..errors import ParameterError
from .balls_sound import ball_clicks, check_ball_scene, render_clicks
from .operating import (
    NOISE_RATE,
    OperatingNoise,
    check_seconds,
    default_listener,
    rerun_cycles,
    train_noise,
    train_window,
)
from .sources import cavity
from .synthesis import ClickModel

__all__ = ["SAMPLES_PER_CYCLE", "balls_operating_noise", "steady_ball_clicks"]

#: Samples of the re-run motion per forcing cycle: they place two balls in contact (their mean centre
#: interpolated linearly between samples); the collision times and speeds are the solver's own.
SAMPLES_PER_CYCLE = 400


def steady_ball_clicks(steady, scene, click: ClickModel, *, positions=None, cycles: int | None = None):
    """The radiating spheres of one window of a multi-ball attractor, times in s from the window's start.

    Parameters
    ----------
    steady : acoustiviz.dynamics.forced.SteadyState
        A measured motion of :mod:`acoustiviz.dynamics.balls_forced` (its model a
        :class:`~acoustiviz.dynamics.MultiBallModel`).
    scene : CavityScene
        The surroundings, rebuilt around the first cavity's column (:func:`~.balls_sound.check_ball_scene`).
    click : ClickModel
        The ball-wall contact.
    positions : (n_cavities, 3) array_like, optional
        The cavities' offsets in m (:func:`~.balls_sound.cavity_places`).

    Returns
    -------
    clicks : BallClicks
        The clicks of the collisions that begin in the ``cycles`` forcing cycles (default its measured
        cycles) after the first cycle of the re-run (:func:`~.balls_sound.ball_clicks`), shifted to start at 0.
    restart : dict
        Where the re-run started: ``cycles_before_last`` (its section point, counted back from the final
        state) and ``overlap_removed_m`` (the compression of pressed balls moved apart, 0 if none).
    """
    from ..dynamics import simulate_balls
    from ..dynamics.balls_forced import restart_state

    model, period = steady.model, steady.excitation.period
    if not steady.success or len(steady.final_state) != 2 + 2 * model.n_balls:
        raise ParameterError("steady", "the noise of several balls needs a measured multi-ball motion")
    restart = restart_state(steady)
    if restart is None:
        raise ParameterError("steady", f"at {steady.excitation.frequency:g} Hz no section point of the motion "
                                       "can start a run: its collisions cannot be run again")
    cycles = steady.measured_cycles if cycles is None else int(cycles)
    duration = period * (1 + cycles)
    t_eval = np.linspace(0.0, duration, int(math.ceil((1 + cycles) * SAMPLES_PER_CYCLE)) + 1)
    run = simulate_balls(model, duration, initial=restart[1], rtol=steady.settings["rtol"], t_eval=t_eval,
                         excitation=steady.excitation)
    if not run.success:
        raise ParameterError("steady", f"re-running the attractor at {steady.excitation.frequency:g} Hz failed: "
                                       f"{run.message}")
    clicks = ball_clicks(run, scene, click, positions=positions)
    keep = (clicks.times >= period) & (clicks.times < duration)
    return clicks.take(keep).shifted(-period), {"cycles_before_last": restart[0], "overlap_removed_m": restart[2]}


def balls_operating_noise(steady, *, listener=None, kind: str = "plane", radius: float = PAPER_RADIUS,
                          seconds: float = 1.0, sample_rate: int = NOISE_RATE, settings=None,
                          positions=None) -> OperatingNoise:
    """Render a multi-ball attractor's steady collisions at a listener and give their weighted levels.

    Parameters
    ----------
    steady : acoustiviz.dynamics.forced.SteadyState
        A measured motion of :func:`acoustiviz.dynamics.balls_forced.ball_attractor_response`.
    listener : (3,) array_like, optional
        Position in m (default :func:`~.operating.default_listener`, 0.7 m at 45° above the plane).
    kind : {"free", "plane", "wall-floor", "room"}
        The configuration kind of the surroundings.
    radius : float
        Radius in m of the sphere one ball radiates as (several balls: each its own,
        :func:`~.balls_sound.radiating_radius`).
    seconds : float
        Least length of the interval in s, (0, 60]; it spans whole periods of the motion.
    sample_rate : {44100, 48000, 96000}
        Rate of the rendering and the levels in Hz (default 96 kHz).
    settings : dict, optional
        The geometry's settings (:func:`acoustiviz.sound.sources.cavity`), ``room`` for a shoebox room.
    positions : sequence, optional
        Several cavities: per cavity its offset in m, or None for its default (:func:`~.balls_sound.cavity_places`).

    Returns
    -------
    OperatingNoise
        Its ``balls`` holds the radiating spheres of the train; its rendering's ``levels`` give the
        collisions of the attractor's measured cycles and of the re-run window.
    """
    seconds = check_seconds(seconds)
    model = steady.model
    first = model.cavities[0]
    scene = cavity(kind, radius, first.gap, **(settings or {}))
    pts = default_listener(radius) if listener is None else np.asarray(listener, dtype=float)
    scene, places, pts = check_ball_scene(model, scene, pts, positions, name="listener")
    click = ClickModel(k_hertz=first.k_wall, mass=first.masses[0], main_mass=model.M)
    cycles = rerun_cycles(steady, seconds)
    one, restart = steady_ball_clicks(steady, scene, click, positions=places, cycles=cycles)
    c = scene.medium.c
    arrivals = one.times + np.array([np.linalg.norm(pts[0] - srcs[0].position) / c for srcs in one.sources])
    w = train_window(steady, arrivals, seconds, cycles=cycles)
    train = one.repeat(w.window, w.total) if w.total else one
    out = render_clicks(train, scene, click, pts, sample_rate=sample_rate, duration=w.end)
    noise = train_noise(steady, out, w, seconds, sequence=out.sequence, scene=scene, clicks=click,
                        listener=pts[0], balls=train)
    levels = noise.rendering["levels"]
    levels["collisions_measured"] = int(np.count_nonzero(np.asarray(steady.impact_speeds) > 0))
    levels["collisions_rendered_per_window"] = int(np.unique(one.collision).size)
    levels["restart"] = restart
    levels["motion"] = ("the attractor's latest section point outside every contact (its final state where it "
                        f"can) run again with the excitation for 1 + {cycles} "
                        f"cycles ({SAMPLES_PER_CYCLE} samples per cycle place the balls); the collisions of the last "
                        f"{cycles} are the train")
    if not w.total:
        levels["method"] = (f"non-periodic motion: {cycles} cycles (a lead-in and at least {seconds:g} s, at most "
                            f"its {steady.measured_cycles} measured) from a section point rendered "
                            f"once (another stretch of the motion than the measured one), levels over the last "
                            f"{noise.cycles} after a {noise.start:.3g} s lead-in")
    return noise
