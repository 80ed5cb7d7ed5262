"""
Free vibration with and without the impact damper (paper Figure 5).
====================================================================

The Table 1 damper (M = 0.5 kg, K = 500 N/m, C = 0.05 N·s/m, m = 40.5 g, K_HZ = 5.6e8 N/m^1.5,
c1 = 20 N·s/m, gap d = 4 cm) starts from x = 0 with dx/dt = 2 m/s, the impact mass centred and at
rest. The event-driven solver follows about 250 impacts over 20 s; the motion settles after about
15 s, while the dashpot alone would still leave a third of the amplitude after 20 s.

The lower panel shows the positive maxima and the two damping inclinations: paper eq 16 from the
first two maxima, and a straight line fitted to the maxima down to 30 % of the first one.
"""

# %%
import numpy as np
from _gallery import fast_mode, output_dir

from acoustiviz.dynamics import TABLE1, exact_maxima, simulate
from acoustiviz.dynamics.metrics import (
    damping_inclination,
    envelope_inclination,
    free_response,
    positive_maxima,
    sample_times,
    settling_time,
)
from acoustiviz.output.plot.dynamics import plot_free_vibration
from acoustiviz.output.plot.style import save_figure, style

DURATION = 4.0 if fast_mode() else 20.0
t = sample_times(DURATION, TABLE1)
run = simulate(TABLE1, DURATION, t_eval=t)
maxima = exact_maxima(run)  # exact: zeros of the closed-form velocity, roots inside contacts
alone = positive_maxima(t, free_response(t))
two, fit = damping_inclination(maxima), envelope_inclination(maxima)
print(f"{len(run.impacts)} impacts, solver time {1000 * run.solver_time:.1f} ms, "
      f"energy closure {run.energy.relative_closure_error:.1e}")
print(f"damping inclination, eq 16 (first two maxima): {100 * two.value:.3f} cm/s")
print(f"damping inclination, fit of {fit.n_maxima} maxima {fit.t_start:.2f}-{fit.t_stop:.2f} s: "
      f"{100 * fit.value:.3f} cm/s")
print(f"settling time (maxima below 5 % of the first): {settling_time(maxima):.2f} s")

# %%
with style():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 6.4), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, height_ratios=(3, 2))
    plot_free_vibration(run, ax=ax1)
    ax2.plot(alone.time, 100 * alone.value, "o", ms=2.5, color="0.6", label="maxima, without damper")
    ax2.plot(maxima.time, 100 * maxima.value, "o", ms=2.5, color="C0", label="maxima, with damper")
    sel = maxima.time <= fit.t_stop
    coef = np.polyfit(maxima.time[sel], maxima.value[sel], 1)
    tt = np.array([fit.t_start, fit.t_stop])
    ax2.plot(tt, 100 * np.polyval(coef, tt), color="C1", lw=1.5,
             label=f"fit {fit.t_start:.1f}-{fit.t_stop:.1f} s: e = {100 * fit.value:.2f} cm/s")
    ax2.plot(maxima.time[:2], 100 * maxima.value[:2], color="C3", lw=2,
             label=f"eq 16, first two maxima: e = {100 * two.value:.2f} cm/s")
    ax2.set_xlabel("time t (s)")
    ax2.set_ylabel("positive maxima X (cm)")
    ax2.legend(fontsize=8, loc="lower left")
    path = save_figure(fig, output_dir() / "plot_04_free_vibration.png")
print(f"wrote {path}")
