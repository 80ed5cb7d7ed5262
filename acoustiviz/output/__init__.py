"""Outputs: figures, 3-D renders, audio and the file writers.

:mod:`.plot` draws matplotlib figures, :mod:`.render` pyvista off-screen renders, :mod:`.audio`
calibrated WAV files, and :mod:`.writers` writes every file atomically.
"""
