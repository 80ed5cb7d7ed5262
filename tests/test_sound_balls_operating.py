"""The noise of several balls in operation (:mod:`acoustiviz.sound.balls_operating`).

Checked against the single-ball operating noise (one ball through the multi-ball path), against the
periodicity of a two-ball attractor (the levels over one and two periods agree) and against the
attractor's own collisions (one collision rendered per impact row of its measured cycles).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from acoustiviz.constants import FORCED_RTOL, FORCED_TOLERANCE
from acoustiviz.dynamics import DamperModel, MultiBallModel, equal_balls
from acoustiviz.dynamics.balls_forced import ball_attractor_response
from acoustiviz.dynamics.forced import attractor_response
from acoustiviz.errors import ParameterError
from acoustiviz.sound.balls_operating import balls_operating_noise
from acoustiviz.sound.operating import operating_noise

#: Table 1 with C = 5 N s/m at 4 Hz and 10 N: a period-1 orbit for one ball, and for two in two cavities.
MODEL = replace(DamperModel(), C=5.0)
FORCE, FREQUENCY = 10.0, 4.0
#: Largest level difference in dB between the single-ball and the multi-ball path for one ball: the two
#: solvers (single-ball shooting, multi-ball event solver re-run from the final state) reach the same
#: orbit to their tolerances, and the rendering of one ball is the same function of the same clicks.
ONE_BALL_DB = 0.1
#: Largest difference in dB between the levels over one period and over two of a periodic train.
PERIODIC_DB = 1e-6
#: LAFmax after the lead-in: the F-weighted mean square within exp(-8) of its periodic state (F_SETTLE).
F_SETTLED_DB = 10 * np.log10(1 + np.exp(-8))
LEVELS = ("laeq_db", "lcpeak_db", "lafmax_db", "lzpeak_db", "lzeq_db", "sel_per_cycle_db", "sel_a_per_cycle_db")


def _attractor(model, **kwargs):
    resp = ball_attractor_response(model, [FREQUENCY], FORCE, starts=1, max_cycles=40, sweep="independent",
                                   tolerance=FORCED_TOLERANCE, rtol=FORCED_RTOL, **kwargs)
    (a,) = [a for _, _, a, _ in resp.entries()]
    return a


@pytest.fixture(scope="module")
def two_balls():
    """Two cavities, one ball of half the impact mass in each: a period-1 orbit with both balls striking."""
    cavity = equal_balls(1, MODEL.m / 2, MODEL.gap, MODEL.k_hertz, MODEL.c1)
    a = _attractor(MultiBallModel((cavity, cavity), MODEL.M, MODEL.K, MODEL.C))
    assert a.regime == "periodic-1" and a.success and a.impacts_per_cycle >= 4
    return a


def test_one_ball_through_the_multi_ball_path_is_the_single_ball_noise():
    (_, _, single, _), = attractor_response(MODEL, [FREQUENCY], FORCE, starts=1, max_cycles=40, sweep="independent",
                                             tolerance=FORCED_TOLERANCE, rtol=FORCED_RTOL).entries()
    multi = _attractor(MultiBallModel.from_damper(MODEL, 1))
    assert single.regime == multi.regime == "periodic-1"
    a = operating_noise(single, seconds=0.5)
    b = balls_operating_noise(multi, seconds=0.5)
    assert b.balls is not None and a.balls is None
    assert b.cycles == a.cycles and b.duration == pytest.approx(a.duration, abs=2 / a.sample_rate)
    for c in LEVELS:
        assert getattr(b, c) == pytest.approx(getattr(a, c), abs=ONE_BALL_DB), c


def test_a_periodic_train_has_the_same_levels_over_one_and_two_periods(two_balls):
    window = two_balls.measured_cycles * two_balls.excitation.period
    one = balls_operating_noise(two_balls, seconds=window)
    two = balls_operating_noise(two_balls, seconds=2 * window)
    assert (one.cycles, two.cycles) == (1, 2)
    assert two.duration == pytest.approx(2 * one.duration, abs=2 / one.sample_rate)
    for c in LEVELS:
        tol = F_SETTLED_DB if c == "lafmax_db" else PERIODIC_DB
        assert getattr(two, c) == pytest.approx(getattr(one, c), abs=tol), c
    # the second period of the interval is the first, sample for sample (the train is periodic)
    n = round(window * one.sample_rate)
    p = two.interval_pressure()
    assert np.allclose(p[n:2 * n], p[:n], rtol=0, atol=1e-9 * np.max(np.abs(p)))


def test_every_collision_of_the_attractor_is_heard_once_per_period(two_balls):
    nz = balls_operating_noise(two_balls, seconds=0.5)
    levels = nz.rendering["levels"]
    rows = int(np.count_nonzero(two_balls.impact_speeds > 0))
    assert rows > 0
    assert levels["collisions_measured"] == levels["collisions_rendered_per_window"] == rows
    # every copy of the window rendered: wall contacts one sphere each, ball-ball contacts two
    copies = round(nz.balls.times.max() // (two_balls.measured_cycles * two_balls.excitation.period)) + 1
    assert np.unique(nz.balls.collision).size == copies * rows
    ball_ball = int(np.count_nonzero(two_balls.impact_walls == 0))
    assert len(nz.balls) == copies * (rows + ball_ball)
    assert nz.rendering["balls"]["ball_ball_contacts"] == copies * ball_ball
    # the collisions re-run are the measured ones: same kinds, times and speeds to 1e-6
    per = two_balls.measured_cycles * two_balls.excitation.period
    first = nz.balls.take(nz.balls.times < per)
    t0 = two_balls.cycles * two_balls.excitation.period
    _, each = np.unique(first.collision, return_index=True)  # one sphere per collision
    assert np.sort(first.times[each]) == pytest.approx(np.sort(two_balls.impact_times - t0), abs=1e-6)
    assert np.sort(first.velocities[each]) == pytest.approx(np.sort(two_balls.impact_speeds), rel=1e-6)


def test_the_listener_in_a_column_is_refused(two_balls):
    with pytest.raises(ParameterError, match="^listener: "):
        balls_operating_noise(two_balls, listener=(0.0, 0.0, 0.03))


def test_a_non_periodic_motion_is_run_again_for_the_lead_in_and_the_interval():
    from types import SimpleNamespace

    from acoustiviz.dynamics.forced import Excitation
    from acoustiviz.sound.operating import F_SETTLE, rerun_cycles

    chaotic = SimpleNamespace(excitation=Excitation(4.0, 10.0), period=0, measured_cycles=128)
    lead = round(F_SETTLE * 4.0)
    assert rerun_cycles(chaotic, 0.5) == lead + 2
    assert rerun_cycles(chaotic, 60.0) == 128  # at most the measured cycles
    assert rerun_cycles(SimpleNamespace(excitation=Excitation(4.0, 10.0), period=2, measured_cycles=2), 60.0) == 2


def test_a_room_of_image_order_zero_hears_the_balls_as_free_field(two_balls):
    from acoustiviz.sound.sources import cavity

    first = two_balls.model.cavities[0]
    radius = float(first.radii[0])  # the balls' own: the scene's geometry is already the column's
    room = {"room": {"dimensions": "3,2.5,2", "source": f"1.5,1.2,{radius}", "absorption": "0.3", "order": 0}}
    places = [(0.0, 0.0, 0.0), (0.05, 0.0, 0.0)]
    heard = {}
    for kind, settings in (("room", room), ("free", {})):
        scene = cavity(kind, radius, first.gap, **settings)
        at = np.asarray(scene.geometry.contact_point, dtype=float) + [0.7, 0.3, 0.8]
        heard[kind] = balls_operating_noise(two_balls, listener=at, kind=kind, radius=radius, seconds=0.3,
                                            settings=settings, positions=places)
    assert heard["room"].rendering["balls"]["room"]
    for c in LEVELS:
        assert getattr(heard["room"], c) == pytest.approx(getattr(heard["free"], c), abs=1e-6), c
