"""Fields for other tools: the data behind each render as VTK files (ParaView, pyvista, meshio).

Each writer writes the value the matching render of :mod:`acoustiviz.output.render` draws (a
:class:`~acoustiviz.field.sections.SectionField` or a :class:`~acoustiviz.field.balloon.BalloonData`,
computed beforehand by the physics layer; a writer evaluates nothing), atomically, as an
unstructured grid of quadrilaterals:

* :func:`write_snapshot_vtk` and :func:`write_animation_vtk` -- the planar sections, with the
  pressure at every requested time as point arrays ``pressure_pa_t0000``, ``pressure_pa_t0001``,
  ... (Pa; NaN inside the sphere) and the times in the field data array ``time_s`` (s from the
  start of contact);
* :func:`write_balloon_vtk` -- the measuring sphere of a directivity balloon (radius
  ``distance`` around the contact point) with every metric of
  :func:`acoustiviz.field.field_metrics` as point arrays: ``peak_positive_pa``,
  ``peak_negative_pa``, ``peak_pa``, ``rms_pa`` (Pa), ``exposure_pa2s`` (Pa² s),
  ``peak_spl_db``, ``rms_spl_db`` and ``sel_db`` (dB re 20 µPa);
* :func:`write_map_vtk` -- a level map on its planar grid (``acoustiviz map``), with point arrays
  named with their units: ``peak_pa`` (Pa), ``peak_spl_db`` (dB re 20 µPa), ``sel_db``
  (dB re (20 µPa)²·s), ``time_of_peak_s`` (s from the start of contact) and ``exposure_pa2s``
  (Pa²·s), NaN inside the sphere;
* :func:`write_geometry_vtk` -- the sphere and the reflecting planes, with a cell array
  ``part`` (0 sphere, 1 floor, 2 wall), beside the data as ``<stem>_geometry.vtu``
  (:func:`geometry_path`).

The data file is ``.vtu`` (VTK XML, read by ParaView, pyvista and meshio) or ``.vtkhdf`` (VTK
HDF, read by ParaView >= 5.12 and pyvista). Lengths in m, in the scene frame of
:mod:`acoustiviz.core.images`.
"""

from __future__ import annotations

import errno
import shutil
from pathlib import Path

import numpy as np

from .._validate import ParameterError
from ..core.geometry import Geometry
from ..field.balloon import BalloonData
from ..field.grids import fluid_box
from ..files import atomic_path, write_bytes_atomic

__all__ = [
    "SUFFIXES",
    "pressure_name",
    "geometry_path",
    "planes_dataset",
    "balloon_dataset",
    "geometry_dataset",
    "write_snapshot_vtk",
    "write_animation_vtk",
    "write_balloon_vtk",
    "write_map_vtk",
    "map_dataset",
    "write_geometry_vtk",
]

#: File name endings of the data files.
SUFFIXES = (".vtu", ".vtkhdf")

#: Point arrays of the balloon file: array name -> FieldMetrics attribute.
BALLOON_ARRAYS = {
    "peak_positive_pa": "peak_positive",
    "peak_negative_pa": "peak_negative",
    "peak_pa": "peak",
    "rms_pa": "rms",
    "exposure_pa2s": "exposure",
    "peak_spl_db": "peak_spl_db",
    "rms_spl_db": "rms_spl_db",
    "sel_db": "sel_db",
}


def pressure_name(index: int) -> str:
    """Name of the point array holding the pressure (Pa) of time number ``index``: ``pressure_pa_t0003``."""
    return f"pressure_pa_t{int(index):04d}"


def _check_vtk_path(path, name="path") -> Path:
    p = Path(path)
    if p.suffix.lower() not in SUFFIXES:
        raise ParameterError(name, f"expected a file name ending in {' or '.join(SUFFIXES)}, got {str(path)!r}")
    return p


def geometry_path(path) -> Path:
    """The geometry file written beside the data file ``path``: ``OUT.vtu`` -> ``OUT_geometry.vtu``."""
    p = Path(path)
    return p.with_name(f"{p.stem}_geometry.vtu")


def _quads(n_u: int, n_v: int, offset: int = 0) -> np.ndarray:
    """Quadrilaterals (m, 4) of a lattice whose point ``(i, j)`` has index ``offset + j n_u + i``."""
    i, j = np.meshgrid(np.arange(n_u - 1), np.arange(n_v - 1), indexing="xy")
    a = (j * n_u + i).ravel() + offset
    return np.column_stack([a, a + 1, a + 1 + n_u, a + n_u])


def _grid(points, quads):
    import pyvista as pv

    return pv.UnstructuredGrid({pv.CellType.QUAD: np.asarray(quads, dtype=np.int64)}, np.asarray(points, float))


def planes_dataset(grids, times, fields):
    """An unstructured grid of planar sections carrying the pressure at each time.

    Parameters
    ----------
    grids : sequence of PlanarGrid
        The sections; their points are stored in order, one section after the other.
    times : (k,) array_like
        Times in s, stored in the field data array ``time_s``.
    fields : sequence of (k, n_i) array_like
        Pressure in Pa at each time on each section's points.

    Returns
    -------
    pyvista.UnstructuredGrid
        Point arrays ``pressure_pa_t0000`` ... (one per time, Pa) and ``section`` (index of
        the section of each point); field data ``time_s``.
    """
    tt = np.atleast_1d(np.asarray(times, dtype=float))
    pts, quads, sec = [], [], []
    offset = 0
    for q, g in enumerate(grids):
        pts.append(g.points)
        quads.append(_quads(g.n_u, g.n_v, offset))
        sec.append(np.full(g.points.shape[0], q, dtype=np.int32))
        offset += g.points.shape[0]
    mesh = _grid(np.vstack(pts), np.vstack(quads))
    values = np.hstack([np.asarray(f, dtype=float).reshape(tt.size, -1) for f in fields])
    for k in range(tt.size):
        mesh.point_data[pressure_name(k)] = values[k]
    mesh.point_data["section"] = np.concatenate(sec)
    mesh.field_data["time_s"] = tt
    return mesh


def balloon_dataset(data, metrics):
    """The measuring sphere of a balloon with every metric as point arrays.

    Parameters
    ----------
    data : acoustiviz.field.balloon.BalloonData
        Its lattice of directions, anchor and distance give the points
        ``anchor + distance * directions`` in m.
    metrics : acoustiviz.field.FieldMetrics
        The metrics at those points, in lattice order.

    Returns
    -------
    pyvista.UnstructuredGrid
        Point arrays named in ``BALLOON_ARRAYS``, the balloon's weighted level if it shows one
        (``lcpeak_db``, ``sel_a_db``, ...) and ``direction`` (unit vectors); field
        data ``distance_m`` and ``window_s`` (the RMS window of every point).
    """
    n_t, n_p = data.directions.shape[:2]
    pts = data.anchor + data.distance * data.directions.reshape(-1, 3)
    mesh = _grid(pts, _quads(n_p, n_t))
    for name, attr in BALLOON_ARRAYS.items():
        mesh.point_data[name] = np.asarray(getattr(metrics, attr), dtype=float)
    if data.metric not in ("peak", "rms", "sel"):  # a weighted level shown by the balloon, e.g. lcpeak_db
        mesh.point_data[data.metric.replace("-", "_") + "_db"] = np.asarray(data.level, dtype=float).reshape(-1)
    mesh.point_data["direction"] = data.directions.reshape(-1, 3)
    mesh.field_data["distance_m"] = np.array([data.distance])
    mesh.field_data["window_s"] = np.array([metrics.window])
    return mesh


def _bounds(geometry: Geometry, points) -> np.ndarray:
    """Box (2, 3) in m holding ``points`` and the sphere, its flat sides widened, cut by the planes."""
    pts = np.vstack([np.asarray(points, float).reshape(-1, 3), geometry.centre - geometry.radius,
                     geometry.centre + geometry.radius])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = float(np.max(hi - lo))
    for k in range(3):
        if hi[k] - lo[k] < 0.2 * span:
            lo[k] -= 0.3 * span
            hi[k] += 0.3 * span
    return np.array(fluid_box(geometry, lo, hi))


def geometry_dataset(geometry: Geometry, bounds):
    """The sphere and the planes of ``geometry`` as one unstructured grid.

    Parameters
    ----------
    geometry : acoustiviz.core.geometry.Geometry
        The scene.
    bounds : (2, 3) array_like
        Lower and upper corners in m of the box the planes fill.

    Returns
    -------
    pyvista.UnstructuredGrid
        Triangles of the sphere and one quadrilateral per plane; cell array ``part``
        (0 sphere, 1 floor, 2 wall).
    """
    import pyvista as pv

    lo, hi = np.asarray(bounds, dtype=float)
    sphere = pv.Sphere(radius=geometry.radius, center=geometry.centre, theta_resolution=48, phi_resolution=32)
    tris = sphere.faces.reshape(-1, 4)[:, 1:]
    pts = [np.asarray(sphere.points, float)]
    cells = {pv.CellType.TRIANGLE: tris}
    quads, parts = [], [np.zeros(tris.shape[0], dtype=np.int32)]
    n = pts[0].shape[0]
    for p in geometry.planes:
        k = int(np.argmax(np.abs(p.normal)))
        i, j = [a for a in range(3) if a != k]
        corner = np.empty((4, 3))
        corner[:, k] = p.point[k]
        corner[:, i] = [lo[i], hi[i], hi[i], lo[i]]
        corner[:, j] = [lo[j], lo[j], hi[j], hi[j]]
        pts.append(corner)
        quads.append(np.arange(n, n + 4))
        parts.append(np.array([1 if k == 2 else 2], dtype=np.int32))
        n += 4
    if quads:
        cells[pv.CellType.QUAD] = np.array(quads)
    mesh = pv.UnstructuredGrid(cells, np.vstack(pts))
    # pyvista orders the cells by type as given: triangles first, then quadrilaterals
    mesh.cell_data["part"] = np.concatenate(parts)
    mesh.field_data["sphere_radius_m"] = np.array([geometry.radius])
    mesh.field_data["sphere_centre_m"] = np.asarray(geometry.centre, float)
    return mesh


def _vtu_text(mesh) -> str:
    """``mesh`` as the text of a ``.vtu`` file (binary data base64-encoded, zlib-compressed, as pyvista writes it)."""
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

    writer = vtkXMLUnstructuredGridWriter()
    writer.SetInputData(mesh)
    writer.SetDataModeToBinary()
    writer.SetCompressorTypeToZLib()
    writer.WriteToOutputStringOn()
    if not writer.Write():
        raise OSError(errno.EIO, "cannot write: VTK could not encode the data")
    return writer.GetOutputString()


#: Free space (bytes) a ``.vtkhdf`` needs beyond 8 times the data's size (a 0.33 MiB map made a 2 MiB file).
_HDF_MARGIN = 8 << 20


def _save(mesh, path: Path) -> Path:
    """Write ``mesh`` to ``path`` atomically; a full disk is an :class:`OSError`, never a native abort.

    A ``.vtu`` is encoded in memory and written by Python (:func:`~acoustiviz.files.write_bytes_atomic`).
    VTK's HDF5 writer can only write to a file and aborts the process on a full disk, so for a
    ``.vtkhdf`` the free space is checked first (8 times the data's size and 8 MiB).
    """
    path = Path(path)
    if path.suffix.lower() == ".vtu":
        return write_bytes_atomic(path, _vtu_text(mesh).encode("ascii"))
    need = 8 * mesh.actual_memory_size * 1024 + _HDF_MARGIN
    try:
        free = shutil.disk_usage(path.parent if str(path.parent) else ".").free
    except OSError:
        free = need
    if free < need:
        raise OSError(errno.ENOSPC, f"cannot write: not enough free space ({free / 2**20:.3g} MiB free, about "
                                    f"{need / 2**20:.3g} MiB needed)", str(path))
    with atomic_path(path) as tmp:
        _write_hdf(mesh, tmp)
    return path


def _write_hdf(mesh, path) -> None:
    """Write ``mesh`` with VTK's own HDF writer (VTK >= 9.4; pyvista saves ``.vtkhdf`` only from 0.46 on)."""
    from vtkmodules.vtkIOHDF import vtkHDFWriter

    writer = vtkHDFWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(mesh)
    if not writer.Write():
        raise OSError(errno.EIO, "cannot write: VTK could not write the HDF file", str(path))


def write_geometry_vtk(geometry: Geometry, path, bounds) -> Path:
    """Write :func:`geometry_dataset` to ``path`` (``.vtu``, atomically); return the path."""
    path = Path(path)
    if path.suffix.lower() != ".vtu":
        raise ParameterError("path", f"expected a file name ending in .vtu, got {str(path)!r}")
    return _save(geometry_dataset(geometry, bounds), path)


def _write_with_geometry(mesh, geometry, path: Path, geometry_file: bool) -> tuple:
    out = _save(mesh, path)
    geo = write_geometry_vtk(geometry, geometry_path(path), _bounds(geometry, mesh.points)) if geometry_file else None
    return out, geo


def _sections(field, geometry, path, geometry_file: bool) -> tuple:
    """Write a :class:`~acoustiviz.field.sections.SectionField` (and the scene beside it) to ``path``."""
    from .render.snapshot import _check_field

    path = _check_vtk_path(path)
    field = _check_field(field)
    mesh = planes_dataset(field.grids, field.times, field.pressures)
    return _write_with_geometry(mesh, geometry, path, geometry_file)


def write_snapshot_vtk(field, geometry: Geometry, path, *, geometry_file: bool = True) -> tuple:
    """Write the pressure of a field snapshot on its planar sections to a VTK file.

    The points and values are those :func:`acoustiviz.output.render.render_snapshot` draws from the
    same ``field``.

    Parameters
    ----------
    field : acoustiviz.field.sections.SectionField
        The pressure evaluated by :func:`acoustiviz.field.sections.section_field`.
    geometry : acoustiviz.core.geometry.Geometry
        The scene of ``field``.
    path : path-like
        Output ``.vtu`` or ``.vtkhdf`` file (written atomically).
    geometry_file : bool
        Also write the sphere and planes to :func:`geometry_path` of ``path``.

    Returns
    -------
    (pathlib.Path, pathlib.Path or None)
        The data file and the geometry file.

    Examples
    --------
    >>> plane = geometry("plane", 0.01905)  # doctest: +SKIP
    >>> write_snapshot_vtk(section_field(pulse, plane, 1e-3), plane, "s.vtu")  # doctest: +SKIP
    (PosixPath('s.vtu'), PosixPath('s_geometry.vtu'))
    """
    return _sections(field, geometry, path, geometry_file)


def write_animation_vtk(field, geometry: Geometry, path, *, geometry_file: bool = True) -> tuple:
    """Write every frame of a wavefront animation to one VTK file (one pressure array per frame).

    The frame times, points and values are those :func:`acoustiviz.output.render.render_animation`
    draws from the same ``field`` (zero where no wave has arrived or all have passed, NaN inside the
    sphere).

    Parameters
    ----------
    field : acoustiviz.field.sections.SectionField
        The frames evaluated by :func:`acoustiviz.field.sections.animation_field` (one frame time is
        enough for a data file).
    geometry : acoustiviz.core.geometry.Geometry
        The scene of ``field``.
    path : path-like
        Output ``.vtu`` or ``.vtkhdf`` file (written atomically).
    geometry_file : bool
        Also write the sphere and planes to :func:`geometry_path` of ``path``.

    Returns
    -------
    (pathlib.Path, pathlib.Path or None)
        The data file and the geometry file.
    """
    return _sections(field, geometry, path, geometry_file)


def write_balloon_vtk(data, geometry: Geometry, path, *, geometry_file: bool = True) -> tuple:
    """Write the metrics of a directivity balloon on its measuring sphere to a VTK file.

    The points are the closed lattice of ``data`` at its distance from the contact point (the whole
    sphere, the half space above the plane or the quarter space of the corner), the values every
    metric ``data`` holds there (see ``BALLOON_ARRAYS`` for the names).

    Parameters
    ----------
    data : acoustiviz.field.balloon.BalloonData
        The balloon computed by :func:`acoustiviz.field.balloon.balloon_data`, holding its metrics
        (``data.metrics``; a balloon of a level of its own gets them from
        :func:`acoustiviz.field.balloon.balloon_metrics`).
    geometry : acoustiviz.core.geometry.Geometry
        The scene of ``data``.
    path : path-like
        Output ``.vtu`` or ``.vtkhdf`` file (written atomically).
    geometry_file : bool
        Also write the sphere and planes to :func:`geometry_path` of ``path``.

    Returns
    -------
    (pathlib.Path, pathlib.Path or None)
        The data file and the geometry file.
    """
    path = _check_vtk_path(path)
    if not isinstance(data, BalloonData):
        raise ParameterError("data", f"expected a BalloonData, got {type(data).__name__}")
    if data.metrics is None:
        raise ParameterError("data", "holds no field metrics: add them with acoustiviz.field.balloon.balloon_metrics")
    return _write_with_geometry(balloon_dataset(data, data.metrics), geometry, path, geometry_file)


def map_dataset(grid, arrays):
    """A planar grid carrying point arrays, as an unstructured grid of quadrilaterals.

    Parameters
    ----------
    grid : acoustiviz.field.grids.PlanarGrid
        The points in m, in order.
    arrays : mapping of str to (n,) array_like
        Point arrays, each named with its unit (``peak_spl_db``, ``time_of_peak_s``).

    Returns
    -------
    pyvista.UnstructuredGrid
    """
    mesh = _grid(grid.points, _quads(grid.n_u, grid.n_v))
    n = grid.points.shape[0]
    for name, values in arrays.items():
        v = np.asarray(values, dtype=float)
        if v.shape != (n,):
            raise ParameterError("arrays", f"array {name!r} must have {n} values, got shape {v.shape}")
        mesh.point_data[name] = v
    return mesh


def write_map_vtk(grid, arrays, geometry: Geometry, path, *, geometry_file: bool = True) -> tuple:
    """Write a level map (``acoustiviz map``) to a VTK file, the sphere and planes beside it.

    Parameters
    ----------
    grid : acoustiviz.field.grids.PlanarGrid
        The map's points in m.
    arrays : mapping of str to (n,) array_like
        Point arrays named with their units (``peak_pa``, ``peak_spl_db``, ``sel_db``,
        ``time_of_peak_s``, ``exposure_pa2s``; NaN where there is no fluid).
    geometry : acoustiviz.core.geometry.Geometry
        The scene.
    path : path-like
        Output ``.vtu`` or ``.vtkhdf`` file (written atomically).
    geometry_file : bool
        Also write the sphere and planes to :func:`geometry_path` of ``path``.

    Returns
    -------
    (pathlib.Path, pathlib.Path or None)
        The data file and the geometry file.
    """
    path = _check_vtk_path(path)
    return _write_with_geometry(map_dataset(grid, arrays), geometry, path, geometry_file)
