"""Outputs: figures, 3-D renders, WAV files, VTK and HTML files (sinks only: no physics here).

:mod:`.plot` draws matplotlib figures, :mod:`.render` pyvista off-screen renders, :mod:`.audio`
writes the calibrated signals of :mod:`acoustiviz.sound` as WAV files; every file is written
atomically through :mod:`acoustiviz.files`.
"""
