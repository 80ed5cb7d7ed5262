"""Several balls in a sweep's designs: the fill of the cavity, and the evaluation of a multi-ball design.

A design with ``balls = N > 1`` holds N equal spheres of the design's mass ``m`` each in a column, as
``acoustiviz damper --balls N`` does (:meth:`acoustiviz.dynamics.MultiBallModel.from_damper`): each
ball's diameter ``D`` follows from its mass and its material's density (steel, or the design's sphere
material), and the design's gap is the cavity's free travel, its length less the N diameters.

Fill
----
The fill is the fraction of the cavity's length the balls take::

    fill = N D / (N D + gap),     so that     gap = N D (1 - fill) / fill,

in (0, 1): near 0 a long cavity with small balls, near 1 a cavity the column packs. A sweep gives either
gaps (the fill then follows) or fills (the gap then follows), never both. One ball has a fill too
(``N = 1``), the same rule.

Evaluation
----------
:func:`acoustiviz.sweep.evaluate.evaluate_balls` runs :func:`acoustiviz.dynamics.simulate_balls` from x = 0,
dx/dt = ``v0``, the balls at rest with the gap split into N + 1 equal spaces, sampled as ``damper --balls`` samples it
(:func:`acoustiviz.dynamics.metrics.sample_times`); the damping metrics come from the main mass's
sampled motion with its maxima refined by a parabola (:func:`acoustiviz.dynamics.metrics.damping_metrics`,
as ``damper --balls``). Every collision counts as an impact (ball-wall and ball-ball). The maximum SPL is
the largest over every collision of the peak of its own clicks (both bodies of a ball-ball contact,
each with its radius and mass; :func:`acoustiviz.sound.balls_sound.ball_clicks`) rendered alone at the
listener at :data:`~acoustiviz.constants.ANALYSIS_RATE` (:func:`acoustiviz.sound.balls_sound.render_clicks`):
a band-limited peak, where one ball's is the exact peak of its pulse. With ``levels`` the run's whole
click train is rendered (:func:`acoustiviz.sound.balls_sound.render_balls`) and its LAFmax, LCpeak and
LAeq over the run are reported. Several balls are heard in free field, on a plane, in a corner or in a
room (each sphere with the room's images of its own position, :mod:`acoustiviz.sound.balls_room`; a sweep
renders no late tail and no absorption bands). SI units.
"""

from __future__ import annotations

from ..errors import ParameterError

__all__ = ["BALL_COLUMNS", "BALL_MATERIAL", "ball_radius", "fill_of", "gap_of_fill", "design_balls_model"]

#: Columns a sweep with several balls (or fills) adds to ``sweep.csv``, after ``radius_m``.
BALL_COLUMNS = ("balls", "fill")
#: Material of the balls when the design names none (that of ``damper --balls``).
BALL_MATERIAL = "steel"


def ball_radius(mass: float, material: str = "") -> float:
    """Radius in m of one ball of ``mass`` kg of ``material`` (default :data:`BALL_MATERIAL`).

    The rule of :func:`acoustiviz.dynamics.equal_balls`: ``(3 m / (4 π ρ))^(1/3)``.

    Examples
    --------
    >>> round(ball_radius(0.0405), 5)
    0.01072
    """
    from ..core.materials import material as find_material
    from ..core.materials import sphere_radius

    return float(sphere_radius(mass, find_material(material or BALL_MATERIAL).density))


def fill_of(n: int, diameter: float, gap: float) -> float:
    """Fraction of the cavity's length taken by ``n`` balls of ``diameter`` m with free travel ``gap`` m.

    ``fill = n D / (n D + gap)`` (module docstring).

    Examples
    --------
    >>> fill_of(2, 0.02, 0.04)
    0.5
    """
    taken = n * diameter
    return float(taken / (taken + gap))


def gap_of_fill(n: int, diameter: float, fill: float) -> float:
    """Free travel in m of ``n`` balls of ``diameter`` m that fill the fraction ``fill`` of the cavity.

    ``gap = n D (1 - fill) / fill``, the inverse of :func:`fill_of`.

    Examples
    --------
    >>> gap_of_fill(2, 0.02, 0.5)
    0.04
    """
    if not 0.0 < fill < 1.0:
        raise ParameterError("fill", f"must be in (0, 1), got {fill!r}")
    return float(n * diameter * (1.0 - fill) / fill)


def design_balls_model(design, settings):
    """The :class:`~acoustiviz.dynamics.MultiBallModel` of a design: ``design.balls`` spheres of ``design.m`` each."""
    from ..dynamics import DamperModel, MultiBallModel

    s = settings
    damper = DamperModel(M=s.M, K=s.K, C=s.C, m=design.m, gap=design.gap, k_hertz=design.k_hertz, c1=design.c1,
                         clip_tensile=s.clip_tensile)
    return damper, MultiBallModel.from_damper(damper, design.balls, k_ball=s.k_hertz_ball, c_ball=s.c1_ball,
                                              material=design.material or BALL_MATERIAL)
