"""Named records passed to and returned by the compiled impact-damper kernels (numba).

numba compiles :func:`collections.namedtuple` classes as structs whose fields are read by name;
defined at module level they pickle, so kernels taking or returning them stay in numba's disk
cache. The parameter vector ``p`` (``PARAM_COLUMNS`` of :mod:`._status`) is what the drivers are
called with from Python; :func:`as_params` (compiled) and :func:`params_record` (Python) turn it
into :class:`Params`, the only place its entries are read by position.
"""

from __future__ import annotations

from collections import namedtuple

from numba import njit

__all__ = ["Params", "Advanced", "DriverResult", "ContactStart", "ContactEnd", "NmBooks", "DenseOutput", "Turns",
           "as_params", "params_record", "without_main"]

#: The model as the kernels see it (paper eq 15): main mass ``M`` (kg), main spring ``K`` (N/m),
#: main dashpot ``C`` (N s/m), damper mass ``m`` (kg), half the gap ``half_gap`` (m), Hertz
#: stiffness ``k_hertz`` (N/m^1.5), contact damping ``c1`` (N s/m) and ``clip`` (True: the contact
#: force is clipped at zero instead of pulling).
Params = namedtuple("Params", ["M", "K", "C", "m", "half_gap", "k_hertz", "c1", "clip"])

#: What a stepping kernel returns: ``n`` the next free impact row, ``status`` a ``STATUS_*`` code
#: of :mod:`._status`, ``t`` the time reached (s) and ``ie`` the next dense-output time due.
Advanced = namedtuple("Advanced", ["n", "status", "t", "ie"])


#: What :func:`~acoustiviz.dynamics._newmark.newmark_advance` books: impact rows ``impacts``
#: (``IMPACT_COLUMNS`` of :mod:`._status`) up to the row limit ``max_impacts``, accumulators ``acc``
#: (added to: work of the forcing, dissipated by the dashpot, dissipated in contacts, J; with
#: ``minmax`` True also the largest and smallest main-mass displacement in m, ``acc[3:5]``).
NmBooks = namedtuple("NmBooks", ["impacts", "max_impacts", "acc", "minmax"])

#: Dense output of a stepping kernel: output times ``t_eval`` (s), the index ``ie`` of the next one
#: due, and ``rows`` (n, 6): x, v, y, w (m, m/s) and the energies dissipated by the dashpot and in
#: contacts (J) at those times. A kernel given None instead compiles without dense output.
DenseOutput = namedtuple("DenseOutput", ["t_eval", "ie", "rows"])

#: Turning points of the main-mass displacement: ``rows`` (time s, x m, +1 maximum / -1 minimum)
#: and ``count`` (a one-element int array, the rows filled). None: compiled without them.
Turns = namedtuple("Turns", ["rows", "count"])


@njit(cache=True, inline="always")
def as_params(p):
    """The :class:`Params` of the parameter vector ``p`` (``PARAM_COLUMNS``, SI; ``clip`` 1.0 or 0.0)."""
    return Params(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7] > 0.5)


def params_record(p) -> Params:
    """:class:`Params` of the parameter vector ``p`` in Python (the same float64 values)."""
    return Params(*(float(v) for v in p[:7]), bool(p[7] > 0.5))


#: What the forced driver returns: ``n`` the next free impact row and ``status`` a ``STATUS_*`` code.
DriverResult = namedtuple("DriverResult", ["n", "status"])

#: Where a contact starts (or resumes): time ``tc`` (s), wall ``sw`` (±1), main-mass displacement
#: ``x`` (m) and velocity ``v`` (m/s), ``xi`` the square root of the penetration (m^0.5) and ``u``
#: the penetration rate (m/s).
ContactStart = namedtuple("ContactStart", ["tc", "sw", "x", "v", "xi", "u"])

#: What :func:`~acoustiviz.dynamics._contact.contact` returns: ``ended`` (the bodies parted before
#: the end time), ``status`` (a ``STATUS_*`` code), ``ie`` (the next dense-output time due),
#: ``duration`` (s integrated), ``peak`` (the largest contact force, N) and ``y`` (the contact
#: state at the end, t counted from the start; a view of the caller's work buffer).
ContactEnd = namedtuple("ContactEnd", ["ended", "status", "ie", "duration", "peak", "y"])


@njit(cache=True, inline="always")
def without_main(prm):
    """The two masses alone: ``prm`` with the main spring and dashpot (``K``, ``C``) set to zero."""
    return Params(prm.M, 0.0, 0.0, prm.m, prm.half_gap, prm.k_hertz, prm.c1, prm.clip)
