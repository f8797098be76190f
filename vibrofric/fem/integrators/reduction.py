"""The reduced model: the block condensed onto what the friction law needs (Craig-Bampton).

The friction law and the penalty contact act on the contact-face nodes only,
the drive on its attachment, and the excitation (3-4 kHz and the harmonics
the friction makes) lies below most of the block's elastic modes. So the
block's displacement from the preload is written

    u - u0 = T q,   T = [ I    0    0   ]   rows: the boundary b (the interface's contact
                        [ Psi  Phi  psi ]         candidates' X, Y, Z: interface.py)
                                                  the interior i (all other DOFs)

with q = (u_b, eta, xi):

    Psi = -K_ii^-1 K_ib   constraint modes: the static shape of the block when
                          one boundary DOF moves by 1 and the others stay
                          (Guyan's static condensation)
    Phi                   fixed-interface modes (K_ii phi = w^2 M_ii phi, the
                          face clamped) with f < fem.cutoff * vibration.f,
                          M_ii-normalized (Craig & Bampton, AIAA J. 6, 1968)
    psi                   the drive's attachment mode when the drive pulls on
                          interior nodes (drive.attach = "front-face"):
                          K_ii^-1 d_i, M_ii-orthogonalized against Phi

The model's equations are projected: M_r = T^T M T, K_r = T^T K T (dense,
size 3 contacts + modes + 1), C_r = beta K_r, x_A = (T^T d)^T q, and the
contact forces act on u_b = q_b directly (T^T P = P). Statics are exact for
loads on the face and the drive (constraint and attachment modes span them);
what is lost is the interior's inertia beyond the kept modes, which at the
excitation frequency w scales as (w / w_cut)^2. The reduced system runs in
the implicit integrator (implicit.py) with its dense inverse.

Its error is measured, not assumed: ``compliance_error`` compares the
face's dynamic compliance of the reduced and the full model, on the
contact linearized about the preload (k_t w_i in X, Y; k_pen w_i in Z on the
candidates in the preload's patch, the others open), for uniform tractions on
the patch in X and Y and the drive's load, at the harmonics h f of the excitation
that the friction force carries (compared_harmonics: 3, or up to 8 on a
fast-sliding or stiff contact), with a 5% loss factor (the friction's
hysteresis) so that a resonance does not make the comparison singular:

    e = max_{p, h} |c_red(h w) - c_full(h w)| / |c(0)|,   c = p^T (K + L - w^2 M)^-1 p

(c(0) the same for both: the reduction is exact in statics). F_dv moves with
the contact's compliance by less than one for one (the block's own
compliance, ~5% of 1 / k_t, moves F_dv by ~2.8% on the Fig 7 scene), so e
estimates the reduction's F_dv error from above: on the Fig 7 scene
(coarse mesh, dt = 1e-6 s, against the explicit run) e = 15% for a cutoff
of 5 f where F_dv is off by 0.18% (a 5 ms run), e = 0.8% for 12 f (the
default) where it is off by 0.04% (0.3 s). The third harmonic is the hard
one: 12 kHz lies between the block's rocking modes on its contact (10.7
and 12.7 kHz). On a curved body most candidates are open at the preload, and
with every candidate on the interface (fem.interface_reach = "all") the
fixed-interface modes are clamped on all of them: the coarse ball keeps 3
modes below the cutoff (from 22.9 kHz) against 6 (from 11.7 kHz) on its
5-candidate default interface, on which the out-of-reach candidates are free;
its periodic F_dv at dt = 5e-6 s is off the full model's by 0.47% (the
default interface's by 0.007%), and e says 0.41% (1.5e-5). Springs on the
open candidates would clamp the face in the comparison as well, where that
basis is exact: e was 1e-4 so.

The full model's compliances at all the compared harmonics come from one
real factorization (FullCompliance: a Krylov space of the shifted model,
grown until they settle to 1e-10 of themselves); they agree with the
complex LU at each harmonic (direct_compliance) to ~1e-12 of c(0).

Cost. The set-up factorizes K_ii, solves it for every boundary DOF (3 per
interface node: on a curved body only the candidates within fem.interface_reach
of the base, interface.py), forms T^T M T and T^T K T (dense, dofs x size^2) and, for the
error, factorizes the full real matrix K + L + s M once and solves it a few
dozen times (FullCompliance); a step
costs ~3 size^2 multiply-adds. ``vibrofric bench`` reports both per mesh level.

A sweep runs many scenes on one block: the Fig 12 grid's 125 points differ
only in the vibration's level and angle. The reduction depends on the model
and the cutoff only, the full model's compliance on the model, the contact's
stiffness and the frequency; a process keeps both for the last model it
reduced (``reduced``, ``_full_compliance``), recognized by its matrices'
content, and ``forget()`` drops them. On the Fig 12 study the set-up was
0.75 s of each point's 2.8 s. Both are also kept on disk (model/model_cache.py), so
that a repeat run or another process finds them built.

The steps need only the small arrays: M_r, K_r, the boundary and the
projections T^T d of the drive and of the compliance's loads, which the set-up
computes once from T. T itself (dofs x size, 0.7 GB on a 47k-DOF ball) only
expands a state into the whole field, for frames and the run's last fields: from
the model cache it is read (mapped, and checked) when first asked for
(``Reduction.basis``), not at set-up.
"""

import hashlib
import math
import time

import numpy as np
import scipy
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from ...core.errors import ReductionFailed
from ...core.law_limits import sliding_length
from ..model import model_cache
from .generalized_alpha import LinearSystem
from .implicit import ImplicitRun
from .interface import Interface, Watch
from ..model.linalg import (dof_points, fastest_spd_factor, nested_dissection, spd_factor,
                            symmetric_lu)

# Harmonics of the excitation at which the compliance is compared (compared_harmonics),
# and the loss factor.
HARMONICS = 3
MAX_HARMONICS = 8
LOSS_FACTOR = 0.05
# What the compliance's loads and springs act on (_compliance_loads, _linearized_contact),
# in the model cache's keys of the entries that hold them: the preload's patch
COMPLIANCE_LOADS = "patch"
# The full model's compliance (FullCompliance): its Krylov space is grown until no
# compliance moves by more than KRYLOV_TOLERANCE of itself over a block, at most
# KRYLOV_BLOCKS blocks; a new direction below DEFLATION of its norm is dropped
KRYLOV_TOLERANCE = 1e-10
KRYLOV_BLOCKS = 100
DEFLATION = 1e-10
# Below this many interior DOFs the fixed-interface modes are found densely.
DENSE_EIGEN = 600


def model_key(model) -> str:
    """A digest of what the reduction and the compliance are computed from."""
    K = model.stiffness.tocsr()
    digest = hashlib.blake2b(digest_size=16)
    for array in (K.indptr, K.indices, K.data, model.disc.mass, model.contact_nodes,
                  model.area_share, model.penalty_share, model.attach_nodes,
                  model.attach_weights, model.disc.coordinates):
        digest.update(np.ascontiguousarray(array).tobytes())
    return digest.hexdigest()


# The last model's reduction, by (model_key, cutoff), and its full compliances by
# (model_key, contact stiffness, omega).
_last_reduction: dict = {}
_full_compliance: dict = {}


def forget() -> None:
    """Drop the kept reduction and compliances (the next run computes them again)."""
    _last_reduction.clear()
    _full_compliance.clear()


def reduced(model, cutoff_hz: float, watched=None, interface: str = "") -> "Reduction":
    """Reduction(model, cutoff_hz, watched), or the one this process made last for the
    same, or the one the model cache holds (model/model_cache.py): its small arrays read,
    its basis read when first asked for (``Reduction.basis``). ``model`` is the
    interface's (interface.Interface.model), ``watched`` the Z DOFs of the candidates it
    left out and ``interface`` its digest (Interface.digest: "" for every candidate)."""
    key = model_key(model)
    watched = np.zeros(0, dtype=np.int64) if watched is None else watched
    if (key, cutoff_hz, interface) not in _last_reduction:
        forget()
        parts = {"model": key, "cutoff_hz": float(cutoff_hz), "numpy": np.__version__,
                 "scipy": scipy.__version__, "compliance_loads": COMPLIANCE_LOADS}
        if interface:
            parts["interface"] = interface
        built = []

        def build():
            made = Reduction(model, cutoff_hz, key, watched)
            built.append(made)
            return {**made.arrays(),
                    "basis_sha256": model_cache.store_array("basis", parts, made.basis)}

        arrays = model_cache.cached("reduction", parts, build)
        if built:
            made = built[0]
        else:
            def basis():
                shape = (model.dofs, arrays["mass"].shape[0])
                T = model_cache.mapped_array("basis", parts, str(arrays["basis_sha256"]),
                                             shape)
                if T is None:   # pruned or damaged: made again (the same computation)
                    T = Reduction(model, cutoff_hz, key, watched).basis
                    model_cache.store_array("basis", parts, T)
                return T

            made = Reduction.from_arrays(arrays, key, basis)
        _last_reduction[key, cutoff_hz, interface] = made
    return _last_reduction[key, cutoff_hz, interface]


class Reduction:
    """The Craig-Bampton basis of a model and the reduced matrices.

    basis       T (dofs, size), dense (read when first asked for: from_arrays)
    mass, stiffness   M_r, K_r (size, size)
    boundary    the full-model DOFs of q_b, contact node by node (X, Y, Z)
    frequencies the kept fixed-interface modes' frequencies, Hz
    drive_x, drive_y  T^T d_x, T^T d_y (size,): the drive's attachment weights d on
                the nodes' X, Y DOFs, projected (x_A = (T^T d_x)^T q)
    compliance_loads  T^T P (size, 3): compliance_error's loads P projected
    watch_rows  T's rows (m, size) of the ``watched`` DOFs: the Z of the candidates the
                interface left out (interface.py), whose gaps the run watches
    model_key   model_key(model): its full compliances are kept under it
    compliances the reduced compliances computed so far, by (k_t, omega) (compliance_error)
    """

    # model_cache's entry: all but the basis, which it keeps apart
    STORED = ("boundary", "frequencies", "mass", "stiffness", "drive_x", "drive_y",
              "compliance_loads")

    def arrays(self) -> dict:
        """What model_cache stores of it in its entry (the watched rows where there are
        any: an entry of a whole-candidate interface is as it always was)."""
        arrays = {name: getattr(self, name) for name in self.STORED}
        if self.watch_rows.shape[0]:
            arrays["watch_rows"] = self.watch_rows
        return arrays

    @classmethod
    def from_arrays(cls, arrays: dict, key: str, basis) -> "Reduction":
        """The Reduction that ``arrays()`` gave, for the model of ``model_key`` ``key``;
        ``basis()`` gives its T, called when T is first asked for."""
        reduction = cls.__new__(cls)
        reduction.model_key = key
        reduction.compliances = {}
        for name in cls.STORED:
            setattr(reduction, name, arrays[name])
        reduction.watch_rows = (arrays["watch_rows"] if "watch_rows" in arrays
                                else np.zeros((0, reduction.size)))
        reduction._basis, reduction._read_basis = None, basis
        return reduction

    @property
    def basis(self) -> np.ndarray:
        """T (dofs, size)."""
        if self._basis is None:
            self._basis = self._read_basis()
            self._read_basis = None
        return self._basis

    @property
    def size(self) -> int:
        return self.mass.shape[0]

    def __init__(self, model, cutoff_hz: float, key: str | None = None, watched=None):
        self.model_key = key if key is not None else model_key(model)
        self.compliances = {}
        n = model.dofs
        boundary = (3 * model.contact_nodes[:, None] + np.arange(3)[None, :]).ravel()
        interior = np.setdiff1d(np.arange(n), boundary)
        K = model.stiffness.tocsr()
        K_ii = K[interior][:, interior].tocsc()
        K_ib = K[interior][:, boundary]
        mass_i = model.disc.mass[interior]
        # nested dissection where the model found a structured grid (fe_model), else
        # the sparse LU's minimum degree
        order = (None if model.elimination_order is None
                 else nested_dissection(dof_points(model.disc.coordinates)[interior]))
        lu = spd_factor(K_ii, order)
        constraint = -lu.solve(K_ib.toarray())                  # Psi
        modes, omega = self._modes(K_ii, mass_i, lu, 2.0 * math.pi * cutoff_hz)
        drive = np.zeros(n)
        drive[3 * model.attach_nodes] = model.attach_weights
        extra = []
        if np.any(drive[interior] != 0.0):                       # the attachment mode psi
            psi = lu.solve(drive[interior])
            psi -= modes @ (modes.T @ (mass_i * psi))
            psi /= math.sqrt(psi @ (mass_i * psi))
            extra.append(psi[:, None])
        size = boundary.size + omega.size + len(extra)
        T = np.zeros((n, size))
        T[boundary, np.arange(boundary.size)] = 1.0
        T[np.ix_(interior, np.arange(boundary.size))] = constraint
        T[interior, boundary.size:] = np.hstack([modes] + extra)
        self._basis = T
        self.boundary = boundary
        self.watch_rows = T[np.zeros(0, dtype=np.int64) if watched is None else watched]
        self.drive_x, self.drive_y = (T.T @ d for d in _drive_loads(model))
        self.compliance_loads = T.T @ _compliance_loads(model, boundary)
        self.frequencies = omega / (2.0 * math.pi)
        self.mass, self.stiffness = self._projected(K, model.disc.mass, boundary, interior,
                                                    constraint, T[interior, boundary.size:])

    @staticmethod
    def _projected(K, mass, boundary, interior, constraint, shapes):
        """M_r = T^T M T and K_r = T^T K T from the blocks, without T's products with the
        whole model (on the fine mesh 31 k x 1,078 twice over). With the interior shapes
        V = [Phi psi], M lumped and Psi^T K_ii = -K_bi (a constraint mode is static):

            K_r = [[K_bb + K_bi Psi, 0], [0, V^T K_ii V]]
            M_r = [[M_bb + Psi^T M_ii Psi, Psi^T M_ii V], [V^T M_ii Psi, V^T M_ii V]]
        """
        nb, size = boundary.size, boundary.size + shapes.shape[1]
        mass_i = mass[interior]
        K_bi = K[boundary][:, interior]
        weighted = mass_i[:, None] * constraint                  # M_ii Psi
        M_r, K_r = np.zeros((size, size)), np.zeros((size, size))
        M_r[:nb, :nb] = np.diag(mass[boundary]) + constraint.T @ weighted
        M_r[:nb, nb:] = weighted.T @ shapes
        M_r[nb:, :nb] = M_r[:nb, nb:].T
        M_r[nb:, nb:] = shapes.T @ (mass_i[:, None] * shapes)
        K_r[:nb, :nb] = K[boundary][:, boundary].toarray() + K_bi @ constraint
        K_r[nb:, nb:] = shapes.T @ (K[interior][:, interior] @ shapes)
        return 0.5 * (M_r + M_r.T), 0.5 * (K_r + K_r.T)

    @staticmethod
    def _modes(K_ii, mass_i, lu, omega_cut):
        """Fixed-interface modes with w < omega_cut: (interior, k) M_ii-normalized, and w."""
        if omega_cut <= 0.0:
            return np.zeros((mass_i.size, 0)), np.zeros(0)
        if mass_i.size <= DENSE_EIGEN:
            w2, vectors = la.eigh(K_ii.toarray(), np.diag(mass_i))
            keep = w2 < omega_cut ** 2
            return vectors[:, keep], np.sqrt(w2[keep])
        operator = sla.LinearOperator(K_ii.shape, matvec=lu.solve, dtype=float)  # shift-invert at 0
        start = np.random.default_rng(0).standard_normal(mass_i.size)  # reproducible runs
        k = 6
        while True:
            k = min(k, mass_i.size - 2)
            w2, vectors = sla.eigsh(K_ii, k=k, M=sp.diags(mass_i), sigma=0.0, which="LM",
                                    OPinv=operator, v0=start)
            order = np.argsort(w2)
            w2, vectors = w2[order], vectors[:, order]
            if w2[-1] >= omega_cut ** 2 or k == mass_i.size - 2:
                keep = w2 < omega_cut ** 2
                vectors = vectors[:, keep] / np.sqrt(np.sum(vectors[:, keep] ** 2 * mass_i[:, None], axis=0))
                return vectors, np.sqrt(w2[keep])
            k *= 2

    def system(self) -> LinearSystem:
        """The reduced model as the implicit integrator's linear system."""
        drive_x, drive_y = self.drive_x, self.drive_y
        index = np.flatnonzero((drive_x != 0.0) | (drive_y != 0.0))
        contact_dofs = np.arange(self.boundary.size).reshape(-1, 3)
        boundary, size = self.boundary, self.size

        def rigid(motion):
            # A rigid motion is static (K annihilates it): its interior is Psi times its
            # boundary, so q = (its boundary values, no modal amplitudes) reproduces it.
            q = np.zeros(size)
            q[:boundary.size] = motion[boundary]
            return q

        return LinearSystem(self.mass, self.stiffness, contact_dofs, index,
                            drive_x[index], drive_y[index], lambda q: self.basis @ q, rigid)


def _drive_loads(model) -> tuple:
    """d_x, d_y (dofs,): the drive's attachment weights on its nodes' X and on their Y."""
    dx, dy = np.zeros(model.dofs), np.zeros(model.dofs)
    dx[3 * model.attach_nodes] = model.attach_weights
    dy[3 * model.attach_nodes + 1] = model.attach_weights
    return dx, dy


def _linearized_contact(model, k_t) -> np.ndarray:
    """L on the boundary DOFs: k_t w_i in X, Y and k_pen w_i in Z on the candidates in
    the preload's patch (model.in_contact0), nothing on the others: they are open at the
    state the contact is linearized about. (Springs on the open candidates too would
    clamp the whole face, where the fixed-interface modes are exact, and hide the
    truncation: on the coarse ball with every candidate kept, 1e-4 against the 0.47% its
    answer is off.)"""
    springs = np.empty((model.contact_nodes.size, 3))
    springs[:, 0] = springs[:, 1] = k_t * model.area_share
    springs[:, 2] = model.penalty_share
    springs[~np.asarray(model.in_contact0, dtype=bool)] = 0.0
    return springs.ravel()


def compared_harmonics(scene) -> range:
    """The harmonics h f at which compliance_error compares: the first HARMONICS, and up
    to (v_a + v_d) / (2 pi s_c), at most MAX_HARMONICS.

    The friction force turns over a slip of a few sliding lengths s_c, so its
    spectrum reaches about the frequency at which the fastest sliding covers
    s_c a radian: 8 kHz on the Fig 7 scene (the first 3 harmonics of 4 kHz
    cover it), 26 kHz at k_v = 20, ten times more at k_t x 100. A stiff contact
    also lifts the block's rocking modes on it above 3 f: on the Fig 7 scene at
    k_t x 100 the default cutoff errs by 0.1% at 3 f but 5.2% at 5-6 f, and
    that reduced run's F_dv was 10% below the implicit one (a cutoff of 24 f:
    0.2%, 0.4%). Up to 8 f the paper's scenes' estimates stay within 1%:
    0.8% (Fig 7, at 3 f) and 0.63% (k_v = 20, at 6 f).
    """
    # (no friction: an infinite sliding length, reach 0, the first HARMONICS)
    reach = (scene.v_a + scene.drive.v_d) / (2.0 * math.pi * sliding_length(scene))
    last = min(MAX_HARMONICS, max(HARMONICS, math.ceil(reach / scene.vibration.f)))
    return range(1, last + 1)


def compliance_error(model, reduction: Reduction, scene) -> dict:
    """The measured reduction error (see the module docstring): per harmonic, and the max."""
    k_t = scene.law_bounds.stiffness
    static = np.abs(_reduced_compliance(model, reduction, k_t, 0.0))  # exact in statics
    omegas = {h: 2.0 * math.pi * h * scene.vibration.f for h in compared_harmonics(scene)}
    full = _full_compliances(model, reduction, k_t, list(omegas.values()))
    errors = {}
    for h, omega in omegas.items():
        difference = _reduced_compliance(model, reduction, k_t, omega) - full[omega]
        errors[h] = float(np.max(np.abs(difference) / static))
    return {"per_harmonic": errors, "max": max(errors.values())}


def _compliance_loads(model, boundary) -> np.ndarray:
    """The three loads the compliances answer: uniform traction on the preload's patch in
    X, in Y (w_i on the patch's candidates, summing to 1), the drive's."""
    loads = np.zeros((model.dofs, 3))
    traction = np.where(np.asarray(model.in_contact0, dtype=bool), model.area_share, 0.0)
    loads[boundary[0::3], 0] = traction
    loads[boundary[1::3], 1] = traction
    loads[3 * model.attach_nodes, 2] = model.attach_weights
    return loads


def _full_compliances(model, reduction: Reduction, k_t: float, omegas: list) -> dict:
    """The full model's compliances at each of ``omegas`` on the linearized contact (k_t),
    by omega: kept in this process and in the model cache; those not kept are solved
    together in one Krylov space (FullCompliance), built when first needed."""
    solver = []

    def solved(omega):
        if not solver:
            solver.append(FullCompliance(model, reduction.boundary, k_t, omegas))
        return {"c": solver[0].at(omega)}

    out = {}
    for omega in omegas:
        key = (reduction.model_key, k_t, omega)
        if key not in _full_compliance:
            parts = {"model": key[0], "k_t": float(k_t), "omega": float(omega),
                     "loss_factor": LOSS_FACTOR, "compliance_loads": COMPLIANCE_LOADS,
                     "solver": f"krylov {KRYLOV_TOLERANCE:g}", "numpy": np.__version__,
                     "scipy": scipy.__version__}
            _full_compliance[key] = model_cache.cached(
                "compliance", parts, lambda omega=omega: solved(omega))["c"]
        out[omega] = _full_compliance[key]
    return out


class FullCompliance:
    """The full model's compliances c_j(w) = p_j^T A(w)^-1 p_j on the linearized contact,

        A(w) = (1 + i eta)(K + L) - w^2 M,

    for the three loads p_j (_compliance_loads) at any w, from one real factorization.

    With the shift P = K + L + s M (s = w_1^2, the lowest asked frequency's: P is
    symmetric positive definite on any body, held or not),

        A(w) = (1 + i eta) P - sigma M,   sigma = (1 + i eta) s + w^2,

    so A(w)^-1 p lies, for every w, in the block Krylov space of P^-1 M started from
    P^-1 p, whose first vectors are the body's lowest modes on the contact springs (the
    space inverse iteration explores: Grimme, "Krylov projection methods for model
    reduction", PhD thesis, Illinois 1997, ch. 3). Its basis V, P-orthonormal
    (V^T P V = I), grows a block of three at a time (two passes of Gram-Schmidt in the
    P inner product; a direction the others already span, below DEFLATION of its norm,
    is dropped), and the Galerkin projection gives

        c(w) = diag(g^T [(1 + i eta) I - sigma H]^-1 g),   H = V^T M V,   g = V^T p,

    which is complex symmetric like A(w), so its error is second order in the solution's
    (a variational quantity). The space grows until no compliance at the asked
    frequencies ``omegas`` moves by more than KRYLOV_TOLERANCE of itself over a block,
    or until it is invariant (the projection then exact), and they are read off it
    (``at``). Where it has not settled within KRYLOV_BLOCKS blocks (not seen: 14 to 18
    vectors on the blocks and balls, docs/performance.md), the complex LU of A(w)
    answers instead (direct_compliance).
    """

    def __init__(self, model, boundary, k_t: float, omegas):
        self.model, self.boundary, self.k_t = model, boundary, k_t
        springs = _full_contact_springs(model, boundary, k_t)
        mass = model.disc.mass
        self.shift = min(omegas) ** 2
        shifted = (model.stiffness + sp.diags(springs + self.shift * mass)).tocsc()
        factor = fastest_spd_factor(shifted, model.elimination_order)
        self.loads = _compliance_loads(model, boundary)
        self.settled = False
        blocks, products = [], []
        self.H, self.g = np.zeros((0, 0)), np.zeros((0, 3))
        start = factor.solve(self.loads)
        previous = None
        for _ in range(KRYLOV_BLOCKS):
            block = self._orthonormal(start, blocks, products, shifted)
            if block.shape[1] == 0:   # the space is invariant: the projection is exact
                self.settled = bool(blocks)
                break
            blocks.append(block)
            products.append(shifted @ block)
            weighted = mass[:, None] * block
            cross = np.hstack(blocks).T @ weighted              # H's new columns
            old, new = cross[:-block.shape[1]], cross[-block.shape[1]:]
            self.H = np.block([[self.H, old], [old.T, 0.5 * (new + new.T)]])
            self.g = np.vstack([self.g, block.T @ self.loads])
            now = np.array([self._projected(omega) for omega in omegas])
            if previous is not None and np.all(
                    np.abs(now - previous) <= KRYLOV_TOLERANCE * np.abs(now)):
                self.settled = True
                break
            previous = now
            start = factor.solve(weighted)
        self.size = self.g.shape[0]

    @staticmethod
    def _orthonormal(W, blocks, products, P) -> np.ndarray:
        """W's columns P-orthonormalized against ``blocks`` (their P-products ``products``)
        and among themselves, the directions already spanned dropped."""
        scale = np.sqrt(np.maximum(np.einsum("ij,ij->j", W, P @ W), 0.0))
        for _ in range(2):
            for block, product in zip(blocks, products):
                W = W - block @ (product.T @ W)
        gram = W.T @ (P @ W)
        values, vectors = la.eigh(0.5 * (gram + gram.T))
        keep = values > (DEFLATION * scale.max()) ** 2
        return W @ (vectors[:, keep] / np.sqrt(values[keep]))

    def _projected(self, omega: float) -> np.ndarray:
        sigma = (1.0 + 1j * LOSS_FACTOR) * self.shift + omega ** 2
        matrix = (1.0 + 1j * LOSS_FACTOR) * np.eye(self.g.shape[0]) - sigma * self.H
        return np.einsum("ij,ij->j", self.g, la.solve(matrix, self.g.astype(complex)))

    def at(self, omega: float) -> np.ndarray:
        """(3,) the compliances at omega."""
        if not self.settled:
            return direct_compliance(self.model, self.boundary, self.k_t, omega)
        return self._projected(omega)


def _full_contact_springs(model, boundary, k_t: float) -> np.ndarray:
    """(dofs,) _linearized_contact's springs on the full model's boundary DOFs, 0 elsewhere."""
    springs = np.zeros(model.dofs)
    springs[boundary] = _linearized_contact(model, k_t)
    return springs


def direct_compliance(model, boundary, k_t: float, omega: float) -> np.ndarray:
    """(3,) the full model's compliances at omega by the complex LU of A(w) (FullCompliance):
    the reference the Krylov space is checked against (tests), and its fallback."""
    springs = _full_contact_springs(model, boundary, k_t)
    K_full = (model.stiffness + sp.diags(springs)).tocsc()
    loads = _compliance_loads(model, boundary)
    matrix = K_full * (1.0 + 1j * LOSS_FACTOR) - omega ** 2 * sp.diags(model.disc.mass)
    lu = symmetric_lu(matrix, model.elimination_order)
    return np.einsum("ij,ij->j", loads, lu.solve(loads.astype(complex)))


def _reduced_compliance(model, reduction: Reduction, k_t: float, omega: float) -> np.ndarray:
    """The reduced model's compliances at omega on the linearized contact (k_t), kept with
    the reduction."""
    kept = reduction.compliances
    if (k_t, omega) not in kept:
        b, reduced_loads = reduction.boundary, reduction.compliance_loads
        reduced_springs = np.zeros(reduction.size)
        reduced_springs[:b.size] = _linearized_contact(model, k_t)
        K_red = reduction.stiffness + np.diag(reduced_springs)
        matrix = K_red * (1.0 + 1j * LOSS_FACTOR) - omega ** 2 * reduction.mass
        kept[k_t, omega] = np.einsum("ij,ij->j", reduced_loads,
                                     la.solve(matrix, reduced_loads.astype(complex)))
    return kept[k_t, omega]


class ReducedRun(ImplicitRun):
    """The implicit integrator on the Craig-Bampton reduction of the model."""

    def __init__(self, scene, model):
        cutoff = scene.fem.cutoff * scene.vibration.f
        self.interface = Interface.of(model, scene.fem.interface_reach)
        inner = self.interface.model(model)       # its contact arrays the interface's
        start = time.perf_counter()
        reduction = reduced(inner, cutoff, self.interface.watched_dofs(model),
                            self.interface.digest())
        self.reduction_time = time.perf_counter() - start
        self.reduction = reduction
        super().__init__(scene, inner, reduction.system(), name="reduced")
        self.watch = Watch(reduction.watch_rows, self.interface.watch_rest(model))
        start = time.perf_counter()
        self.error = compliance_error(inner, reduction, scene)
        self.error_time = time.perf_counter() - start
        if not np.isfinite(self.error["max"]):
            raise ReductionFailed("the reduced model's compliance could not be compared "
                                           "with the full model's")

    @property
    def info(self) -> dict:
        r = self.reduction
        return {**super().info,
                "reduced_size": int(r.mass.shape[0]),
                "interface_nodes": int(self.interface.kept.size),
                "kept_modes": int(r.frequencies.size),
                "kept_modes_hz": [float(f) for f in r.frequencies],
                "cutoff_hz": self.scene.fem.cutoff * self.scene.vibration.f,
                "reduction_time_s": self.reduction_time,
                "reduction_error_per_harmonic": {str(h): e for h, e in self.error["per_harmonic"].items()},
                "reduction_error_estimate": self.error["max"],
                "reduction_error_time_s": self.error_time}

    def full_state(self, state):
        return self.interface.full_state(state, self.scene.friction.law)

    def full_normals(self, node_normals):
        return self.interface.full_normals(node_normals)
