"""The Dormand-Prince 8(5,3) Runge-Kutta tableau ("DOP853"), vendored with its source named.

Coefficients of the explicit 12-stage, order-8 method with embedded error estimators of orders
5 and 3 used by Hairer's code DOP853:

    E. Hairer, S. P. Norsett and G. Wanner, *Solving Ordinary Differential Equations I: Nonstiff
    Problems*, 2nd ed., Springer (1993), section II.10 ("DOP853") and the Fortran code
    ``dop853.f`` distributed by the authors (http://www.unige.ch/~hairer/software.html);
    after J. R. Dormand and P. J. Prince, "A family of embedded Runge-Kutta formulae",
    J. Comput. Appl. Math. 6 (1980) 19-26, and P. J. Prince and J. R. Dormand, "High order
    embedded Runge-Kutta formulae", J. Comput. Appl. Math. 7 (1981) 67-75.

The decimal values are those of ``dop853.f`` (30 significant digits; the same digits appear in
SciPy's ``solve_ivp`` implementation, BSD licence). Only the 12 stages of the step, the weights
and the two error estimators are kept; the dense-output coefficients are not needed here (the
contact solver locates events by re-stepping from the step start, see ``_contact``).

Arrays (all read-only float64):

``C`` (13,)
    Nodes c_i of stages 0..11 and of the FSAL stage 12 (c = 1).
``A`` (12, 12)
    Strictly lower-triangular stage coefficients a_ij of stages 0..11.
``B`` (12,)
    Weights b_j of the 8th-order solution.
``E5``, ``E3`` (13,)
    Error-estimator weights (the 5th- and 3rd-order differences) applied to stages 0..12,
    stage 12 being the derivative at the new point.

Checks in ``tests/test_dynamics_dop853.py``: the order conditions up to order 8 for quadrature
(sum_j b_j c_j^k = 1/(k+1)) and the row-sum conditions c_i = sum_j a_ij, that each estimator's
weights sum to zero, an observed convergence order of 8 on a smooth problem, and that the compiled
sums equal the sums over the arrays bit for bit.

Compiled pieces shared by every DOP853 solver of the package (the single-ball contact, free and
forced, and the multi-ball contact): :func:`stage_state` and :func:`solution` (a stage's state and
the step's end, in the first ``n`` components only: the quadratures, which no derivative reads,
need no stage states), :func:`estimates` (one component of the two error estimates) and
:func:`error_norm`, Hairer's error norm of one step. The sums run over every coefficient of a row,
zeros included, in stage order: loops that compile once for every stage (the 12 rows unrolled over
their non-zero terms alone make a step about a tenth faster and its compilation a second or more
longer, paid by every first run).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import helper, njit

__all__ = ["N_STAGES", "C", "A", "B", "E3", "E5", "stage_state", "solution", "estimates", "error_norm"]

#: Stages of one step (the 13th, at the new point, is reused as the next step's first).
N_STAGES = 12

_C = (
    0.0,
    0.526001519587677318785587544488e-01,
    0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    0.333333333333333333333333333333,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
    1.0,
)

# nonzero a_ij of stages 1..12 as (j, a_ij); row 12 holds the weights b_j
_A_ROWS = (
    (),
    (  # stage 1
        (0, 5.26001519587677318785587544488e-2),
    ),
    (  # stage 2
        (0, 1.97250569845378994544595329183e-2),
        (1, 5.91751709536136983633785987549e-2),
    ),
    (  # stage 3
        (0, 2.95875854768068491816892993775e-2),
        (2, 8.87627564304205475450678981324e-2),
    ),
    (  # stage 4
        (0, 2.41365134159266685502369798665e-1),
        (2, -8.84549479328286085344864962717e-1),
        (3, 9.24834003261792003115737966543e-1),
    ),
    (  # stage 5
        (0, 3.7037037037037037037037037037e-2),
        (3, 1.70828608729473871279604482173e-1),
        (4, 1.25467687566822425016691814123e-1),
    ),
    (  # stage 6
        (0, 3.7109375e-2),
        (3, 1.70252211019544039314978060272e-1),
        (4, 6.02165389804559606850219397283e-2),
        (5, -1.7578125e-2),
    ),
    (  # stage 7
        (0, 3.70920001185047927108779319836e-2),
        (3, 1.70383925712239993810214054705e-1),
        (4, 1.07262030446373284651809199168e-1),
        (5, -1.53194377486244017527936158236e-2),
        (6, 8.27378916381402288758473766002e-3),
    ),
    (  # stage 8
        (0, 6.24110958716075717114429577812e-1),
        (3, -3.36089262944694129406857109825),
        (4, -8.68219346841726006818189891453e-1),
        (5, 2.75920996994467083049415600797e1),
        (6, 2.01540675504778934086186788979e1),
        (7, -4.34898841810699588477366255144e1),
    ),
    (  # stage 9
        (0, 4.77662536438264365890433908527e-1),
        (3, -2.48811461997166764192642586468),
        (4, -5.90290826836842996371446475743e-1),
        (5, 2.12300514481811942347288949897e1),
        (6, 1.52792336328824235832596922938e1),
        (7, -3.32882109689848629194453265587e1),
        (8, -2.03312017085086261358222928593e-2),
    ),
    (  # stage 10
        (0, -9.3714243008598732571704021658e-1),
        (3, 5.18637242884406370830023853209),
        (4, 1.09143734899672957818500254654),
        (5, -8.14978701074692612513997267357),
        (6, -1.85200656599969598641566180701e1),
        (7, 2.27394870993505042818970056734e1),
        (8, 2.49360555267965238987089396762),
        (9, -3.0467644718982195003823669022),
    ),
    (  # stage 11
        (0, 2.27331014751653820792359768449),
        (3, -1.05344954667372501984066689879e1),
        (4, -2.00087205822486249909675718444),
        (5, -1.79589318631187989172765950534e1),
        (6, 2.79488845294199600508499808837e1),
        (7, -2.85899827713502369474065508674),
        (8, -8.87285693353062954433549289258),
        (9, 1.23605671757943030647266201528e1),
        (10, 6.43392746015763530355970484046e-1),
    ),
    (  # stage 12
        (0, 5.42937341165687622380535766363e-2),
        (5, 4.45031289275240888144113950566),
        (6, 1.89151789931450038304281599044),
        (7, -5.8012039600105847814672114227),
        (8, 3.1116436695781989440891606237e-1),
        (9, -1.52160949662516078556178806805e-1),
        (10, 2.01365400804030348374776537501e-1),
        (11, 4.47106157277725905176885569043e-2),
    ),
)

# the third-order embedded weights differ from b_j in three places: E3 = b - bhat3
_BHAT3 = (
    (0, 0.244094488188976377952755905512),
    (8, 0.733846688281611857341361741547),
    (11, 0.220588235294117647058823529412e-1),
)

# the fifth-order error estimator (dop853.f: ER1, ER6 ... ER12)
_E5 = (
    (0, 0.1312004499419488073250102996e-1),
    (5, -0.1225156446376204440720569753e+1),
    (6, -0.4957589496572501915214079952),
    (7, 0.1664377182454986536961530415e+1),
    (8, -0.3503288487499736816886487290),
    (9, 0.3341791187130174790297318841),
    (10, 0.8192320648511571246570742613e-1),
    (11, -0.2235530786388629525884427845e-1),
)


def _freeze(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a, dtype=np.float64)
    a.setflags(write=False)
    return a


def _tableau():
    a = np.zeros((N_STAGES + 1, N_STAGES))
    for i, row in enumerate(_A_ROWS):
        for j, v in row:
            a[i, j] = v
    b = a[N_STAGES].copy()
    e3 = np.zeros(N_STAGES + 1)
    e3[:N_STAGES] = b
    for j, v in _BHAT3:
        e3[j] -= v
    e5 = np.zeros(N_STAGES + 1)
    for j, v in _E5:
        e5[j] = v
    return _freeze(_C), _freeze(a[:N_STAGES]), _freeze(b), _freeze(e3), _freeze(e5)


C, A, B, E3, E5 = _tableau()


#: The stage coefficients a_ij (rows 0..11) and, as row 12, the weights b_j.
_AB = _freeze(np.vstack([A, B]))


@njit(inline="always")
def _rows(st, y, h, kst, out, n):  # pragma: no cover - compiled
    """``out[:n] = y[:n] + h sum_j ab_(st,j) kst[j]`` over the stages j < ``st``, in order."""
    for i in range(n):
        acc = 0.0
        for j in range(st):
            acc += _AB[st, j] * kst[j, i]
        out[i] = y[i] + h * acc


@njit(inline="always")
def stage_state(st, y, h, kst, ytmp, n):  # pragma: no cover - compiled
    """The state of stage ``st`` (1..11) in its first ``n`` components: ``y + h sum_j a_(st,j) k_j``.

    ``kst`` holds the stages 0..st-1 in its rows.
    """
    _rows(st, y, h, kst, ytmp, n)


@njit(inline="always")
def solution(y, h, kst, ynew, n):  # pragma: no cover - compiled
    """The 8th-order step end in its first ``n`` components: ``ynew = y + h sum_j b_j k_j``."""
    _rows(N_STAGES, y, h, kst, ynew, n)


@njit(inline="always")
def estimates(kst, i):  # pragma: no cover - compiled
    """Component ``i`` of the 5th- and 3rd-order error estimates ``sum_j E5_j k_j`` and ``sum_j E3_j k_j``."""
    a5 = 0.0
    a3 = 0.0
    for j in range(N_STAGES + 1):
        a5 += E5[j] * kst[j, i]
        a3 += E3[j] * kst[j, i]
    return a5, a3


@helper
def error_norm(y, ynew, h, kst, rtol, atol):  # pragma: no cover - compiled
    """Hairer's DOP853 error norm of one step over all components of ``y`` (1 = at tolerance).

    ``kst`` holds the 12 stages and the derivative at the new point (13 rows); the 5th- and
    3rd-order estimates are combined as in ``dop853.f``:
    ``|h| e5 / sqrt((e5 + 0.01 e3) n)`` with ``e_k = sum_i (E_k · k_i / sc_i)²`` and
    ``sc_i = atol_i + rtol max(|y_i|, |ynew_i|)``. A step whose scale ``sc_i`` is not finite (an
    end that overflowed) has an infinite error: it is rejected.
    """
    n = y.shape[0]
    e5 = 0.0
    e3 = 0.0
    for i in range(n):
        sc = atol[i] + rtol * max(abs(y[i]), abs(ynew[i]))
        if not sc < math.inf:
            return math.inf
        a5, a3 = estimates(kst, i)
        q5 = a5 / sc
        q3 = a3 / sc
        e5 += q5 * q5
        e3 += q3 * q3
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)
