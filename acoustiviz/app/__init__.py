"""The application layer: one place that turns a user's settings into results and files.

The command line (:mod:`acoustiviz.cli`) and scene files (:mod:`acoustiviz.scene`) only parse
their input; both call these functions, so the two front-ends cannot disagree on a rule, a
default or a file format.

* :mod:`.settings` -- one frozen settings object per workflow, checked against one table of ranges,
  defaults and units from which the options and the scene keys are built;
* :mod:`.names` -- errors in the user's words: API parameter names mapped to options or scene keys;
* :mod:`.columns` -- the waveform and directivity tables and the peaks a waveform reports;
* :mod:`.waveform` -- the waveform job: :class:`~.waveform.WaveformJob` (its settings), :func:`~.waveform.run`
  and :class:`~.waveform.WaveformResult` with its files (``docs/guide/layout.md``: the pattern);
* :mod:`.directivity` -- the directivity job: the levels of one impact against angle on a circle, and its files;
* :mod:`.render` -- the 3-D views' memory estimate and files;
* :mod:`.impacts` -- sphere, contact, pulse, medium, configuration and observers of one impact;
* :mod:`.damper` -- build and run a damper model, and the figures reported about it;
* :mod:`.wav` -- auralised WAV files and their one sidecar schema;
* :mod:`.auralize` -- an auralised damper run: its checks, its rendering, its report and files;
* :mod:`.forced` -- the damper in operation: frequency response, its report and files;
* :mod:`.sweep` -- design sweeps from settings, and their output files;
* :mod:`.pipeline` -- run a scene: exactly the outputs it names.
"""
