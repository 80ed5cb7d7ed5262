"""
Where is an impact loud? Peak SPL and SEL over a plane in a wall-floor corner
=============================================================================

The paper's steel sphere (a = 19.05 mm, 1.4 m/s, K_HZ = 5.6e8 N/m^1.5, exact Hertz pulse) strikes
the floor 5 cm from a rigid wall. On the vertical plane through its centre, normal to the wall,
every point gets the peak of the continuous pressure (peak SPL, dB re 20 µPa) and the exposure of
the whole response (SEL, dB re (20 µPa)²·s), from the closed form of the four image sources
without a time loop (:func:`acoustiviz.field.fast_peaks`, through
:func:`acoustiviz.app.maps.level_map`, the function behind ``acoustiviz map``).

The sphere radiates as a dipole along its vertical axis: loud above it, quiet sideways along the
floor. Near the wall the wall's image adds to the direct sound, so the loud region leans towards
the wall and the level stays high along it. Points inside the sphere are blank; each colour scale
spans at most 60 dB below the 99.5th percentile of its map, so the few points touching the sphere
saturate.

The same map from the command line::

    acoustiviz map --config wall-floor --wall-distance 0.05 --pulse hertz --extent 0.5 \\
        --resolution 401 --png map.png --csv map.csv --vtk map.vtu
"""

# %%
import time

from _gallery import fast_mode, output_dir

from acoustiviz.app.impacts import impact_setup
from acoustiviz.app.maps import level_map, map_title, write_map_outputs

setup = impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, pulse="hertz",
                     config="wall-floor", wall_distance=0.05)
resolution = 81 if fast_mode() else 401
start = time.perf_counter()
level = level_map(setup.pulse, setup.geometry, medium=setup.medium, plane="vertical", extent=0.5,
                  resolution=resolution)
print(f"{level.grid.points.shape[0]} points in {time.perf_counter() - start:.2f} s")

# %%
title = map_title(level, setup.geometry, "a = 19.05 mm, U0 = 1.4 m/s, Hertz pulse, wall 5 cm from the centre")
(out,) = write_map_outputs(level, setup.geometry, png=output_dir() / "plot_15_level_map.png", title=title)
print(f"wrote {out}")
