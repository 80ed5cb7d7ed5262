"""An independent SciPy reference of the multi-ball damper's collisions (a test harness).

Kept outside the installed package: the benchmarks and the tests (``pythonpath = ["benchmarks"]``
in the pytest settings) import it as ``_balls_reference``.

The equations of :mod:`acoustiviz.dynamics.balls` are written out here again, in NumPy: state =
reduced positions then velocities of the main mass and the balls; every pair in contact pushes its
bodies apart with ``K d^1.5 + c dd/dt``; with an excitation the main mass also carries
``F(t) = P cos ωt + Q sin ωt``. ``solve_ivp(method="DOP853")`` integrates them with a terminal event on
every pair, restarted at each event (the force law changes form there).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from acoustiviz.dynamics import BallState, MultiBallModel

__all__ = ["REFERENCE_RTOL", "scipy_collisions"]

#: Relative tolerance of the reference (absolute 1e-16 on every component).
REFERENCE_RTOL = 1e-13


def scipy_collisions(model: MultiBallModel, n_collisions: int, t_max: float = 2.0,
                     initial: BallState | None = None, excitation=None) -> list:
    """First touches ``(time s, pair index)`` of the first ``n_collisions`` collisions, up to ``t_max`` s.

    Between events the right-hand side is smooth: a pair in contact keeps its law, continued oddly
    past d = 0, until the event switches it off. ``initial`` defaults to :class:`BallState` ().
    ``excitation`` (an :class:`~acoustiviz.dynamics.forced.Excitation`, None for free vibration): the
    force on the main mass, from its angular frequency and ``(P, Q)`` alone (``force_coefficients``).
    """
    om = 0.0 if excitation is None else excitation.omega
    fp, fq = (0.0, 0.0) if excitation is None else excitation.force_coefficients(model)
    pr, mass = model.pairs(), model.masses()
    pa, pb, hg, kh, cc = pr["pa"], pr["pb"], pr["hg"], pr["kh"], pr["cc"]
    nb = mass.size
    q0, u0 = (BallState() if initial is None else initial).reduced(model)
    state = np.concatenate([q0, u0])
    active = np.zeros(pa.size, bool)

    def rhs(t, s):
        q, u = s[:nb], s[nb:]
        acc = np.zeros(nb)
        acc[0] = -model.K * q[0] - model.C * u[0] + fp * math.cos(om * t) + fq * math.sin(om * t)
        d = q[pa] - q[pb] - hg
        f = np.where(active, kh * d * np.sqrt(np.abs(d)) + cc * (u[pa] - u[pb]), 0.0)
        np.add.at(acc, pa, -f)
        np.add.at(acc, pb, f)
        return np.concatenate([u, acc / mass])

    def make_event(p):
        def ev(t, s):
            return s[pa[p]] - s[pb[p]] - hg[p]
        ev.terminal = True
        return ev

    events = [make_event(p) for p in range(pa.size)]
    t, found = 0.0, []
    while len(found) < n_collisions and t < t_max:
        sol = solve_ivp(rhs, (t, t_max), state, method="DOP853", rtol=REFERENCE_RTOL, atol=1e-16, events=events)
        hits = [(te[0], p) for p, te in enumerate(sol.t_events) if te.size]
        if not hits:
            break
        te, p = min(hits)
        state = sol.y_events[p][0].copy()
        rate = state[nb + pa[p]] - state[nb + pb[p]]
        if not active[p] and rate > 0:
            found.append((te, p))
        active[p] = rate > 0
        # carry on past the crossing without events for 1 ns (far shorter than any contact or flight of
        # the runs compared), so that the next run does not stop again at the event just handled
        t = te + 1e-9
        state = solve_ivp(rhs, (te, t), state, method="DOP853", rtol=REFERENCE_RTOL, atol=1e-16).y[:, -1]
    return found
