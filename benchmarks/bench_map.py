"""Time of a level map (``acoustiviz map``) at its default settings, and of each of its files.

Run ``python benchmarks/bench_map.py`` (or ``--quick``: one repeat). The scene is the paper's
Figure 2 impact (a = 19.05 mm steel sphere, 1.4 m/s, K = 5.6e8 N/m^1.5, half-sine and Hertz
pulses); the map is the default one (vertical plane through the sphere, extent 0.5 m, 317 points
along the longer side), in the free field, above the plane and in the wall-floor corner 5 cm from
the wall. The table gives the points of each map, the best-of-n wall time of
:func:`acoustiviz.app.maps.level_map` (grid, checks and :func:`acoustiviz.field.fast_peaks`; the
numba kernels compiled beforehand) and of writing the CSV, the PNG and the VTK file, on one
thread. The horizontal plane at 0.1 m in the corner is the last row.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from _timing import best_of

from acoustiviz.app.impacts import impact_setup
from acoustiviz.app.maps import level_map, write_map_outputs

CASES = [("free", "half-sine", "vertical"), ("plane", "half-sine", "vertical"), ("plane", "hertz", "vertical"),
         ("wall-floor", "half-sine", "vertical"), ("wall-floor", "hertz", "vertical"),
         ("wall-floor", "half-sine", "horizontal")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one repeat instead of three")
    args = parser.parse_args()
    repeat = 1 if args.quick else 3
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        for config, pulse, plane in CASES:
            s = impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, pulse=pulse, config=config,
                             wall_distance=0.05 if config == "wall-floor" else None)
            height = 0.1 if plane == "horizontal" else None
            level_map(s.pulse, s.geometry, medium=s.medium, resolution=16)  # compile the kernels
            t_map, m = best_of(lambda s=s, height=height, plane=plane: level_map(
                s.pulse, s.geometry, medium=s.medium, plane=plane, height=height), repeat)
            t_csv, _ = best_of(lambda m=m, s=s: write_map_outputs(m, s.geometry, csv=out / "m.csv"), repeat)
            t_png, _ = best_of(lambda m=m, s=s: write_map_outputs(m, s.geometry, png=out / "m.png"), repeat)
            t_vtk, _ = best_of(lambda m=m, s=s: write_map_outputs(m, s.geometry, vtk=out / "m.vtu"), repeat)
            n = m.grid.points.shape[0]
            rows.append((config, pulse, plane, n, t_map, n / t_map, t_csv, t_png, t_vtk))
    head = f"{'config':<11} {'pulse':<10} {'plane':<10} {'points':>7} {'map s':>7} {'points/s':>9} " \
           f"{'csv s':>6} {'png s':>6} {'vtk s':>6}"
    print(head)
    print("-" * len(head))
    for r in rows:
        print(f"{r[0]:<11} {r[1]:<10} {r[2]:<10} {r[3]:>7d} {r[4]:>7.3f} {r[5]:>9.3g} {r[6]:>6.2f} {r[7]:>6.2f} "
              f"{r[8]:>6.2f}")


if __name__ == "__main__":
    main()
