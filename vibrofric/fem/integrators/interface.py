"""The reduced model's interface: the contact candidates that can touch during a run.

The Craig-Bampton reduction (reduction.py) keeps every DOF of its interface and
condenses the rest; the friction law and the penalty act on the interface's nodes
only. A curved body's candidates are mostly far from its contact patch (the fine
ball: 73 of 636 in the preload's patch), and the set-up's two main costs (the
constraint modes, one sparse solve per interface DOF, and Psi^T M Psi) grow with
the interface. So the interface holds only the candidates within reach of the base:

    kept_i  =  in the preload's patch,  or  g0_i <= fem.interface_reach * g_edge

g0_i the candidate's height at rest (FEModel.initial_gap) and g_edge that of the
preload patch's edge: it lies between the largest g0 in the patch and the smallest
outside it, and is taken as their mean (on a patch resolved by one node, the
coarse ball's, half the first ring's gap). On a Hertz contact (radius R) a
candidate at radius r has g0 = r^2 / 2R, so g_edge = a^2 / 2R with a the patch's
radius; a^2 grows with the load as L^(2/3) (a^3 = 3 F R / 4 E*), so the
candidates a load L F_N brings into contact have g0 <= L^(2/3) g_edge: the
default reach 3 covers the normal force up to 3^(3/2) = 5.2 F_N, well beyond the
swings of the shipped scenes. Where the whole face is in contact at rest (the
block: every g0 = 0) every candidate is kept, and the reduced model is the one
it always was; fem.interface_reach = "all" keeps every candidate on any body.

The candidates left out are interior DOFs of the reduction, linear, and watched:
their gaps g_i = g0_i + u_z,i - z_b (u_z,i = u0_z,i + T_z,i q, a row of the
basis each: ``Watch``) are checked after every step (``watched_contact``), and a
run in which one closes stops (core.errors.ContactBeyondInterface, through
outputs/trouble.py): nothing is silently wrong.

The run itself sees the interface's model (``Interface.model``: the FEModel with
its contact arrays restricted to the kept candidates); what it hands back is on
every candidate again (``Interface.full_state``, ``full_normals``): the others
open, their friction laws at rest.
"""

import dataclasses
import hashlib
from typing import NamedTuple

import numpy as np
from numba import njit

from ...friction_law.contract import FASTMATH
from ..outputs.recording import State

# fem.interface_reach's value that keeps every candidate
ALL = "all"


def kept_candidates(model, reach) -> np.ndarray:
    """(k,) the indices, among model.contact_nodes, of the candidates the interface holds
    (the module docstring): all for ``reach`` "all", else those in the preload's patch or
    with g0_i <= reach * g_patch."""
    candidates = np.arange(model.contact_nodes.size)
    if reach == ALL:
        return candidates
    patch = np.asarray(model.in_contact0, dtype=bool)
    if patch.all() or not patch.any():
        return candidates
    g0 = model.initial_gap
    g_edge = 0.5 * (float(g0[patch].max()) + float(g0[~patch].min()))
    return candidates[patch | (g0 <= reach * g_edge)]


# FEModel's fields with one entry per contact candidate
PER_CANDIDATE = ("contact_nodes", "initial_gap", "contact_area", "area_share", "penalty_share",
                 "nominal_normal", "normal0", "in_contact0")


class Watch(NamedTuple):
    """The candidates left out of the interface, as the compiled step checks them."""

    rows: np.ndarray    # (m, size) T_z,i: the basis's rows of their Z DOFs
    rest: np.ndarray    # (m,) g0_i + u0_z,i: their gaps at the preload (z_b = 0)

    @classmethod
    def none(cls, size: int) -> "Watch":
        """Nothing watched (every candidate on the interface, or the full model)."""
        return cls(np.zeros((0, size)), np.zeros(0))


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def watched_contact(q, rows, rest, z_b) -> bool:
    """Whether a watched candidate has reached the base: g_i = rest_i + rows_i q - z_b < 0,
    where the penalty would push on it (model/contact.py normal_force)."""
    for i in range(rows.shape[0]):
        g = rest[i] - z_b
        for k in range(q.shape[0]):
            g += rows[i, k] * q[k]
        if g < 0.0:
            return True
    return False


@dataclasses.dataclass
class Interface:
    """The choice of interface on a model: ``kept`` (indices among its candidates) of
    ``candidates`` in all."""

    kept: np.ndarray
    candidates: int

    @classmethod
    def of(cls, model, reach) -> "Interface":
        return cls(kept_candidates(model, reach), model.contact_nodes.size)

    @property
    def complete(self) -> bool:
        return self.kept.size == self.candidates

    def left_out(self) -> np.ndarray:
        """The indices among the candidates of those left out (watched)."""
        return np.setdiff1d(np.arange(self.candidates), self.kept)

    def digest(self) -> str:
        """What distinguishes this interface in the model cache's keys ("" for every
        candidate: the entries made before the interface could be chosen)."""
        if self.complete:
            return ""
        return hashlib.blake2b(self.kept.astype(np.int64).tobytes(), digest_size=8).hexdigest()

    def model(self, model):
        """The model with its contact arrays restricted to the interface's candidates (the
        model itself where it holds them all)."""
        if self.complete:
            return model
        return dataclasses.replace(model, **{name: np.asarray(getattr(model, name))[self.kept]
                                             for name in PER_CANDIDATE})

    def watch_rest(self, model) -> np.ndarray:
        """(m,) the left-out candidates' gaps at the preload, g0_i + u0_z,i."""
        out = self.left_out()
        return model.initial_gap[out] + model.u0[3 * model.contact_nodes[out] + 2]

    def watched_dofs(self, model) -> np.ndarray:
        """(m,) the full model's Z DOFs of the left-out candidates."""
        return 3 * model.contact_nodes[self.left_out()] + 2

    def _spread(self, values: np.ndarray, fill: np.ndarray) -> np.ndarray:
        if self.complete:
            return values
        out = np.repeat(fill[None], self.candidates, axis=0) if fill.ndim else \
            np.full(self.candidates, fill)
        out[self.kept] = values
        return out

    def full_state(self, state: State, law) -> State:
        """``state`` (on the interface's candidates) on every candidate: the others open
        (no forces), their friction laws at rest."""
        if self.complete:
            return state
        law_state = self._spread(state.law_state, law.initial_state(1)[0])
        return dataclasses.replace(
            state, law_state=law_state, deformation=law.deformation(law_state),
            normal=self._spread(state.normal, np.float64(0.0)),
            friction=self._spread(state.friction, np.zeros(2)))

    def full_normals(self, node_normals: np.ndarray) -> np.ndarray:
        """(samples, candidates): the interface's N_i over the samples, 0 for the others."""
        if self.complete:
            return node_normals
        out = np.zeros((node_normals.shape[0], self.candidates))
        out[:, self.kept] = node_normals
        return out
