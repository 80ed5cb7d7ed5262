"""Outputs: figures, 3-D renders, WAV files and the file writers (sinks only: no physics here).

:mod:`.plot` draws matplotlib figures, :mod:`.render` pyvista off-screen renders, :mod:`.audio`
writes the calibrated signals of :mod:`acoustiviz.sound` as WAV files, and :mod:`.writers` writes
every file atomically.
"""
