"""The lumped elastic asperity both built-in laws share (paper Fig. 1, eqs 4-11).

One contact node carries one asperity MN: its free end M sits on the base, its
body end N' moves with the body. The state is the deformation vector
d = N' - M, kept as its length s = |d| and direction e = d / s (the paper's
Table 1 carries the same as s and the angle beta), and the sliding length
s_c = F_c / k of the node's previous step: a node's state is
(s, e_x, e_y, s_c). The friction force is F = k s e (eq 1, eqs 38-39).

A changing normal force (``normal_change``; the contract's rule). The paper's
lumped body has a constant F_N; an FE contact node's normal force changes every
step as the block rocks, and with it its sliding length s_c = mu N / k. Before
a step's two phases the asperity is brought to the step's own s_c by one of

    "return"  |s| <= s_lim: an asperity longer than the step's sliding limit
              returns to it at once (the radial return of computational
              contact: Simo and Laursen 1992; Wriggers, Computational Contact
              Mechanics, 2006, ch. 5). Coulomb's inequality |F| <= mu N then
              holds at every step at the step's own N: the junctions cannot
              hold more than mu N, and slip at once when N drops. A rising N
              leaves the asperity as it is (pressing harder does not load it
              tangentially). The default.
    "keep"    the asperity keeps its length; one longer than the new limit
              relaxes only with further slip (Dahl's equation past its limit),
              so |F| may exceed mu N for a while. The rule before the
              contract stated one; kept to compare with.
    "scale"   the asperity keeps its length relative to the sliding length,
              s -> s s_c(N) / s_c(N_prev): F = mu N z with z = s / s_c carried
              (the normalized state of LuGre-type bristle models); the force
              follows N both ways, without slip.

N <= 0 (out of contact) releases the asperity under every rule: s = 0, the
force 0; a node coming back into contact starts from rest.

Each phase of a step (phase 1: the body end moves by the slip, eqs 18-22;
phase 2: the free end moves with the base, eqs 28-35) first stretches the
asperity rigidly to the trial vector, then relaxes its length along the trial
direction by the law (``relax_length`` here for Dahl's, with the sliding
length set by the law).
"""

import math

from numba import njit

from .contract import FASTMATH, Parameter

PAPER = 0  # explicit Euler update, as the paper (eqs 18, 31)
EXACT = 1  # the exact solution for a constant slip rate over the step
UPDATES = ("paper", "exact")   # the choices of contact.update, in code order
RETURN, KEEP, SCALE = 0, 1, 2
NORMAL_CHANGES = ("return", "keep", "scale")  # the choices of contact.normal_change, in code order

# The parameters both asperity laws take, in the order of their params array.
PARAMETERS = {
    "k_t": Parameter(80e6, "N/m", low=0.0, low_open=True,
                     doc="tangential stiffness of the whole contact"),
    "mu": Parameter(0.1, "", low=0.0, doc="Coulomb friction coefficient: F_c = mu F_N (eq 3)"),
    "update": Parameter("exact", choices=UPDATES,
                        doc="\"exact\" for a constant slip rate over the step, or the paper's "
                            "explicit \"paper\" (eq 18)"),
    "normal_change": Parameter("return", choices=NORMAL_CHANGES,
                               doc="what the asperity does when the node's normal force changes: "
                                   "\"return\" to the step's Coulomb limit (|F| <= mu N at every "
                                   "step), \"keep\" its length, or \"scale\" with the limit"),
}
STATE_SIZE = 4                       # (s, e_x, e_y, s_c of the previous step)
INITIAL_STATE = (0.0, 1.0, 0.0, 0.0)  # at rest; before any motion the direction is X


@njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def trial(s, ex, ey, trial_x, trial_y):
    """Length and direction of the trial vector; a zero-length trial keeps the
    previous direction (the paper's guards against 0/0). Returns (|trial|, ex, ey)."""
    length = math.sqrt(trial_x * trial_x + trial_y * trial_y)
    if length > 0.0:
        inverse = 1.0 / length
        ex = trial_x * inverse
        ey = trial_y * inverse
    return length, ex, ey


@njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def to_normal_force(s, s_previous, s_now, reach, rule):
    """The asperity length s carried into a step whose sliding length is s_now (the
    previous step's: s_previous), by the rule ``normal_change`` (module docstring).

    ``reach`` is the largest length the law holds in units of the sliding length (Dahl 1;
    LuGre max(1, F_s / F_c)). "return" takes off what the limit dropped by, down to the
    new limit: an asperity within its old limit lands within the new one, and the
    paper's explicit update keeps any overshoot of its own (its divergence stays
    visible); a limit that held or rose changes nothing.
    """
    if rule == RETURN:
        limit, drop = reach * s_now, reach * (s_previous - s_now)
        if drop > 0.0 and s > limit:
            return max(limit, s - drop)
        return s
    if rule == SCALE and s_previous > 0.0:
        return s * (s_now / s_previous)
    return s


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def relax_length(s, stretch, s_limit, exponent, update):
    """New asperity length after a trial change of length ``stretch`` (= v_r dt).

    Dahl (eqs 2, 4-6) with shape exponent i: ds/dx = r^i along the slip x,
    where r = 1 - (s / s_limit) sgn(v_r) is the distance to the sliding limit
    s_limit = F_c / k in units of it (r < 0, past the limit, relaxes by the
    same law on |r|, keeping its sign). Exactly, over the step's |dx| = |stretch|:

        i = 1:  s' = s_limit sgn + (s - s_limit sgn) exp(-|dx| / s_limit)
        i < 1:  r'^(1-i) = max(0, r^(1-i) - (1 - i) |dx| / s_limit)    (reaches 0: brittle)
        i > 1:  r'^(1-i) = r^(1-i) + (i - 1) |dx| / s_limit              (ductile)

    and s' = (1 - r') s_limit sgn. The paper's explicit update (eq 18):
    s' = s + dx r^i.
    """
    if stretch == 0.0:
        return s
    sgn = 1.0 if stretch > 0.0 else -1.0
    if exponent == 1.0:
        if update == EXACT:
            return s_limit * sgn + (s - s_limit * sgn) * math.exp(-abs(stretch) / s_limit)
        return s + stretch * (1.0 - (s / s_limit) * sgn)
    r = 1.0 - (s / s_limit) * sgn
    distance = abs(r)
    if update == EXACT:
        slip = abs(stretch) / s_limit
        if exponent < 1.0:
            power = 1.0 - exponent
            base = distance ** power - power * slip
            distance = base ** (1.0 / power) if base > 0.0 else 0.0
        elif distance > 0.0:
            power = exponent - 1.0
            distance = (distance ** -power + power * slip) ** (-1.0 / power)
        r = distance if r >= 0.0 else -distance
        return (1.0 - r) * s_limit * sgn
    rate = distance ** exponent if distance > 0.0 else 0.0
    return s + stretch * (rate if r >= 0.0 else -rate)


def deformation(states):
    """(n, 2): the deformation vectors d = s e of states (n, 4) = (s, e_x, e_y, s_c)."""
    return states[:, :1] * states[:, 1:3]
