"""The FE model of a scene as plain arrays: body, loads, contact, drive, preload, step.

``build_model(scene, comm)`` does everything that happens once per run:

1. the elastic body (assembly.py) on its placed mesh, a meshes.BodyMesh (body_of:
   the paper's block, meshes.block_body, unless meshes offers body_mesh): K, lumped
   mass M, the facet groups' areas, with rho = body.density or body.mass / the
   mesh's volume (0.5 kg -> 7850 kg/m^3 and 2 kg -> 31400 kg/m^3 on the paper's
   block), read from the model cache after the first run on the same mesh
   (model_cache.py);
2. the normal load (loads.py): gravity + a uniform pressure on the group "load" (the
   block's top), total F_N; without that group gravity alone, which must be F_N;
3. the contact (contact.py): the nodes of the group "contact" (the candidates),
   their tributary areas a_i, shares w_i = a_i / A and initial gaps g0_i (their
   heights at rest), their penalty springs k_pen,i = k_c a_i (penalty_shares: k_c
   per unit area), and the normal force each node's law sees under
   fem.normal_force (contact.nominal_normal);
4. the drive's attachment nodes and weights (drive.py), a front-face drive that
   would tip the body refused (check_tipping); with drive.holder = "translating",
   the attachment's ties to one rigid translation joined to K (holder.py);
5. the static preload u0 and its contact patch (preload.py), read from the model
   cache after the first run on the same inputs;
6. the highest frequency, the damping and the stable step (stability.py).

Damping (fem.damping = beta, seconds; C = beta (K + K_pen), stability.py).
What the scene needs from the block is its quasi-static compliance: the
excitation (3-4 kHz and the harmonics the Dahl law makes) lies far below the
block's elastic modes, and the 2 kHz mode of the block on its tangential
contact stiffness is a rigid-body motion that K does not touch (nor the
lumped model's). What it does not need, and what rings when the friction
forces jump every half cycle, are the mesh's high-frequency modes: Abaqus/
Explicit damps them by default with bulk viscosity, whose linear term gives
the highest element mode a damping ratio of about 0.06. The default here does
the same with Rayleigh damping: beta = 2 XI_MAX / w_max, XI_MAX = 0.06, which
costs 6% of the stable step (the 0.5 kg block on the "coarse" mesh: 1.046 us,
just above the paper's 1e-6 s) and gives the quasi-static deformation at 4 kHz
a damping ratio beta w / 2 ~ 1e-3. Starting from the static preload, that is
enough: the summed normal force stays within 0.1-0.35% of F_N over the
averaging window (simulate.py judges it: outputs/normal_swing.py), and 7x more damping changed F_dv by 0.02%
(transverse, k_v = 20). Stiffness-proportional damping cannot reach the
block's rigid contact modes (rocking and bounce on the penalty springs, 10-25
kHz for 0.5 kg) without eating the stable step: they get xi ~ 0.003.
"""

import dataclasses
import math
from contextlib import contextmanager
from dataclasses import dataclass, fields

import numpy as np

from ... import meshes
from ...core.errors import DriveTipsBlock, StepTooLong
from . import stability
from . import model_cache
from .assembly import Discretization
from .contact import curvature_radius, default_contact_stiffness, nominal_normal
from .drive import ATTACH_GROUPS, attachment, drive_stiffness_action
from .holder import held
from .loads import normal_load, load_pressure
from .linalg import dof_points, nested_dissection, on_grid
from .preload import static_preload


@dataclass
class FEModel:
    disc: Discretization
    density: float           # kg/m^3
    block_mass: float        # kg, rho V (the body's, whatever its shape)
    pressure: float          # Pa, on the group "load" (0 without one)
    load: np.ndarray         # (dofs,) gravity + the load group's pressure
    inverse_mass: np.ndarray  # (dofs,) 1 / m_i
    contact_nodes: np.ndarray  # (n,) node indices of the group "contact" (the candidates)
    initial_gap: np.ndarray    # (n,) each contact node's height above the base's plane at
                               # rest, before the preload, m (its z: meshes/body.py places
                               # the lowest contact point on z = 0; the block's face is all 0)
    contact_area: np.ndarray   # (n,) tributary areas a_i, m^2
    area_share: np.ndarray     # (n,) w_i = a_i / A_0, A_0 the preload patch's area: each node's
                               # share of the law's k_t and (under "nominal") of F_N; sum 1
                               # over the patch (patch_share)
    penalty: float             # N/m, sum of penalty_share (the whole candidate surface's)
    penalty_share: np.ndarray  # (n,) k_pen,i = k_c a_i (penalty_shares)
    nominal_normal: np.ndarray  # (n,) F_N w_i under fem.normal_force "nominal", else 0
                                # (contact.nominal_normal)
    attach_nodes: np.ndarray
    attach_weights: np.ndarray
    u0: np.ndarray             # (dofs,) static preload displacement
    normal0: np.ndarray        # (n,) static normal forces, sum F_N
    in_contact0: np.ndarray    # (n,) bool: the preload's contact patch (its active set)
    length: float              # m, the body's extent in X (the sliding direction), to
                               # LENGTH_DIGITS significant digits
    friction_coefficient: float  # the law's sliding coefficient mu (friction_law Bounds): the
                                 # frames' stick / slip (outputs/contact_patch.py)
    elimination_order: np.ndarray | None  # (dofs,) for the sparse LUs: nested dissection
                                          # on a grid (linalg), else None: minimum degree
    omega_max: float           # rad/s
    beta: float                # s, Rayleigh stiffness-proportional damping
    dt_stable: float           # s

    @property
    def stiffness(self):
        return self.disc.stiffness

    @property
    def dofs(self) -> int:
        return self.disc.dofs


def body_of(scene, level: str | None = None) -> meshes.BodyMesh:
    """The scene's body as a placed mesh (meshes.BodyMesh) at refinement ``level``
    (default fem.mesh): the one place that says which body a scene is (meshes.body_mesh;
    a user's mesh is named by its absolute path once the scene is read)."""
    level = scene.fem.mesh if level is None else level
    # F_N sizes a ball's Hertz patch at the levels that resolve it
    return meshes.body_mesh(scene.body, level, normal_load=scene.contact.F_N)


def block_size(scene):
    """body.size where the scene's body is the paper's block (body_of's default), else
    None: the block keeps the whole-face default penalty of the lumped model's bounce
    (core/bounce.py; penalty_shares)."""
    if scene.body.is_block:
        return scene.body.size
    return None


def density(scene, body: meshes.BodyMesh) -> float:
    """body.density, else body.mass / the mesh's volume (the block's L_x L_y L_z)."""
    if scene.body.density is not None:
        return scene.body.density
    return scene.body.mass / body.volume


def check_tipping(scene, disc: Discretization, contact_nodes, contact_area) -> None:
    """Refuse a front-face drive strong enough to tip the body over its front edge.

    About the front edge of the preload's contact patch (its largest x), the drive
    (up to the sliding force max(mu, mu_s) F_N, acting at the front group's mean height
    h) turns the body against the normal load F_N acting at the patch's centre x_c
    (area-weighted; ``contact_nodes`` and ``contact_area`` are the patch's): it
    tips, and the back of the contact lifts off the base, once max(mu, mu_s) h >=
    x_edge - x_c. The block: h = L_z / 2, x_edge - x_c = L_x / 2, so once
    max(mu, mu_s) L_z >= L_x. The other attachments act at the contact (no moment) or
    where the mesh's own "drive" group is, which the user placed; a holder (drive.holder)
    does not let the body turn.
    """
    if scene.drive.attach != "front-face" or scene.drive.holder != "none":
        return
    front = disc.face_area[ATTACH_GROUPS["front-face"]]
    front_nodes = np.flatnonzero(front > 0.0)
    height = float(np.average(disc.coordinates[front_nodes, 2], weights=front[front_nodes]))
    x = disc.coordinates[contact_nodes, 0]
    lever = float(x.max() - np.average(x, weights=contact_area))
    mu_max = scene.mu_max
    if mu_max * height >= lever:
        raise DriveTipsBlock(f"a front-face drive at mid-height would tip the body "
                             f"(friction coefficient {mu_max:g} >= {lever / height:.3g}, the "
                             "contact's half-length over the drive's height) and leave its "
                             "back off the base; use \"contact-plane\"")


# Within kept_between_runs(): the last model built, under what it was built from
# (_built_from); else None.
_kept: dict | None = None


@contextmanager
def kept_between_runs():
    """Within the block, build_model hands back the model it built last when a scene
    asks for the same one (_built_from: the block, its mesh, contact, drive and the
    law's stiffnesses), instead of reading the block from the model cache and solving
    the preload and the highest frequency again: the points of a sweep that vary the
    vibration share one model. Its arrays are made read-only, as every run that
    shares it must leave it as it was."""
    global _kept
    outer, _kept = _kept, {}
    try:
        yield
    finally:
        _kept = outer


def kept_for_this_process() -> None:
    """What kept_between_runs() does, for the rest of this process: a sweep's pool
    worker, which is handed the sweep's points one at a time."""
    global _kept
    if _kept is None:
        _kept = {}


def _built_from(scene) -> str:
    """What build_model reads of a scene, as a key: equal keys build equal models."""
    bounds = scene.law_bounds
    return repr((scene.body, scene.fem.mesh, scene.fem.penalty, scene.fem.contact_stiffness,
                 scene.fem.damping, scene.fem.normal_force, scene.drive.attach, scene.drive.holder,
                 scene.drive.prescribed, scene.drive.k_d, scene.contact.F_N, scene.mu_max,
                 bounds.stiffness, bounds.max_stiffness))


def _read_only(model: FEModel) -> FEModel:
    for name in [f.name for f in fields(model)]:
        value = getattr(model, name)
        if isinstance(value, np.ndarray):
            value.setflags(write=False)
    return model


def build_model(scene, comm) -> FEModel:
    """Everything a run needs before its first step; refuses a scene it cannot run
    (core.errors.Refusal). Within kept_between_runs(), the model built last for the
    same inputs, if any."""
    if _kept is None:
        return _built(scene, comm)
    key = _built_from(scene)
    if key not in _kept:
        _kept.clear()
        _kept[key] = _read_only(_built(scene, comm))
    return _kept[key]


# The facet groups the model reads (meshes/body.py): the contact candidates, the load's
# surface and the drive's attachments
MODEL_GROUPS = ("contact", "load", "front", "drive")


def cached_levels(scene) -> list[str]:
    """The refinement levels other than fem.mesh whose body for ``scene`` is cached
    (model_cache.holds_source, asked without meshing): the meshes a mesh error can be
    had from cheaply."""
    return [level for level in meshes.LEVELS
            if level != scene.fem.mesh and model_cache.holds_source(body_source(scene, level))]


def body_source(scene, level: str) -> dict:
    """What the model's arrays of ``scene``'s body at ``level`` are made from, short of
    the mesh itself (model_cache's source entries): the body section (its shape or mesh,
    size, material, density, mass), the level and, on a body other than the block, F_N
    (which sizes a ball's mesh at its patch: body_of)."""
    source = {"body": repr(scene.body), "level": level}
    if not scene.body.is_block:
        source["F_N"] = scene.contact.F_N
    return source


def patch_share(contact_area: np.ndarray, in_contact: np.ndarray) -> np.ndarray:
    """(n,) w_i = a_i / A_0: each candidate's tributary area over the area A_0 of the
    preload's contact patch (``in_contact``).

    The law's k_t (N/m) is the stiffness of the whole contact (docs/model.md section 1),
    and the contact is the patch the body rests on, not every facet that might touch:
    node i takes k_t w_i, as it takes F_N w_i under fem.normal_force = "nominal", so the
    patch's nodes hold k_t and F_N in all, as the lumped body's one node does. A
    candidate outside the patch that closes later takes the same stiffness per area.
    On the block the patch is the whole face, and w_i the face's shares to the bit.
    """
    return contact_area / contact_area[in_contact].sum()


def penalty_shares(scene, contact_area: np.ndarray, area_share: np.ndarray,
                   height: float, radius: float) -> tuple:
    """(k_pen, (n,) k_pen,i): each candidate's penalty stiffness k_pen,i = k_c a_i, N/m,
    k_c the contact's stiffness per unit area (Pa/m), so that refining the mesh leaves
    it as it is, and k_pen that of the whole candidate surface (N/m).

    fem.contact_stiffness gives k_c; fem.penalty (N/m) the whole candidate surface's,
    k_pen w_i; neither: the default k_c (contact.default_contact_stiffness: PENALTY_FACTOR
    E / H, H the body's ``height``, raised on a curved contact of radius ``radius`` to
    keep the penalty's compliance 0.6% of Hertz's), which on the paper's block is
    computed as its whole face's
    PENALTY_FACTOR E L_x L_y / L_z times w_i: the same penalty as the lumped model's
    bounce (core/bounce.py), and the floats the block always had.
    """
    if scene.fem.penalty is not None:
        return scene.fem.penalty, scene.fem.penalty * area_share
    if scene.fem.contact_stiffness is None and block_size(scene) is not None:
        whole = scene.block_penalty
        return whole, whole * area_share
    k_c = scene.fem.contact_stiffness
    if k_c is None:
        k_c = default_contact_stiffness(scene.body.E, scene.body.nu, height,
                                        scene.contact.F_N, radius)
    shares = k_c * contact_area
    return float(shares.sum()), shares


def _built(scene, comm) -> FEModel:
    body = scene.body
    body_mesh = body_of(scene)
    rho = density(scene, body_mesh)
    disc = model_cache.body(comm, body_mesh, body.E, body.nu, rho, MODEL_GROUPS,
                            body_source(scene, scene.fem.mesh))
    if "contact" not in disc.face_area:
        raise ValueError(f"{body_mesh.description}: the mesh has no \"contact\" facet group")

    area = disc.face_area["contact"]
    contact_nodes = np.flatnonzero(area > 0.0).astype(np.int64)
    contact_area = area[contact_nodes]
    candidate_share = contact_area / contact_area.sum()   # of the whole candidate surface

    block_mass = rho * disc.volume
    load_area = disc.face_area.get("load")
    pressure = load_pressure(scene, block_mass, load_area, body_mesh.description)
    load = normal_load(disc.mass, load_area, body.gravity, pressure)

    extent = np.ptp(disc.coordinates, axis=0)
    gap0 = initial_gap(disc.coordinates, contact_nodes)
    radius = curvature_radius(disc.coordinates[contact_nodes, :2], gap0)
    penalty, penalty_share = penalty_shares(scene, contact_area, candidate_share, float(extent[2]),
                                            radius)

    attach_nodes, attach_weights = attachment(scene, disc.face_area, body_mesh.description)
    if scene.drive.holder == "translating":
        disc = dataclasses.replace(disc, stiffness=held(disc.stiffness, attach_nodes,
                                                         attach_weights))
    elimination_order = (nested_dissection(dof_points(disc.coordinates))
                         if on_grid(disc.coordinates) else None)

    u0, normal0, in_contact0 = model_cache.preload(
        static_preload, disc.stiffness, load, contact_nodes, penalty_share, candidate_share,
        scene.law_bounds.stiffness, scene.contact.F_N, elimination_order, gap0)
    check_tipping(scene, disc, contact_nodes[in_contact0], contact_area[in_contact0])
    area_share = patch_share(contact_area, in_contact0)

    omega_max = stability.max_frequency(
        disc.stiffness, disc.mass, contact_nodes, penalty_share, scene.law_bounds.max_stiffness * area_share,
        drive_stiffness_action(0.0 if scene.drive.prescribed else scene.drive.k_d,
                               attach_nodes, attach_weights, disc.dofs))
    beta = scene.fem.damping if scene.fem.damping > 0.0 else stability.default_damping(omega_max)
    dt_stable = stability.critical_step(omega_max, beta)

    return FEModel(disc=disc, density=rho, block_mass=block_mass, pressure=pressure, load=load,
                   inverse_mass=1.0 / disc.mass, contact_nodes=contact_nodes,
                   initial_gap=gap0, contact_area=contact_area, area_share=area_share,
                   penalty=penalty, penalty_share=penalty_share,
                   nominal_normal=nominal_normal(scene.fem.normal_force, scene.contact.F_N,
                                                 area_share),
                   attach_nodes=attach_nodes,
                   attach_weights=attach_weights, u0=u0, normal0=normal0,
                   in_contact0=in_contact0, length=float(f"{extent[0]:.{LENGTH_DIGITS}g}"),
                   friction_coefficient=scene.law_bounds.friction_coefficient,
                   elimination_order=elimination_order,
                   omega_max=omega_max, beta=beta, dt_stable=dt_stable)


# FEModel.length is a scale (the periodic solver's difference step of a turn,
# integrators/cycle_map.py): rounded, so that gmsh's rounding of the coordinates (the
# block's 0.03 m comes back 0.030000000000000002) does not move it.
LENGTH_DIGITS = 12

# Heights within this fraction of the body's extent are the base's plane itself: gmsh
# leaves ~1e-18 m of rounding on the block's flat face (z = 0 by construction).
PLANE_TOLERANCE = 1e-12


def initial_gap(coordinates: np.ndarray, contact_nodes: np.ndarray) -> np.ndarray:
    """(n,) each contact node's height z above the base's plane, m, exactly 0 on it."""
    z = coordinates[contact_nodes, 2]
    extent = float(np.ptp(coordinates, axis=0).max())
    return np.where(np.abs(z) <= PLANE_TOLERANCE * extent, 0.0, z)


def check_step(scene, model: FEModel) -> None:
    """Refuse a time.dt above the explicit stable step, naming the ways out: a step below
    it, or an integrator without one (fem/integrators: implicit and reduced take any
    step that resolves the vibration)."""
    if scene.time.dt > model.dt_stable:
        raise StepTooLong(f"time step {scene.time.dt:g} s is above the explicit stable step "
                          f"{model.dt_stable:.4g} s of mesh {scene.fem.mesh!r} "
                          f"(highest frequency {model.omega_max / (2 * math.pi):.4g} Hz, "
                          f"damping {model.beta:.3g} s): use time.dt <= "
                          f"{model.dt_stable:.4g}, a coarser fem.mesh or less fem.damping, "
                          'or fem.integrator = "reduced" or "implicit", whose step '
                          "has no such bound")
