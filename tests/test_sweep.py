"""Design sweeps: per-design values against direct calls, the maximum over impacts, the design
table by hand, resumable row-by-row output, and the process-pool and Dask executors."""

import csv
import math
from concurrent.futures import Executor, Future

import numpy as np
import pytest

from acoustiviz.core.contact import Impact, acceleration_pulse
from acoustiviz.core.geometry import geometry
from acoustiviz.core.medium import Medium
from acoustiviz.dynamics import DamperModel, InitialState, simulate
from acoustiviz.dynamics import metrics as dm
from acoustiviz.dynamics.maxima import exact_maxima
from acoustiviz.errors import ParameterError
from acoustiviz.field import field_metrics
from acoustiviz.sweep import (
    CSV_COLUMNS,
    SWEEP_CSV,
    Design,
    FixedSettings,
    SweepMismatch,
    SweepSpec,
    SweepTable,
    design,
    design_table,
    evaluate_design,
    impact_spl_db,
    load_sweep,
    max_spl_db,
    parse_values,
    run_sweep,
    sweep_sphere_radius,
    value_range,
)

SPL_TOL_DB = 1e-9  # the same arithmetic: agreement to round-off


class _ConsumedFuture(Future):
    """A finished future that reports when its result has been taken."""

    def __init__(self, on_result):
        super().__init__()
        self._on_result = on_result

    def result(self, timeout=None):
        out = super().result(timeout)
        self._on_result()
        return out


class InlineExecutor(Executor):
    """Runs each task at submission and counts submissions.

    With ``interrupt_at=k`` it simulates Ctrl-C after k finished designs: task k + 1 fails with
    KeyboardInterrupt as soon as the sweep has taken the first k results (not after a delay, so the
    outcome does not depend on how fast the machine is), and later tasks never start.
    """

    def __init__(self, interrupt_at=None):
        self.submitted = 0
        self.taken = 0
        self.interrupt_at = interrupt_at
        self._late = None

    def _taken(self):
        self.taken += 1
        if self.taken == self.interrupt_at and self._late is not None:
            self._late.set_exception(KeyboardInterrupt())

    def submit(self, fn, /, *args, **kwargs):
        self.submitted += 1
        if self.interrupt_at is None or self.submitted <= self.interrupt_at:
            fut = _ConsumedFuture(self._taken)
            fut.set_result(fn(*args, **kwargs))
            return fut
        fut = Future()
        if self.submitted == self.interrupt_at + 1:
            self._late = fut
            if self.interrupt_at == 0 or self.taken >= self.interrupt_at:
                fut.set_exception(KeyboardInterrupt())
        return fut  # later tasks stay pending (cancellable)


def small_spec(**settings):
    kw = {"duration": 2.0}
    kw.update(settings)
    return SweepSpec(gap=value_range(0.02, 0.06, 3), m=value_range(0.02, 0.08, 2), settings=FixedSettings(**kw))


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


# --------------------------------------------------------------------------- parsing
def test_ranges_are_inclusive_and_lists_kept_in_order():
    assert parse_values("--gap", "0.02:0.06:5") == (0.02, 0.03, 0.04, 0.05, 0.06)
    assert parse_values("--m", "0.08,0.02") == (0.08, 0.02)
    assert parse_values("--m", "0.04") == (0.04,)
    assert parse_values("--config", "plane,wall-floor", str) == ("plane", "wall-floor")
    assert value_range(1.0, 1.0, 1) == (1.0,)


@pytest.mark.parametrize("start, stop, count", [(0.02, 0.06, 20), (0.02, 0.08, 20), (-0.1, 0.2, 4), (1e-6, 3e-6, 7),
                                               (5e8, 1e9, 3), (0.0, 1.0, 11)])
def test_one_range_rule_for_scenes_and_options(start, stop, count):
    """The scene's range keys and the sweep's options give the same grid, exactly, and the grid
    is the exact arithmetic progression (computed here in rational arithmetic) to 15 digits."""
    from fractions import Fraction

    from acoustiviz.scene import parse_range

    text = f"{start!r}:{stop!r}:{count}"
    grid = parse_values("--gap", text)
    assert tuple(parse_range(text)) == grid == value_range(start, stop, count)
    assert len(grid) == count and grid[0] == start and grid[-1] == stop
    scale = max(abs(start), abs(stop))
    a, b = Fraction(start), Fraction(stop)
    for i, v in enumerate(grid):
        exact = a + i * (b - a) / (count - 1)
        assert abs(Fraction(v) - exact) <= Fraction(scale) * Fraction(1, 10**14), (i, v, float(exact))


@pytest.mark.parametrize("start, stop, count", [(0.06, 0.02, 9), (0.02, 0.02, 3), (-0.1, -0.2, 2)])
def test_one_range_rule_refuses_a_range_not_in_increasing_order(start, stop, count):
    """Every front-end (sweep options, scene keys, forced frequencies) refuses it, with the same words."""
    from acoustiviz.app.forced import parse_frequencies
    from acoustiviz.scene import parse_range

    text = f"{start!r}:{stop!r}:{count}"
    with pytest.raises(ParameterError, match="stop > start") as a:
        parse_values("--gap", text)
    with pytest.raises(ParameterError, match="stop > start") as b:
        parse_range(text, "outputs.sweep.gap_m")
    with pytest.raises(ParameterError, match="stop > start"):
        parse_frequencies(text)
    assert a.value.name == "--gap" and b.value.name == "outputs.sweep.gap_m"
    assert a.value.detail.split(" (in ")[0] == b.value.detail.split(" (in ")[0]


def test_the_figure_6_grid_has_decimal_values():
    # 0.02 + 9 * 0.04/19 = 0.0389473684210526315...: 15 significant digits, not start + i*step's
    # 0.038947368421052626 nor the 0.038947368421053 of rounding to 15 decimals
    assert value_range(0.02, 0.06, 20)[9] == 0.0389473684210526
    assert value_range(0.02, 0.06, 5) == (0.02, 0.03, 0.04, 0.05, 0.06)


@pytest.mark.parametrize("text", ["0.02:0.06", "0.02:0.06:0", "a:b:3", "0.02:0.06:2.5", "x", "1:2:1", "",
                                  "0:1:10001", "0:inf:3"])
def test_bad_ranges_name_the_option(text):
    with pytest.raises(ParameterError, match="^--gap"):
        parse_values("--gap", text)


@pytest.mark.parametrize("kw, name", [
    ({"gap": (-0.01,)}, "gap"), ({"m": (0.0,)}, "m"), ({"c1": (-1.0,)}, "c1"),
    ({"angle": (2.0,)}, "angle"), ({"config": ("room",)}, "config"), ({"distance": (0.01,)}, "distance"),
    ({"m": (0.04,), "mass_ratio": (0.1,)}, "m"), ({"material": ("steel",), "k_hertz": (1e8,)}, "k_hertz"),
    ({"material": ("unobtainium",)}, "material"), ({"gap": (0.02, 0.02)}, "gap"),
])
def test_bad_specs_are_refused_before_any_work(kw, name):
    with pytest.raises(ParameterError, match=f"^{name}"):
        SweepSpec(**kw)


def test_settings_validate():
    with pytest.raises(ParameterError, match="^radius_mode"):
        FixedSettings(radius_mode="guess")
    with pytest.raises(ParameterError, match="^pulse_mass"):
        FixedSettings(pulse_mass="both")
    with pytest.raises(ParameterError, match="^n_fastest"):
        FixedSettings(n_fastest=-1)


def test_grid_order_and_mass_ratio():
    spec = SweepSpec(gap=(0.02, 0.04), mass_ratio=(0.1, 0.2), settings=FixedSettings(M=0.5))
    ds = spec.designs()
    assert [(d.gap, d.m) for d in ds] == [(0.02, 0.05), (0.02, 0.1), (0.04, 0.05), (0.04, 0.1)]
    assert [d.design_id for d in ds] == [0, 1, 2, 3]
    assert spec.swept() == ("gap", "m")


def test_sphere_radius_choices():
    s = FixedSettings(radius_mode="from-mass", density=7800.0)
    m = 0.0405
    assert sweep_sphere_radius(m, s) == pytest.approx((3 * m / (4 * math.pi * 7800.0)) ** (1 / 3), rel=1e-12)
    assert sweep_sphere_radius(m, FixedSettings()) == 0.01905
    # materials give the density and K_HZ (paper eq 2) at the sphere's radius
    spec = SweepSpec(k_hertz=None, material=("steel", "brass"), settings=FixedSettings(radius_mode="from-mass"))
    d_steel, d_brass = spec.designs()
    assert d_brass.radius < d_steel.radius  # brass is denser than steel
    from acoustiviz.core.contact import hertz_stiffness
    from acoustiviz.core.materials import material

    st = material("steel")
    assert d_steel.k_hertz == pytest.approx(hertz_stiffness(d_steel.radius, st, st), rel=1e-12)
    assert d_steel.radius == pytest.approx((3 * 0.0405 / (4 * math.pi * st.density)) ** (1 / 3), rel=1e-12)


def test_spec_roundtrips_through_json_dict():
    spec = SweepSpec(gap=(0.02, 0.03), mass_ratio=(0.1,), config=("plane", "wall-floor"),
                     settings=FixedSettings(pulse="hertz", radius_mode="from-mass"))
    assert SweepSpec.from_dict(spec.to_dict()) == spec


# --------------------------------------------------------------------------- one design
def direct_reference(gap, m, settings, *, angle=math.pi / 4, distance=0.7, config="plane"):
    """Every value of one design from direct calls of the dynamics and field functions,
    with the level of *every* impact evaluated."""
    model = DamperModel(M=settings.M, K=settings.K, C=settings.C, m=m, gap=gap, k_hertz=5.6e8, c1=20.0)
    r = simulate(model, settings.duration, initial=InitialState(v=2.0), rtol=settings.rtol)
    mx = exact_maxima(r)
    a = 0.01905
    conf = geometry(config, a, wall_distance=0.05 if config == "wall-floor" else None)
    centre = conf.sources[0].position
    point = centre + distance * np.array([math.sin(angle), 0.0, math.cos(angle)])
    levels = [field_metrics(acceleration_pulse(Impact(u, 5.6e8, m), "half-sine"), point[None, :], conf,
                            medium=Medium(343.2, 1.204)).peak_spl_db[0] for u in r.impacts.approach_velocity]
    return r, mx, max(levels)


def test_design_values_equal_direct_calls():
    s = FixedSettings(duration=4.0)
    d = SweepSpec(gap=(0.03,), m=(0.05,), settings=s).designs()[0]
    res = evaluate_design(d, s)
    r, mx, spl = direct_reference(0.03, 0.05, s)
    assert res.n_impacts == len(r.impacts)
    assert res.inclination_two_maxima == dm.damping_inclination(mx).value
    fit = dm.envelope_inclination(mx, 0.3)
    assert res.inclination_fit == fit.value
    assert (res.fit_window_start, res.fit_window_stop) == (fit.t_start, fit.t_stop)
    st = dm.settling_time(mx, 0.05)
    assert res.settling_time == st or (math.isnan(st) and math.isnan(res.settling_time))
    assert res.energy_dissipated_contact == r.energy.dissipated_contact
    assert res.max_spl_db == pytest.approx(spl, abs=SPL_TOL_DB)
    assert res.spl_impacts_evaluated < res.n_impacts  # only the fastest few were computed


def test_listener_in_wall_floor_corner_matches_direct_call():
    s = FixedSettings(duration=1.0)
    d = SweepSpec(gap=(0.04,), m=(0.03,), config=("wall-floor",), angle=(math.radians(60),), distance=(0.4,),
                  settings=s).designs()[0]
    res = evaluate_design(d, s)
    _, _, spl = direct_reference(0.04, 0.03, s, angle=math.radians(60), distance=0.4, config="wall-floor")
    assert res.max_spl_db == pytest.approx(spl, abs=SPL_TOL_DB)


@pytest.mark.parametrize("settings", [
    FixedSettings(duration=3.0),
    FixedSettings(duration=3.0, radius_mode="from-mass", pulse_mass="effective"),
    FixedSettings(duration=3.0, pulse="hertz"),
    FixedSettings(duration=3.0, pulse="impulse-matched", radius=0.005),
])
@pytest.mark.parametrize("config", ["free", "plane", "wall-floor"])
@pytest.mark.slow
def test_level_of_fastest_impacts_is_the_max_over_all_impacts(settings, config):
    """The shortcut (the few fastest impacts) against every impact of the run."""
    d = SweepSpec(gap=(0.05,), m=(0.03,), config=(config,), settings=settings).designs()[0]
    model = DamperModel(m=d.m, gap=d.gap)
    u = simulate(model, settings.duration, rtol=1e-10).impacts.approach_velocity
    conf = geometry(config, d.radius, wall_distance=0.05 if config == "wall-floor" else None)
    from acoustiviz.sweep import listener_point

    kw = dict(mass=d.m, partner_mass=math.inf if settings.pulse_mass == "impact" else settings.M,
              k_hertz=d.k_hertz, pulse=settings.pulse, geometry=conf, point=listener_point(conf, 0.7, math.pi / 4),
              medium=Medium())
    every = max(impact_spl_db(v, **kw) for v in u)
    fast, n = max_spl_db(u, n_fastest=1, **kw)
    assert n == 1 and u.size > 20
    assert fast == pytest.approx(every, abs=SPL_TOL_DB)
    assert max_spl_db(u, n_fastest=0, **kw) == (pytest.approx(every, abs=SPL_TOL_DB), np.unique(u).size)


@pytest.mark.slow
def test_level_grows_with_approach_speed_over_a_wide_range():
    """The premise of the shortcut: at fixed geometry the peak level rises with the approach speed,
    by 6 dB or more per doubling, over radii, masses, stiffnesses, listeners, configurations, pulses."""
    rng = np.random.default_rng(7)
    speeds = np.geomspace(1e-3, 10.0, 21)
    lowest = np.inf
    for _ in range(40):
        radius = float(rng.choice([0.002, 0.01, 0.01905, 0.05]))
        config = str(rng.choice(["free", "plane", "wall-floor"]))
        conf = geometry(config, radius, wall_distance=radius * 3 if config == "wall-floor" else None)
        angle = float(rng.choice([0.0, 0.7, 1.2, 1.5]))
        from acoustiviz.sweep import listener_point

        kw = dict(mass=float(rng.choice([0.005, 0.04, 0.5])), partner_mass=float(rng.choice([math.inf, 0.5])),
                  k_hertz=float(rng.choice([1e7, 5.6e8, 1e10])), pulse=str(rng.choice(["half-sine", "hertz"])),
                  geometry=conf, point=listener_point(conf, float(rng.choice([0.1, 0.7, 3.0])), angle),
                  medium=Medium())
        levels = np.array([impact_spl_db(v, **kw) for v in speeds])
        step = np.diff(levels) / np.log2(speeds[1] / speeds[0])  # dB per doubling of the speed
        assert np.all(step > 5.0), (kw, step)  # rising everywhere, never flat
        lowest = min(lowest, step.min())
    assert lowest > 5.9  # the short-pulse limit U^1 is 6.02 dB per doubling


def test_non_monotone_levels_fall_back_to_every_impact(monkeypatch):
    import acoustiviz.sweep.evaluate as sw

    table = {3.0: 100.0, 2.0: 101.0, 1.0: 120.0, 0.5: 90.0}  # a made-up non-monotone law
    monkeypatch.setattr(sw, "impact_spl_db", lambda v, **kw: table[float(v)])
    assert sw.max_spl_db([0.5, 1.0, 2.0, 3.0], n_fastest=2) == (120.0, 4)
    table[2.0] = 99.0
    assert sw.max_spl_db([0.5, 1.0, 2.0, 3.0], n_fastest=2) == (100.0, 2)


# --------------------------------------------------------------------------- design table by hand
def hand_table(e, spl, gap, mass):
    spec = SweepSpec(gap=tuple(sorted(set(gap))), m=tuple(sorted(set(mass))))
    n = len(e)
    cols = {c: np.full(n, np.nan) for c in CSV_COLUMNS}
    cols.update(inclination_two_maxima_m_s=np.array(e), inclination_fit_m_s=np.array(e)[::-1],
                max_spl_db=np.array(spl), gap_m=np.array(gap), mass_kg=np.array(mass), design_id=np.arange(n))
    for c in ("material", "config"):
        cols[c] = np.array([""] * n)
    for c in ("mass_ratio", "c1_n_s_m", "k_hertz_n_m1_5", "v0_m_s", "distance_m", "angle_deg", "radius_m",
              "energy_dissipated_contact_j", "energy_dissipated_main_j", "max_approach_velocity_m_s",
              "fit_window_start_s", "fit_window_stop_s", "fit_n_maxima", "spl_impacts_evaluated", "success"):
        cols[c] = np.zeros(n)
    return SweepTable(spec, cols)


def test_design_table_bands_by_hand():
    # inclinations (m/s), levels (dB), designs
    e = [0.0071, 0.0079, 0.0081, 0.0084, 0.0096, math.nan, 0.0120]
    spl = [104.0, 101.0, 107.0, 100.5, 103.0, 90.0, 105.0]
    gap = [0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08]
    mass = [0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07]
    bands = design_table(hand_table(e, spl, gap, mass))
    # bands [c - 0.5 mm/s, c + 0.5 mm/s): 0.007 <- 0.0071; 0.008 <- 0.0079, 0.0081, 0.0084;
    # 0.010 <- 0.0096; 0.012 <- 0.0120; the NaN design is left out
    assert [b.centre for b in bands] == [0.007, 0.008, 0.010, 0.012]
    b8 = bands[1]
    assert (b8.n_designs, b8.min_spl_db, b8.max_spl_db, b8.decrease_db) == (3, 100.5, 107.0, 6.5)
    assert (b8.quietest_gap, b8.quietest_mass, b8.loudest_gap, b8.loudest_mass) == (0.05, 0.04, 0.04, 0.03)
    assert bands[0].decrease_db == 0.0 and bands[0].quietest_gap == 0.02
    # explicit centres and the other definition
    only = design_table(hand_table(e, spl, gap, mass), centres=[0.008, 0.009])
    assert [b.centre for b in only] == [0.008]


def test_design_helper_by_hand():
    e = [0.0071, 0.0079, 0.0081, 0.0084, 0.0096]
    spl = [104.0, 101.0, 107.0, 100.5, 103.0]
    t = hand_table(e, spl, [0.02, 0.03, 0.04, 0.05, 0.06], [0.01, 0.02, 0.03, 0.04, 0.05])
    c = design(t, 0.008, 0.001)  # 0.0071, 0.0079, 0.0081, 0.0084 in; 0.0096 out
    assert c.n_candidates == 4
    assert (c.quietest["gap_m"], c.quietest["mass_kg"], c.quietest["max_spl_db"]) == (0.05, 0.04, 100.5)
    assert (c.loudest["gap_m"], c.loudest["max_spl_db"]) == (0.04, 107.0)
    assert c.saving_db == 6.5
    assert "6.50 dB quieter" in c.summary()
    # a target no design meets: an empty answer naming the nearest designs, not an error
    none = design(t, 0.02, 0.001)
    assert none.n_candidates == 0 and none.quietest is None and np.isnan(none.saving_db)
    assert [r["inclination"] for r in none.nearest] == [0.0096, 0.0084, 0.0081]
    assert none.span == (0.0071, 0.0096)
    assert "no design" in none.summary() and "0.0096" in none.summary()
    with pytest.raises(ParameterError, match="^tolerance"):
        design(t, 0.008, -1.0)


# --------------------------------------------------------------------------- files and resume
def test_rows_written_one_by_one_and_resumed_after_interruption(tmp_path):
    spec = small_spec()
    n = len(spec.designs())
    with pytest.raises(KeyboardInterrupt):
        run_sweep(spec, tmp_path / "a", executor=InlineExecutor(interrupt_at=2))
    rows = read_csv(tmp_path / "a" / SWEEP_CSV)
    assert tuple(rows[0][: len(CSV_COLUMNS)]) == CSV_COLUMNS
    assert len(rows) == 1 + 2  # the two finished designs were kept
    again = InlineExecutor()
    table = run_sweep(spec, tmp_path / "a", executor=again)
    assert again.submitted == n - 2  # only the missing designs were computed
    assert read_csv(tmp_path / "a" / SWEEP_CSV)[:3] == rows  # finished rows untouched
    assert sorted(table["design_id"]) == list(range(n))
    # a finished sweep computes nothing
    third = InlineExecutor()
    run_sweep(spec, tmp_path / "a", executor=third)
    assert third.submitted == 0
    # the values are those of an uninterrupted run and of a direct evaluation
    ref = run_sweep(spec, tmp_path / "b", executor=InlineExecutor())
    for c in CSV_COLUMNS:
        np.testing.assert_array_equal(table[c], ref[c])
    d = spec.designs()[4]
    assert table["max_spl_db"][4] == evaluate_design(d, spec.settings).max_spl_db


def test_a_finished_sweep_is_in_design_order_whatever_order_its_rows_came_in(tmp_path):
    spec = small_spec(duration=1.0)
    ref = tmp_path / "ref"
    run_sweep(spec, ref, executor=InlineExecutor())  # one design after another: the design order
    expected = (ref / SWEEP_CSV).read_bytes()
    # the journal of a sweep whose designs finished last first, cut before the first design
    shuffled = tmp_path / "shuffled"
    shuffled.mkdir()
    (shuffled / "sweep.json").write_bytes((ref / "sweep.json").read_bytes())
    header, *lines = expected.decode().splitlines(keepends=True)
    (shuffled / SWEEP_CSV).write_text(header + "".join(reversed(lines[1:])))
    again = InlineExecutor()
    run_sweep(spec, shuffled, executor=again)
    assert again.submitted == 1  # only the first design was missing
    assert (shuffled / SWEEP_CSV).read_bytes() == expected


def test_a_file_already_in_design_order_is_not_rewritten(tmp_path):
    from acoustiviz.sweep.store import put_in_design_order, read_rows

    spec = small_spec(duration=1.0)
    run_sweep(spec, tmp_path, executor=InlineExecutor())
    path = tmp_path / SWEEP_CSV
    before = path.stat().st_mtime_ns, path.read_bytes()
    assert not put_in_design_order(path, read_rows(path, spec), spec.designs())
    assert (path.stat().st_mtime_ns, path.read_bytes()) == before


def test_torn_last_line_is_dropped_and_recomputed(tmp_path):
    spec = small_spec(duration=1.0)
    with pytest.raises(KeyboardInterrupt):
        run_sweep(spec, tmp_path, executor=InlineExecutor(interrupt_at=3))
    path = tmp_path / SWEEP_CSV
    whole = path.read_bytes()
    torn = whole.splitlines(keepends=True)[-1][:25]  # a kill in the middle of writing a row
    path.write_bytes(whole[: -len(whole.splitlines(keepends=True)[-1])] + torn)
    ex = InlineExecutor()
    table = run_sweep(spec, tmp_path, executor=ex)
    assert ex.submitted == len(spec.designs()) - 2
    assert len(table) == len(spec.designs())
    text = path.read_text()
    assert text.endswith("\n") and len(text.splitlines()) == 1 + len(spec.designs())
    assert len(load_sweep(tmp_path)) == len(spec.designs())


def test_other_settings_are_refused_unless_overwritten(tmp_path):
    spec = small_spec(duration=1.0)
    run_sweep(spec, tmp_path, executor=InlineExecutor())
    other = small_spec(duration=1.5)
    with pytest.raises(SweepMismatch, match=r"^out: .*different settings.*settings.duration"):
        run_sweep(other, tmp_path, executor=InlineExecutor())
    with pytest.raises(SweepMismatch):
        run_sweep(SweepSpec(gap=(0.02,), settings=FixedSettings(duration=1.0)), tmp_path, executor=InlineExecutor())
    ex = InlineExecutor()
    table = run_sweep(other, tmp_path, executor=ex, overwrite=True)
    assert ex.submitted == len(other.designs()) and len(table) == len(other.designs())
    assert (tmp_path / "sweep.previous-1.csv").exists()  # kept beside the settings that made it
    assert read_spec_of(tmp_path / "sweep.previous-1.json") == spec.to_dict()


def read_spec_of(path):
    """The settings recorded in a sweep.json (or a moved-aside sweep.previous-N.json)."""
    import json

    return json.loads(path.read_text())["spec"]


def test_process_pool_gives_the_same_rows(tmp_path):
    spec = SweepSpec(gap=(0.03, 0.05), m=(0.04,), settings=FixedSettings(duration=1.0))
    pooled = run_sweep(spec, tmp_path / "p", workers=2)
    inline = run_sweep(spec, tmp_path / "i", executor=InlineExecutor())
    for c in CSV_COLUMNS:
        np.testing.assert_array_equal(pooled[c], inline[c])


def test_dask_local_cluster(tmp_path):
    distributed = pytest.importorskip("distributed")
    spec = SweepSpec(gap=(0.03, 0.05), m=(0.04,), settings=FixedSettings(duration=1.0))
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cl, \
            distributed.Client(cl) as client:
        table = run_sweep(spec, tmp_path / "d", executor=client.get_executor())
    inline = run_sweep(spec, tmp_path / "i", executor=InlineExecutor())
    for c in CSV_COLUMNS:
        np.testing.assert_array_equal(table[c], inline[c])


def test_progress_bar_only_on_a_terminal_and_resume_count_always():
    import io

    from acoustiviz.sweep import Progress

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    log = io.StringIO()  # not a terminal: no bar, the lines still written
    p = Progress(4, done_before=2, stream=log)
    assert not p.bar
    p.say("sweep: resuming: 2 of 4 designs done before")
    p.update()
    p.update()
    p.close()
    assert log.getvalue() == "sweep: resuming: 2 of 4 designs done before\n"
    tty = Terminal()
    p = Progress(4, done_before=2, stream=tty)
    assert p.bar
    p.update()
    p.update()
    p.close()
    assert "4/4" in tty.getvalue() and "design" in tty.getvalue()
    quiet = Terminal()
    p = Progress(4, stream=quiet, bar=False)  # --quiet on a terminal
    p.update()
    p.close()
    assert quiet.getvalue() == ""


def test_design_type_is_frozen():
    d = Design(0, 0.04, 0.04, 20.0, 5.6e8, "", 2.0, 0.7, 0.7, "plane", 0.01905)
    with pytest.raises(AttributeError):
        d.gap = 1.0


# --------------------------------------------------------------------------- failed designs
def _failing(monkeypatch, bad_id, fail):
    """Make the design ``bad_id`` fail with ``fail(design)``; the others are evaluated as usual."""
    import acoustiviz.sweep.evaluate as ev

    real = ev.evaluate_design

    def patched(d, settings):
        if d.design_id == bad_id:
            fail(d)
        return real(d, settings)

    monkeypatch.setattr(ev, "evaluate_design", patched)


def _check_failed_row(table, bad_id, reason, ref):
    bad = table["design_id"] == bad_id
    assert table.failed.tolist() == bad.tolist()
    assert reason in table["error"][bad][0]
    assert table["success"][bad][0] == 0 and np.isnan(table["max_spl_db"][bad][0])
    for c in CSV_COLUMNS:  # the other designs as in a run without the failure
        np.testing.assert_array_equal(table[c][~bad], ref[c][~bad])


def test_a_design_that_raises_is_a_failed_row_and_the_sweep_goes_on(tmp_path, monkeypatch):
    spec = small_spec(duration=1.0)
    ref = run_sweep(spec, tmp_path / "ref", executor=InlineExecutor())

    def overflow(d):
        raise OverflowError("math range error")

    _failing(monkeypatch, 3, overflow)
    table = run_sweep(spec, tmp_path / "a", executor=InlineExecutor())
    assert table.complete
    _check_failed_row(table, 3, "OverflowError: math range error", ref)
    again = InlineExecutor()  # a failed design is a finished row: resuming recomputes nothing
    assert len(run_sweep(spec, tmp_path / "a", executor=again)) == len(spec.designs()) and again.submitted == 0
    assert len(load_sweep(tmp_path / "a")) == len(spec.designs())
    bands = design_table(table)  # the failed design is left out of the design table
    assert sum(b.n_designs for b in bands) == np.isfinite(ref["inclination_two_maxima_m_s"]).sum() - 1


def test_an_executor_error_is_a_failed_row(tmp_path):
    class Flaky(InlineExecutor):
        def submit(self, fn, /, *args, **kwargs):
            if args[0].design_id == 1:
                fut = Future()
                fut.set_exception(RuntimeError("worker lost"))
                return fut
            return super().submit(fn, *args, **kwargs)

    spec = small_spec(duration=1.0)
    ref = run_sweep(spec, tmp_path / "ref", executor=InlineExecutor())
    table = run_sweep(spec, tmp_path / "a", executor=Flaky())
    _check_failed_row(table, 1, "RuntimeError: worker lost", ref)


def test_a_dead_worker_process_is_a_failed_row_and_the_sweep_goes_on(tmp_path, monkeypatch):
    import os

    spec = small_spec(duration=1.0)
    ref = run_sweep(spec, tmp_path / "ref", executor=InlineExecutor())
    _failing(monkeypatch, 2, lambda d: os._exit(3))  # the worker process dies (BrokenProcessPool)
    table = run_sweep(spec, tmp_path / "a", workers=2)
    assert table.complete
    _check_failed_row(table, 2, "worker process died", ref)
    assert "BrokenProcessPool" in table["error"][table["design_id"] == 2][0]
