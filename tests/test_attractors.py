"""The attractors of one frequency: starts, regime rules, de-duplication."""

import numpy as np
import pytest

from acoustiviz.dynamics._attractors import start_states
from acoustiviz.dynamics._measure import _classify, _drifting, same_motion
from acoustiviz.dynamics.forced import Excitation, steady_state
from acoustiviz.dynamics.model import DamperModel


def test_starts_are_deterministic_and_inside_the_cavity():
    model, ex = DamperModel(), Excitation(5.0, 5.0)
    a, b = start_states(model, ex, 8), start_states(model, ex, 8)
    assert a == b and len(a) == 8 and len(set(a)) == 8
    assert a[1] == (0.0, 0.0, 0.0, 0.0)  # rest
    for x, _, y, _ in a[2:]:
        assert abs(y - x) < 0.5 * model.gap


@pytest.mark.parametrize("lam,err,regime,word", [
    (5.0, 0.5, "chaotic", "positive beyond"),
    (-1.0, 0.1, "unresolved", "contracting"),
    (1e-3, 1e-3, "quasi-periodic", "zero within"),
    (0.5, 0.4, "unresolved", "cannot be told"),
    (float("nan"), 0.1, "unresolved", "failed"),
])
def test_regime_rules_from_the_lyapunov_exponent(lam, err, regime, word):
    got, why = _classify(lam, err, 0.2)  # 1/s, forcing period 0.2 s
    assert got == regime and word in why


def test_a_drifting_window_is_told_from_a_stationary_one():
    rng = np.random.default_rng(1)
    noise = rng.normal(0.0, 1e-3, 8)
    assert not _drifting(0.14 + noise)
    assert _drifting(0.14 + noise + np.linspace(0.02, 0.0, 8))  # a decaying transient


@pytest.mark.slow
def test_motions_without_impacts_are_one_motion_wherever_the_impact_mass_floats():
    model, ex = DamperModel(gap=10.0), Excitation(3.0, 5.0)
    a = steady_state(model, ex, initial=(0.0, 0.0, 0.0, 0.0), tolerance=1e-12)
    b = steady_state(model, ex, initial=(0.0, 0.0, 1.0, 0.0), tolerance=1e-12)
    assert a.impacts_per_cycle == b.impacts_per_cycle == 0
    assert abs(a.poincare[0, 2] - b.poincare[0, 2]) > 0.5  # the impact mass elsewhere
    assert same_motion(a, b)


@pytest.mark.parametrize("mass,frequency", [(None, 3.5), (None, 5.0), (None, 7.0), (0.0395, 6.5)])
def test_screened_checkpoints_keep_the_attractors_of_the_full_search(mass, frequency):
    """Screening the checkpoints finds no motion the full search does not, and its largest amplitude.

    At 6.5 Hz with a 39.5 g impact mass the full search's starts also reach a small orbit by a
    shooting from far away, which the screened search may skip: a subset, with the same worst case.
    """
    from dataclasses import replace

    from acoustiviz.dynamics.forced import SCREENED_CHECKPOINT_RETURN, SteadyStateOptions, attractors_at

    model, ex = DamperModel(), Excitation(frequency, 5.0)
    model = model if mass is None else replace(model, m=mass)
    full = attractors_at(model, ex, SteadyStateOptions())
    screened = attractors_at(model, ex, SteadyStateOptions(checkpoint_return=SCREENED_CHECKPOINT_RETURN))
    assert screened.attractors and all(a.success for a in screened.attractors)
    for a in screened.attractors:
        assert any(same_motion(a, b) for b in full.attractors), a.regime
    worst_full = max(full.attractors, key=lambda a: a.amplitude)
    worst = max(screened.attractors, key=lambda a: a.amplitude)
    assert worst.period == worst_full.period
    se = np.hypot(worst.amplitude_std_err, worst_full.amplitude_std_err)
    assert abs(worst.amplitude - worst_full.amplitude) <= max(3.0 * se, 1e-6 * worst_full.amplitude)
    assert screened.cycles_integrated <= full.cycles_integrated


def test_every_checkpoint_is_tried_unless_asked_and_the_screen_is_checked():
    from acoustiviz._validate import ParameterError
    from acoustiviz.dynamics.forced import SteadyStateOptions, check_settings

    model, ex = DamperModel(), Excitation(5.0, 5.0)
    assert check_settings(model, ex).checkpoint_return == np.inf
    assert check_settings(model, ex, checkpoint_return=0.1).checkpoint_return == 0.1
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(ParameterError, match="checkpoint_return"):
            check_settings(model, ex, SteadyStateOptions(checkpoint_return=bad))


@pytest.mark.parametrize("mass,frequency", [(0.0385, 4.5), (0.0385, 3.5), (0.0385, 7.0), (None, 5.0)])
def test_reusing_known_orbits_keeps_every_attractor_and_count(mass, frequency):
    """A start whose shooting lands on a known stable orbit ends there: the same attractors, counts, fewer cycles.

    At 38.5 g several starts reach the periodic orbits of 3.5, 4.5 and 7 Hz after one was measured;
    at 5 Hz (40.5 g) every start ends on one chaotic motion, which reusing orbits leaves alone.
    """
    from dataclasses import replace

    from acoustiviz.dynamics.forced import SCREENED_CHECKPOINT_RETURN, SteadyStateOptions, attractors_at

    model, ex = DamperModel(), Excitation(frequency, 5.0)
    model = model if mass is None else replace(model, m=mass)
    options = SteadyStateOptions(checkpoint_return=SCREENED_CHECKPOINT_RETURN)
    full = attractors_at(model, ex, options)
    reused = attractors_at(model, ex, replace(options, reuse_known=True))
    assert len(reused.attractors) == len(full.attractors)
    for a, b in zip(reused.attractors, full.attractors, strict=True):
        assert (a.regime, a.period, a.stable) == (b.regime, b.period, b.stable)
        assert a.amplitude == b.amplitude and a.amplitude_std_err == b.amplitude_std_err
        np.testing.assert_array_equal(a.poincare, b.poincare)
        np.testing.assert_allclose(a.floquet, b.floquet, rtol=1e-9, atol=1e-12)  # the same orbit point, rescaled
    assert reused.counts == full.counts and reused.seeded == full.seeded
    assert reused.cycles_integrated <= full.cycles_integrated
    if any(a.period for a in full.attractors) and sum(full.counts) > len(full.attractors):
        assert reused.cycles_integrated < full.cycles_integrated  # a known orbit was not measured again


def test_known_orbits_are_measured_again_unless_asked_and_the_switch_is_checked():
    from acoustiviz._validate import ParameterError
    from acoustiviz.dynamics.forced import SteadyStateOptions, check_settings

    model, ex = DamperModel(), Excitation(5.0, 5.0)
    assert check_settings(model, ex).reuse_known is False
    assert check_settings(model, ex, reuse_known=True).reuse_known is True
    for bad in (1, "yes", None):
        with pytest.raises(ParameterError, match="reuse_known"):
            check_settings(model, ex, SteadyStateOptions(reuse_known=bad))


def test_transients_run_at_the_search_rtol_unless_asked_and_their_rtol_is_checked():
    from acoustiviz._validate import ParameterError
    from acoustiviz.constants import FORCED_RTOL_RANGE
    from acoustiviz.dynamics.forced import SteadyStateOptions, check_settings

    model, ex = DamperModel(), Excitation(5.0, 5.0)
    assert check_settings(model, ex).transient_rtol is None
    assert check_settings(model, ex, transient_rtol=1e-7).transient_rtol == 1e-7
    assert check_settings(model, ex, rtol=1e-8, transient_rtol=1e-8).transient_rtol == 1e-8
    top = FORCED_RTOL_RANGE[1]
    for bad in (1e-12, 2 * top, 0.0, -1e-6, float("nan")):  # tighter than rtol 1e-10, or beyond the range
        with pytest.raises(ParameterError, match=r"transient_rtol.*(\[1e-10, 0\.0001\]|finite)"):
            check_settings(model, ex, SteadyStateOptions(transient_rtol=bad))


def test_the_direct_run_alone_takes_the_transient_rtol():
    from dataclasses import replace

    from acoustiviz.dynamics._attractors import _Settler
    from acoustiviz.dynamics.forced import SteadyStateOptions

    model, ex = DamperModel(), Excitation(5.0, 5.0)
    options = SteadyStateOptions()
    tight = _Settler(model, ex, options, start_states(model, ex, 1)[0], ())
    loose = _Settler(model, ex, replace(options, transient_rtol=1e-7), start_states(model, ex, 1)[0], ())
    assert tight.run.rtol == options.rtol and loose.run.rtol == 1e-7
    assert loose.pmap.run.rtol == loose.settings.rtol == options.rtol  # shooting at the search's rtol


#: Standard errors within which a chaotic worst case agrees with another run's (the batch means' spread).
SIGMAS = 3.0


@pytest.mark.parametrize("mass,frequency", [(0.0385, 4.5), (None, 5.0)])
def test_loose_transients_reach_the_attractors_measured_at_the_search_rtol(mass, frequency):
    """Transients at rtol 1e-7: a periodic orbit both searches reach is the same to the Newton tolerance,
    and the chaotic worst case agrees within the standard errors of its batch means.

    At 38.5 g and 4.5 Hz starts end on periodic orbits; at 5 Hz (40.5 g) every start on one chaotic motion.
    """
    from dataclasses import replace

    from acoustiviz.dynamics.forced import SCREENED_CHECKPOINT_RETURN, SteadyStateOptions, attractors_at

    model, ex = DamperModel(), Excitation(frequency, 5.0)
    model = model if mass is None else replace(model, m=mass)
    options = SteadyStateOptions(checkpoint_return=SCREENED_CHECKPOINT_RETURN, reuse_known=True)
    tight = attractors_at(model, ex, options)
    loose = attractors_at(model, ex, replace(options, transient_rtol=1e-7))
    assert loose.attractors and all(a.success for a in loose.attractors)
    orbits = 0
    for a in loose.attractors:
        for b in tight.attractors:
            if a.period and same_motion(a, b):
                orbits += 1
                assert a.period == b.period
                assert abs(a.amplitude - b.amplitude) <= 10 * options.tolerance
                assert a.max_floquet_modulus == pytest.approx(b.max_floquet_modulus, abs=1e-5)
    worst, worst_tight = (max(r.attractors, key=lambda a: a.amplitude) for r in (loose, tight))
    if mass is None:
        assert worst.regime == worst_tight.regime == "chaotic"
        se = np.hypot(worst.amplitude_std_err, worst_tight.amplitude_std_err)
        assert abs(worst.amplitude - worst_tight.amplitude) <= SIGMAS * se
    else:
        assert orbits >= 1
