"""What the compiled integration loops share: statuses, scipy's coefficients, the result type.

Their argument checks and the runner that enlarges a sample buffer are in :mod:`rotorkit.engines.rk_arguments`.

Both loops, numba's (:mod:`rotorkit.engines.rk_numba`) and C's
(:mod:`rotorkit.engines.rk_c`, whose C source gets its tables from here),
use these, so there is one source of truth for the numbers and one for the
contract of ``integrate``. numpy only: importing this module loads neither
numba nor a C compiler.

The numba loop compiles these numbers in as constants; its cache folder is
named by a digest of this file and ``rk_numba.py``
(:func:`rotorkit.engines.rk_numba.cache_name`), so a changed number compiles
it again. The C loop's source carries them, and its library is signed with
its source, so it is rebuilt too.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rotorkit.errors import ParameterError, RotorkitError

__all__ = [
    "METHODS",
    "STATUS_SUCCESS",
    "STATUS_STEP_TOO_SMALL",
    "STATUS_NON_FINITE",
    "STATUS_MAX_STEPS",
    "STATUS_PAUSED",
    "STATUS_NO_MEMORY",
    "DIVERGED",
    "CoreSignatureError",
    "RKSolution",
    # shared with the two loops (rk_numba compiles the numbers in, rk_c writes them into its C source)
    "STATUS_RUNNING", "SAFETY", "MIN_FACTOR", "MAX_FACTOR", "EPS", "RK45_ID", "DOP853_ID", "METHOD_IDS",
    "RK45_N_STAGES", "RK45_ERROR_ORDER", "RK45_C", "RK45_A", "RK45_B", "RK45_E", "RK45_P", "RK45_PT", "RK45_A_SQ",
    "RK45_C_EXT", "DOP853_N_STAGES", "DOP853_N_STAGES_EXTENDED", "DOP853_ERROR_ORDER", "DOP853_INTERPOLATOR_POWER",
    "DOP853_C", "DOP853_A", "DOP853_B", "DOP853_D", "DOP853_E3", "DOP853_E5",
    "status_message", "loop_method_id",
]

# ---------------------------------------------------------------------------
# Status codes and controller constants (scipy's rk.py values)
# ---------------------------------------------------------------------------

STATUS_SUCCESS = 0
STATUS_STEP_TOO_SMALL = -1
STATUS_NON_FINITE = -2
STATUS_MAX_STEPS = -3
STATUS_PAUSED = -4
#: the C loop could not allocate its scratch memory (the numba loop raises MemoryError instead)
STATUS_NO_MEMORY = -5
STATUS_RUNNING = 1

SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0

RK45_ID = 0
DOP853_ID = 1
METHODS = ("RK45", "DOP853")
METHOD_IDS = {"RK45": RK45_ID, "DOP853": DOP853_ID}

EPS = np.finfo(float).eps

# ---------------------------------------------------------------------------
# Coefficients (data transcribed from scipy.integrate._ivp)
# ---------------------------------------------------------------------------

RK45_N_STAGES = 6
RK45_ERROR_ORDER = 4
RK45_C = np.array([0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1], dtype=np.float64)
RK45_A = np.array([
    [0, 0, 0, 0, 0],
    [1 / 5, 0, 0, 0, 0],
    [3 / 40, 9 / 40, 0, 0, 0],
    [44 / 45, -56 / 15, 32 / 9, 0, 0],
    [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0],
    [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
], dtype=np.float64)
RK45_B = np.array([35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
                  dtype=np.float64)
RK45_E = np.array([-71 / 57600, 0, 71 / 16695, -71 / 1920, 17253 / 339200,
                   -22 / 525, 1 / 40], dtype=np.float64)
RK45_P = np.array([
    [1, -8048581381 / 2820520608, 8663915743 / 2820520608,
     -12715105075 / 11282082432],
    [0, 0, 0, 0],
    [0, 131558114200 / 32700410799, -68118460800 / 10900136933,
     87487479700 / 32700410799],
    [0, -1754552775 / 470086768, 14199869525 / 1410260304,
     -10690763975 / 1880347072],
    [0, 127303824393 / 49829197408, -318862633887 / 49829197408,
     701980252875 / 199316789632],
    [0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844],
    [0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423],
], dtype=np.float64)
# The loop works row-wise on the dense-output weights: one row per power of x.
RK45_PT = np.ascontiguousarray(RK45_P.T)
# Pad A to a square (n_stages + 1) table so both methods share one layout.
RK45_A_SQ = np.zeros((RK45_N_STAGES + 1, RK45_N_STAGES + 1))
RK45_A_SQ[:RK45_N_STAGES, :RK45_N_STAGES - 1] = RK45_A
RK45_C_EXT = np.append(RK45_C, 1.0)

DOP853_N_STAGES = 12
DOP853_N_STAGES_EXTENDED = 16
DOP853_ERROR_ORDER = 7
DOP853_INTERPOLATOR_POWER = 7

DOP853_C = np.array([
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
    0.1,
    0.2,
    0.777777777777777777777777777778,
], dtype=np.float64)

# Non-zero entries of the extended Butcher matrix: {row: {column: value}}.
_DOP853_A_ROWS = {
    1: {
        0: 5.26001519587677318785587544488e-2,
    },
    2: {
        0: 1.97250569845378994544595329183e-2,
        1: 5.91751709536136983633785987549e-2,
    },
    3: {
        0: 2.95875854768068491816892993775e-2,
        2: 8.87627564304205475450678981324e-2,
    },
    4: {
        0: 2.41365134159266685502369798665e-1,
        2: -8.84549479328286085344864962717e-1,
        3: 9.24834003261792003115737966543e-1,
    },
    5: {
        0: 3.7037037037037037037037037037e-2,
        3: 1.70828608729473871279604482173e-1,
        4: 1.25467687566822425016691814123e-1,
    },
    6: {
        0: 3.7109375e-2,
        3: 1.70252211019544039314978060272e-1,
        4: 6.02165389804559606850219397283e-2,
        5: -1.7578125e-2,
    },
    7: {
        0: 3.70920001185047927108779319836e-2,
        3: 1.70383925712239993810214054705e-1,
        4: 1.07262030446373284651809199168e-1,
        5: -1.53194377486244017527936158236e-2,
        6: 8.27378916381402288758473766002e-3,
    },
    8: {
        0: 6.24110958716075717114429577812e-1,
        3: -3.36089262944694129406857109825,
        4: -8.68219346841726006818189891453e-1,
        5: 2.75920996994467083049415600797e1,
        6: 2.01540675504778934086186788979e1,
        7: -4.34898841810699588477366255144e1,
    },
    9: {
        0: 4.77662536438264365890433908527e-1,
        3: -2.48811461997166764192642586468,
        4: -5.90290826836842996371446475743e-1,
        5: 2.12300514481811942347288949897e1,
        6: 1.52792336328824235832596922938e1,
        7: -3.32882109689848629194453265587e1,
        8: -2.03312017085086261358222928593e-2,
    },
    10: {
        0: -9.3714243008598732571704021658e-1,
        3: 5.18637242884406370830023853209,
        4: 1.09143734899672957818500254654,
        5: -8.14978701074692612513997267357,
        6: -1.85200656599969598641566180701e1,
        7: 2.27394870993505042818970056734e1,
        8: 2.49360555267965238987089396762,
        9: -3.0467644718982195003823669022,
    },
    11: {
        0: 2.27331014751653820792359768449,
        3: -1.05344954667372501984066689879e1,
        4: -2.00087205822486249909675718444,
        5: -1.79589318631187989172765950534e1,
        6: 2.79488845294199600508499808837e1,
        7: -2.85899827713502369474065508674,
        8: -8.87285693353062954433549289258,
        9: 1.23605671757943030647266201528e1,
        10: 6.43392746015763530355970484046e-1,
    },
    12: {
        0: 5.42937341165687622380535766363e-2,
        5: 4.45031289275240888144113950566,
        6: 1.89151789931450038304281599044,
        7: -5.8012039600105847814672114227,
        8: 3.1116436695781989440891606237e-1,
        9: -1.52160949662516078556178806805e-1,
        10: 2.01365400804030348374776537501e-1,
        11: 4.47106157277725905176885569043e-2,
    },
    13: {
        0: 5.61675022830479523392909219681e-2,
        6: 2.53500210216624811088794765333e-1,
        7: -2.46239037470802489917441475441e-1,
        8: -1.24191423263816360469010140626e-1,
        9: 1.5329179827876569731206322685e-1,
        10: 8.20105229563468988491666602057e-3,
        11: 7.56789766054569976138603589584e-3,
        12: -8.298e-3,
    },
    14: {
        0: 3.18346481635021405060768473261e-2,
        5: 2.83009096723667755288322961402e-2,
        6: 5.35419883074385676223797384372e-2,
        7: -5.49237485713909884646569340306e-2,
        10: -1.08347328697249322858509316994e-4,
        11: 3.82571090835658412954920192323e-4,
        12: -3.40465008687404560802977114492e-4,
        13: 1.41312443674632500278074618366e-1,
    },
    15: {
        0: -4.28896301583791923408573538692e-1,
        5: -4.69762141536116384314449447206,
        6: 7.68342119606259904184240953878,
        7: 4.06898981839711007970213554331,
        8: 3.56727187455281109270669543021e-1,
        12: -1.39902416515901462129418009734e-3,
        13: 2.9475147891527723389556272149,
        14: -9.15095847217987001081870187138,
    },
}

# Non-zero entries of the dense-output matrix D (rows 3..6 of the interpolant).
_DOP853_D_ROWS = {
    0: {
        0: -0.84289382761090128651353491142e+1,
        5: 0.56671495351937776962531783590,
        6: -0.30689499459498916912797304727e+1,
        7: 0.23846676565120698287728149680e+1,
        8: 0.21170345824450282767155149946e+1,
        9: -0.87139158377797299206789907490,
        10: 0.22404374302607882758541771650e+1,
        11: 0.63157877876946881815570249290,
        12: -0.88990336451333310820698117400e-1,
        13: 0.18148505520854727256656404962e+2,
        14: -0.91946323924783554000451984436e+1,
        15: -0.44360363875948939664310572000e+1,
    },
    1: {
        0: 0.10427508642579134603413151009e+2,
        5: 0.24228349177525818288430175319e+3,
        6: 0.16520045171727028198505394887e+3,
        7: -0.37454675472269020279518312152e+3,
        8: -0.22113666853125306036270938578e+2,
        9: 0.77334326684722638389603898808e+1,
        10: -0.30674084731089398182061213626e+2,
        11: -0.93321305264302278729567221706e+1,
        12: 0.15697238121770843886131091075e+2,
        13: -0.31139403219565177677282850411e+2,
        14: -0.93529243588444783865713862664e+1,
        15: 0.35816841486394083752465898540e+2,
    },
    2: {
        0: 0.19985053242002433820987653617e+2,
        5: -0.38703730874935176555105901742e+3,
        6: -0.18917813819516756882830838328e+3,
        7: 0.52780815920542364900561016686e+3,
        8: -0.11573902539959630126141871134e+2,
        9: 0.68812326946963000169666922661e+1,
        10: -0.10006050966910838403183860980e+1,
        11: 0.77771377980534432092869265740,
        12: -0.27782057523535084065932004339e+1,
        13: -0.60196695231264120758267380846e+2,
        14: 0.84320405506677161018159903784e+2,
        15: 0.11992291136182789328035130030e+2,
    },
    3: {
        0: -0.25693933462703749003312586129e+2,
        5: -0.15418974869023643374053993627e+3,
        6: -0.23152937917604549567536039109e+3,
        7: 0.35763911791061412378285349910e+3,
        8: 0.93405324183624310003907691704e+2,
        9: -0.37458323136451633156875139351e+2,
        10: 0.10409964950896230045147246184e+3,
        11: 0.29840293426660503123344363579e+2,
        12: -0.43533456590011143754432175058e+2,
        13: 0.96324553959188282948394950600e+2,
        14: -0.39177261675615439165231486172e+2,
        15: -0.14972683625798562581422125276e+3,
    },
}


def _matrix_from_rows(shape, rows):
    """Build a dense matrix from ``{row: {column: value}}``.

    Parameters
    ----------
    shape : tuple of int
        Shape of the matrix.
    rows : dict
        Non-zero entries.

    Returns
    -------
    numpy.ndarray
        C-contiguous float64 matrix.
    """
    out = np.zeros(shape, dtype=np.float64)
    for i, row in rows.items():
        for j, value in row.items():
            out[i, j] = value
    return out


def _dop853_error_weights(b):
    """Return scipy's ``(E3, E5)`` error weights for DOP853.

    Parameters
    ----------
    b : numpy.ndarray
        Weights of the 8th-order solution (12 entries).

    Returns
    -------
    e3, e5 : numpy.ndarray
        Weights (13 entries, the last one multiplies ``f(t + h, y_new)``) of
        the 3rd- and 5th-order error estimators.
    """
    e3 = np.zeros(DOP853_N_STAGES + 1)
    e3[:-1] = b
    e3[0] -= 0.244094488188976377952755905512
    e3[8] -= 0.733846688281611857341361741547
    e3[11] -= 0.220588235294117647058823529412e-1
    e5 = np.zeros(DOP853_N_STAGES + 1)
    e5[0] = 0.1312004499419488073250102996e-1
    e5[5] = -0.1225156446376204440720569753e+1
    e5[6] = -0.4957589496572501915214079952
    e5[7] = 0.1664377182454986536961530415e+1
    e5[8] = -0.3503288487499736816886487290
    e5[9] = 0.3341791187130174790297318841
    e5[10] = 0.8192320648511571246570742613e-1
    e5[11] = -0.2235530786388629525884427845e-1
    return e3, e5


DOP853_A = _matrix_from_rows(
    (DOP853_N_STAGES_EXTENDED, DOP853_N_STAGES_EXTENDED), _DOP853_A_ROWS)
DOP853_B = DOP853_A[DOP853_N_STAGES, :DOP853_N_STAGES].copy()
DOP853_E3, DOP853_E5 = _dop853_error_weights(DOP853_B)
DOP853_D = _matrix_from_rows(
    (DOP853_INTERPOLATOR_POWER - 3, DOP853_N_STAGES_EXTENDED), _DOP853_D_ROWS)

#: a state beyond this magnitude has diverged (SI rotor states are many orders smaller)
DIVERGED = 1e10


class CoreSignatureError(RotorkitError, TypeError):
    """The right-hand side is not a function the integration loop can call (see the loop's core contract)."""


class RKSolution(NamedTuple):
    """Result of `integrate`.

    Attributes
    ----------
    t : numpy.ndarray, shape (m,)
        The requested output times (``t_eval``).
    y : numpy.ndarray, shape (n_states, m)
        Samples at ``t``.  Only the first ``n_samples_done`` columns are valid;
        the others (times after ``t_reached`` on failure) are NaN.
    n_samples_done : int
        Number of valid columns of ``y``: every ``t_eval`` not after
        ``t_reached``.
    status : int
        0 success; -1 step size fell below ``10 * eps * |t|``; -2 non-finite
        state or derivative; -3 ``max_steps`` exceeded; -4 paused after
        ``pause_after`` accepted steps (continue from ``t_reached``,
        ``y_reached`` with ``first_step=h_next``); -5 (C loop only) out of
        memory for the loop's scratch arrays.
    t_reached : float
        Time of the last accepted step (``t1`` on success).
    y_reached : numpy.ndarray, shape (n_states,)
        State at ``t_reached``.
    nfev : int
        Number of core evaluations (including the initial-step heuristic and
        the DOP853 dense-output stages).
    n_accepted, n_rejected : int
        Number of accepted and rejected step attempts (a step rejected for a
        non-finite value counts as rejected).
    message : str
        Human-readable description of ``status``.
    h_next : float
        The step size the controller proposes after ``t_reached``.
    """

    t: np.ndarray
    y: np.ndarray
    n_samples_done: int
    status: int
    t_reached: float
    y_reached: np.ndarray
    nfev: int
    n_accepted: int
    n_rejected: int
    message: str
    h_next: float = float("nan")

    @property
    def success(self):
        """bool: True when the integration reached ``t1``."""
        return self.status == STATUS_SUCCESS



def status_message(status, t_reached, max_steps):
    """Human-readable text for a loop status."""
    if status == STATUS_SUCCESS:
        return "The solver successfully reached the end of the integration interval."
    if status == STATUS_STEP_TOO_SMALL:
        return (f"Required step size is less than spacing between numbers "
                f"(step fell below 10*eps*|t|) at t={t_reached!r}.")
    if status == STATUS_NON_FINITE:
        return (f"Non-finite or diverging state (NaN, inf or |y| > {DIVERGED:g}) or non-finite derivative "
                f"just after t={t_reached!r}; integration stopped.")
    if status == STATUS_PAUSED:
        return f"Paused at t={t_reached!r} as asked (pause_after)."
    if status == STATUS_NO_MEMORY:
        return (f"The integration loop could not allocate its scratch memory at t={t_reached!r} "
                f"(out of memory; free some, or integrate a smaller system).")
    if status == STATUS_MAX_STEPS:
        return (f"Maximum number of step attempts (max_steps={max_steps}) "
                f"exceeded at t={t_reached!r}.")
    return f"Unknown status {status} at t={t_reached!r}."


def loop_method_id(method):
    """Map a method name to its loop id (ParameterError if unknown)."""
    try:
        return METHOD_IDS[method]
    except (KeyError, TypeError):
        raise ParameterError(
            f"method={method!r} is not supported; expected one of "
            f"{', '.join(repr(m) for m in METHODS)}.") from None
