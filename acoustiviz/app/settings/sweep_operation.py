"""Settings of a sweep in operation: ``acoustiviz sweep --force F0 | --base B --freq ...`` and ``in_operation``.

A sweep evaluates every design under a harmonic excitation over a band of frequencies
(:func:`acoustiviz.sweep.run_operation`) instead of in free vibration when an amplitude is given. The
options are those of ``acoustiviz forced`` (:mod:`acoustiviz.app.settings.forced`: the same ranges and
defaults): :data:`OPERATION_OPTIONS` holds the amplitude of each kind, the frequencies and the search
options the sweep command lacks; the sweep's ``--solver`` and ``--rtol`` then set the search's solver and
contact tolerance, checked against the records of ``forced`` (``impact-map`` allowed, ``rtol`` in its range,
by default 1e-10). A scene asks for it with ``[outputs.sweep] in_operation = true`` (:data:`IN_OPERATION`)
(a record of :data:`~acoustiviz.app.settings.sweep.SCENE_SWEEP`)
and takes the excitation from its ``[excitation]`` table, as its frequency response does.
"""

from __future__ import annotations

import dataclasses

from ...errors import ParameterError
from .forced import AMPLITUDE, FORCED, FREQUENCIES
from .sweep import SWEEP
from .table import by_name

__all__ = ["OPERATION_OPTIONS", "FREE_VIBRATION_ONLY", "split_operation", "SEARCH"]

#: The search records of ``acoustiviz forced`` (the sweep's ``--solver`` and ``--rtol`` set those two in operation).
SEARCH = by_name(FORCED)

#: The options of a sweep in operation: the amplitude of either kind, the band and the search the sweep lacks.
OPERATION_OPTIONS = (
    dataclasses.replace(AMPLITUDE, name="force", option="--force", key=None, default=None, unit="N", table="",
                        metavar="F0", doc="sweep in operation: force amplitude F0 cos(wt) on the main mass"),
    dataclasses.replace(AMPLITUDE, name="base", option="--base", key=None, default=None, unit="m", table="",
                        metavar="B", doc="sweep in operation: base displacement amplitude B cos(wt) (instead of "
                        "--force)"),
    dataclasses.replace(FREQUENCIES, kind="str", key=None, default=None, table="",
                        doc=f"{FREQUENCIES.doc}; each in {FREQUENCIES.range_text()} (required with --force or "
                        "--base)"),
    *(dataclasses.replace(SEARCH[n], key=None, default=None, table="", doc=f"{SEARCH[n].doc} (default "
                          f"{SEARCH[n].default if n == 'sweep' else format(SEARCH[n].default, 'g')})")
      for n in ("sweep", "starts", "tolerance", "max_cycles", "noise_seconds")),
)

#: The sweep's settings of the free run alone (its length, initial velocity, impact pulses and levels): a sweep in
#: operation refuses them typed, and a scene's sweep in operation leaves them at the command line's defaults, so
#: both build the same job.
FREE_VIBRATION_ONLY = ("duration", "levels", "v0", "n_fastest", "pulse", "pulse_mass")

_NAMES = tuple(s.name for s in OPERATION_OPTIONS)


def split_operation(given: dict) -> tuple:
    """``(operation, rest)``: the :class:`~acoustiviz.sweep.Operation` of ``given``'s values (None: free vibration).

    ``given`` holds values as typed: ``force`` in N or ``base`` in m, ``frequencies`` as text
    (``START:STOP:COUNT``, ``F1,F2,...`` or one value, in Hz), ``sweep``, ``starts``, ``tolerance``,
    ``max_cycles``, ``noise_seconds`` (s), and in operation ``solver`` and ``rtol``; absent ones take
    ``acoustiviz forced``'s defaults. In operation, a value of :data:`FREE_VIBRATION_ONLY` other than its
    default is refused. ``rest`` is ``given`` without them (the free-vibration solver and
    rtol stay when there is no operation). Errors name the API parameter.
    """
    from ...sweep import Operation
    from .parse import parse_frequencies

    typed = {k: given[k] for k in _NAMES if given.get(k) is not None}
    rest = {k: v for k, v in given.items() if k not in _NAMES}
    force, base = typed.get("force"), typed.get("base")
    if force is None and base is None:
        if typed:
            raise ParameterError(next(iter(typed)), "applies only to a sweep in operation (give --force F0 or "
                                                    "--base B, and --freq)")
        return None, rest
    unset = (None, False, SWEEP[0].default)  # not given (the command line fills in the duration's default)
    free = [k for k in FREE_VIBRATION_ONLY if rest.get(k) not in unset]
    if free:
        raise ParameterError(free[0], "applies only to a sweep of free vibration, not to one in operation")
    if force is not None and base is not None:
        raise ParameterError("base", "give either a force amplitude (--force) or a base amplitude, not both")
    if "frequencies" not in typed:
        raise ParameterError("frequencies", "is required for a sweep in operation (START:STOP:COUNT, a comma list "
                                            "or one value, in Hz)")
    records = by_name(OPERATION_OPTIONS)
    kind = "force" if force is not None else "base"
    amplitude = records[kind].check(typed[kind], kind)
    freqs = tuple(float(f) for f in parse_frequencies(typed["frequencies"], "frequencies"))
    search = {n: SEARCH[n].check(rest.pop(n, None) if n in ("solver", "rtol") else typed.get(n), n)
              for n in ("sweep", "solver", "starts", "tolerance", "rtol", "max_cycles", "noise_seconds")}
    search = {n: SEARCH[n].default if v is None else v for n, v in search.items()}
    return Operation(amplitude, freqs, kind=kind, **search), rest
