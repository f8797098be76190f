"""Explicit central-difference time integration: the Abaqus/Explicit analogue.

With the lumped (diagonal) mass M, one step from t_n to t_{n+1} = t_n + dt is

    f_n       = f_ext - K (u_n + beta v_n)                  elastic + Rayleigh damping C = beta K
              + sum_i [N_i e_z - F_i]_n                     contact: normal (penalty spring and its
                                                            share beta k_pen w_i of the damping)
                                                            and friction (model/contact.py)
              + sum_a w_a F_d,n e_x                         drive, F_d,n = k_d (v_d t_n - x_A,n) (eq 17)
    v_{n+1/2} = v_{n-1/2} + dt M^-1 f_n
    u_{n+1}   = u_n + dt v_{n+1/2}

(the damping uses the lagging velocity v_{n-1/2}, as Abaqus does, which keeps
the step explicit; stable while dt <= dt_crit, model/stability.py). Then the base
moves to its position at t_{n+1} (eqs 23-25), every contact node's normal force
and asperity are updated from its displacement increment (model/contact.py, the
VFRIC analogue), and F_d = k_d (v_d t_{n+1} - x_A,n+1) is recorded. A node
that slides more than contact.SUBSTEP_ONSET sliding lengths in the step (a
stiff contact) runs its friction law on sub-steps of the step's increments.

This is the lumped stepper's order of operations (analytic/coupled.py, which
writes the same scheme as semi-implicit Euler: v += dt a, x += dt v): drive
force from the start of the step, friction force from the previous update.

The whole step (sparse product with K in 3x3 node blocks, contact, friction,
drive, base, recording, checks, early steady state) is one numba loop; Python
only sees the run again every ``fem.output_every`` steps, to write a ParaView
frame. With fem.energy the loop keeps central differences' own energy balance, in its
shadow form (outputs/energy.py explicit_energy_step).

A base moving along Z (vibration.normal_amplitude > 0): each contact node's gap is
measured against z_b(t_{n+1}) and its dashpot against the base's speed
(model/contact.py), and the body starts on its forced response (normal_start.py).

A base motion given per step (vibration.harmonics, vibration.motion: core/base_table.py)
adds its table's x_b, y_b, z_b and dz_b/dt to the sine's at each step, as the lumped
model does, and its z_b to the start; the FE periodic solver's cycles read it the same
way (cycle_map.py).
"""

import math

import numpy as np
from numba import njit

from ...core.base_motion import (base_displacement, normal_displacement, normal_phase,
                                 vibration_axis)
from ...core.base_table import base_table, table_moves_along_z, table_row, table_velocity_z
from ...friction_law import law_kernel
from ...friction_law.contract import FASTMATH
from ...core.errors import NoEnergyBalance
from ...core.law_limits import SLIP_PER_STEP, slip_per_step, sliding_length
from . import step_cost
from ..outputs import trouble
from ..model.contact import SUBSTEP_ONSET, contact_forces
from ..model.drive import attachment_position, prescribed_position
from ..model.linalg import apply, bsr
from ..model.fe_model import check_step
from ..outputs.energy import (SUMS, energy_before_step, explicit_energy_end,
                              explicit_energy_step)
from ..outputs.energy import record as record_energy
from ..outputs.recording import (COS, LOOP_SCALARS, SIN, XB, YB, finish_step, keep_step,
                                 record_normal)
from .normal_start import first_step_on, normal_force_limit, start_gain, start_motion
from .time_loop import Started, TimeLoop

# scalars[]: the explicit loop's own carried state, after recording's: the base's X and
# Y a step before the last (the energy's mid-step increments), its Z at the last step
# and the one before
OWN_SCALARS = 4
XB_BEFORE, YB_BEFORE, ZB, ZB_BEFORE = range(LOOP_SCALARS, LOOP_SCALARS + OWN_SCALARS)


# The DOF-vector loops are compiled calls, not inlined into the time loop: numba's
# inlining (inline="always") kept LLVM from vectorizing them there, 4x slower.
@njit(cache=True, fastmath=FASTMATH)
def damped_displacement(u, v, beta, out):
    """out = u + beta v: what K takes to give the elastic and Rayleigh damping forces."""
    for k in range(u.shape[0]):
        out[k] = u[k] + beta * v[k]


@njit(cache=True, fastmath=FASTMATH)
def external_less(load, force):
    """force = load - force: the external loads less K (u + beta v)."""
    for k in range(force.shape[0]):
        force[k] = load[k] - force[k]


@njit(cache=True, fastmath=FASTMATH)
def central_difference(u, v, force, inverse_mass, dt):
    """v_{n+1/2} = v_{n-1/2} + dt M^-1 f_n;  u_{n+1} = u_n + dt v_{n+1/2}."""
    for k in range(u.shape[0]):
        v[k] += dt * inverse_mass[k] * force[k]
        u[k] += dt * v[k]


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def step_forces(u, v, beta, stiffness, load, contact_nodes, friction, normal, attach_nodes,
                attach_weights, f_d, work, force_sum):
    """f_n = f_ext - K (u + beta v) + sum_i [N_i e_z - F_i] + sum_a w_a F_d e_x: the
    elastic and Rayleigh damping forces, the contact's (normal force up, friction -F on
    the body, from the last update) and the drive's, into ``force_sum``."""
    damped_displacement(u, v, beta, work)
    apply(stiffness, work, force_sum)  # K in 3x3 node blocks (linalg.bsr)
    external_less(load, force_sum)
    for c in range(contact_nodes.shape[0]):
        d = 3 * contact_nodes[c]
        force_sum[d] -= friction[c, 0]
        force_sum[d + 1] -= friction[c, 1]
        force_sum[d + 2] += normal[c]
    for a in range(attach_nodes.shape[0]):
        force_sum[3 * attach_nodes[a]] += attach_weights[a] * f_d


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def held_attachment(u, v, t, dt, v_d, reference, attach_nodes, attach_weights, inverse_mass,
                    compliance):
    """A prescribed drive's constraints x_A = v_d t (drive.prescribed_position), y_A = 0 at
    the step's end: the forces on the attachment nodes (by their weights w_a) that put it
    there, F_d = (x_A(t) - x_A*) / (dt^2 sum_a w_a^2 / m_a) from the step without them
    (x_A*), and in Y the same towards 0. Moves u and v by them; returns F_d."""
    x_a, y_a = attachment_position(u, reference, attach_nodes, attach_weights)
    f_d = (prescribed_position(t, v_d) - x_a) / (dt * dt * compliance)
    f_hold = -y_a / (dt * dt * compliance)   # held in Y (lumped mass: the same in X and Y)
    for a in range(attach_nodes.shape[0]):
        d = 3 * attach_nodes[a]
        kick = dt * inverse_mass[d] * attach_weights[a]
        v[d] += kick * f_d
        u[d] += dt * kick * f_d
        v[d + 1] += kick * f_hold
        u[d + 1] += dt * kick * f_hold
    return f_d


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def contact_motion(u, v, contact_nodes, disp_new, vel_z):
    """The contact nodes' displacements (disp_new) and Z velocities at the step's end."""
    for c in range(contact_nodes.shape[0]):
        d = 3 * contact_nodes[c]
        disp_new[c, 0] = u[d]
        disp_new[c, 1] = u[d + 1]
        disp_new[c, 2] = u[d + 2]
        vel_z[c] = v[d + 2]


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def next_contact_start(disp, disp_new, friction):
    """The step's end displacements become the next step's start; returns sum |F_i|."""
    magnitude = 0.0
    for c in range(disp.shape[0]):
        disp[c, 0] = disp_new[c, 0]
        disp[c, 1] = disp_new[c, 1]
        disp[c, 2] = disp_new[c, 2]
        magnitude += math.sqrt(friction[c, 0] ** 2 + friction[c, 1] ** 2)
    return magnitude


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def face_height(u, reference, contact_nodes, area_share):
    """The contact face's mean height from the preload, sum_i w_i (u_z,i - u0_z,i)."""
    z = 0.0
    for c in range(contact_nodes.shape[0]):
        d = 3 * contact_nodes[c] + 2
        z += area_share[c] * (u[d] - reference[d])
    return z


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def explicit_steps(first, last, dt,
                   stiffness, inverse_mass, load, beta,
                   contact_nodes, penalty_share, area_share, nominal, params, eta_y,
                   sliding_length, attach_nodes, attach_weights, k_d, v_d, prescribed,
                   amplitude, omega, t_on, cos_theta, sin_theta,
                   amplitude_n, sin_n, cos_n, initial_gap, on_step, start_gain, lift, face_z,
                   table, table_from, table_period, table_lifts, table_start_vz,
                   F_N, mu_max, normal_limit, use_energy, normal0, v_old, k_q, k_v, sums,
                   reference, u, v, work, force_sum, disp, disp_new, vel_z,
                   states, normal, friction, scalars, recorder, steady):
    """Advance steps ``first`` .. ``last`` (inclusive). Returns (failed step, code, stop step):
    (0, OK, 0) if all ran, (0, OK, i) if the run settled at step i (outputs/steady.py).

    ``stiffness`` is K in block sparse rows of 3x3 node blocks (linalg.bsr).
    A ``prescribed`` drive (drive.mode = "velocity") replaces the spring by the
    constraints x_A = v_d t, y_A = 0 (held_attachment).
    All state lives in the arrays (u, v, disp, states, normal,
    friction, scalars, recorder, steady) so that a run can be resumed chunk by chunk.
    Only contact.contact_forces calls the friction law; the rest is compiled once
    for every law.

    The base along Z (amplitude_n > 0): z_b, v_zb at t_{n+1} (base_motion.normal_displacement)
    set every node's gap (contact.py); at ``on_step`` every node first moves by the
    rigid forced response ``start_gain`` (start_motion) along ``lift``, measured on the
    contact nodes' Z (``face_z``). With
    ``use_energy`` the balance's sums (energy.py, the explicit shadow form) grow
    each step: v_old, k_q, k_v are its scratch vectors, ``normal0`` the preload's forces.
    ``table`` (from step ``table_from``, repeating every ``table_period`` steps, 0: its
    last row held; no rows: none) adds the base's motion given per step
    (core/base_table.py) to the sine's; ``table_lifts``: it moves along Z,
    ``table_start_vz`` its dz_b/dt half a step before ``on_step``.
    """
    row = recorder[0]
    xb, yb = scalars[XB], scalars[YB]
    zb, zb_before = scalars[ZB], scalars[ZB_BEFORE]
    sin_phase, cos_phase = scalars[SIN], scalars[COS]
    lifts_off = amplitude_n > 0.0 or table_lifts
    cos_step, sin_step = math.cos(omega * dt), math.sin(omega * dt)
    compliance = 0.0   # sum_a w_a^2 / m_a: the attachment's response to a prescribed drive's force
    for a in range(attach_nodes.shape[0]):
        compliance += attach_weights[a] ** 2 * inverse_mass[3 * attach_nodes[a]]
    stop = 0
    for i in range(first, last + 1):
        t = i * dt
        # Drive force at the start of the step (eq 17).
        x_a, y_a = attachment_position(u, reference, attach_nodes, attach_weights)
        f_d = 0.0 if prescribed else k_d * (v_d * (t - dt) - x_a)
        f_d_start = f_d
        step_forces(u, v, beta, stiffness, load, contact_nodes, friction, normal, attach_nodes,
                    attach_weights, f_d, work, force_sum)
        if use_energy:
            energy_before_step(u, reference, v, v_old, stiffness, k_q, k_v)
        central_difference(u, v, force_sum, inverse_mass, dt)
        if prescribed:
            f_d = held_attachment(u, v, t, dt, v_d, reference, attach_nodes, attach_weights,
                                  inverse_mass, compliance)
        if i == on_step and lifts_off:
            # the body onto its forced response (normal_start.py): u_{n+1} at t_{n+1},
            # v_{n+1/2} at the half step, before the contact sees the base
            k = table_row(table, table_from, table_period, i)
            start_motion(u, reference, v, lift, face_z, area_share, start_gain, t, dt, t_on,
                         amplitude_n, omega, sin_n, cos_n, 0.5,
                         table[k, 2] if k >= 0 else 0.0, table_start_vz)

        # Base at t_{n+1} (eqs 23-25; along Z, base_motion.normal_displacement).
        u_base, sin_phase, cos_phase = base_displacement(i, dt, omega, t_on, amplitude, sin_phase,
                                                         cos_phase, cos_step, sin_step)
        xb_new, yb_new = u_base * cos_theta, u_base * sin_theta
        zb_new = vzb_new = 0.0
        if lifts_off and t >= t_on:
            zb_new, vzb_new = normal_displacement(amplitude_n, omega, sin_n, cos_n, sin_phase,
                                                  cos_phase)
        k = table_row(table, table_from, table_period, i)
        if k >= 0:   # the motion given per step (core/base_table.py), added
            xb_new += table[k, 0]
            yb_new += table[k, 1]
            zb_new += table[k, 2]
            vzb_new += table[k, 5]

        # Contact nodes: normal force and the two-phase friction update (VFRIC analogue).
        contact_motion(u, v, contact_nodes, disp_new, vel_z)
        kinetic = shadow = 0.0
        if use_energy:   # the works of step n's forces (before contact_forces replaces them)
            kinetic, shadow = explicit_energy_step(
                u, reference, v, v_old, inverse_mass, k_q, k_v, beta, dt, contact_nodes,
                initial_gap, disp, penalty_share, normal0, normal, friction, zb, zb_new,
                0.5 * (zb_new - zb_before), 0.5 * (xb_new - scalars[XB_BEFORE]),
                0.5 * eta_y * (yb_new - scalars[YB_BEFORE]), f_d_start, v_d, params,
                area_share, states, sums)
        f_n, f_x, f_y = contact_forces(
            disp, disp_new, vel_z, xb_new - xb, yb_new - yb, eta_y, initial_gap, zb_new, vzb_new,
            penalty_share, area_share, nominal, beta, params, dt, sliding_length, states,
            normal, friction)
        magnitude = next_contact_start(disp, disp_new, friction)
        scalars[XB_BEFORE], scalars[YB_BEFORE] = xb, yb
        xb, yb = xb_new, yb_new
        zb_before, zb = zb, zb_new

        x_a, y_a = attachment_position(u, reference, attach_nodes, attach_weights)
        if not prescribed:
            f_d = k_d * (v_d * t - x_a)  # eq 17; prescribed: the constraint's force

        # Numerical trouble stops the run at once.
        code = finish_step(t, t_on, f_d, f_n, f_x, f_y, x_a, y_a, xb, yb, magnitude, F_N, mu_max,
                           normal_limit, lifts_off, scalars, row)
        if code != trouble.OK:
            return i, code, 0
        if use_energy:
            kinetic, elastic = explicit_energy_end(kinetic, shadow, f_d_start, f_d, k_d, params,
                                                   area_share, states, sums)
            record_energy(row, sums, kinetic, elastic)
        if lifts_off:
            record_normal(row, face_height(u, reference, contact_nodes, area_share), zb, f_n)
        if keep_step(i, f_d, recorder, steady):
            stop = i
            break

    scalars[XB], scalars[YB] = xb, yb
    scalars[ZB], scalars[ZB_BEFORE] = zb, zb_before
    scalars[SIN], scalars[COS] = sin_phase, cos_phase
    return 0, trouble.OK, stop


def explicit_substeps(scene) -> int:
    """The most friction-law updates a step takes (contact.contact_forces): 1 up to
    SUBSTEP_ONSET s_c of slip a step at the fastest sliding, v_a + v_d, else enough
    for sub-steps of SLIP_PER_STEP s_c."""
    slip = slip_per_step(scene)
    if slip <= SUBSTEP_ONSET:
        return 1
    return math.ceil(slip / SLIP_PER_STEP - 1e-9)


class ExplicitRun(TimeLoop):
    """Central differences: the Abaqus/Explicit analogue, prepared for a scene.

    Refuses (core.errors.Refusal) a step above the stable one, and fem.energy with a
    prescribed drive (its constraint's work is not in the balance yet).
    """

    name = "explicit"
    extra_scalars = OWN_SCALARS

    def __init__(self, scene, model):
        check_step(scene, model)
        if scene.fem.energy and scene.drive.prescribed:
            raise NoEnergyBalance("the explicit integrator keeps no energy balance for a "
                                  "prescribed drive (drive.mode = \"velocity\"); use "
                                  "fem.integrator = \"implicit\" or \"reduced\"")
        self.scene, self.model = scene, model
        self.substeps = explicit_substeps(scene)
        self.info = {"friction_substeps": self.substeps}

    @property
    def cost_per_step(self) -> float:
        """ns a step, roughly (step_cost.COST): the product with K, the vectors, the friction law."""
        cost = step_cost.COST
        return (cost["sparse"] * self.model.stiffness.nnz + cost["vector"] * 4 * self.model.dofs
                + cost["friction"] * self.model.contact_nodes.size * self.substeps)

    @property
    def hint(self) -> str:
        return (f"try a smaller time.dt (stable step {self.model.dt_stable:.4g} s) or "
                f"more fem.damping (now {self.model.beta:.3g} s)")

    def start(self, contact, scalars, recorder, steady) -> Started:
        scene, model = self.scene, self.model
        c, dt = scene.contact, scene.time.dt
        law = scene.friction
        cos_theta, sin_theta = vibration_axis(scene.vibration.theta_deg)
        dofs, contacts = model.dofs, model.contact_nodes.size

        u = model.u0.copy()
        v = np.zeros(dofs)
        work, force_sum = np.empty(dofs), np.empty(dofs)
        disp = u.reshape(-1, 3)[model.contact_nodes].copy()
        disp_new, vel_z = np.empty_like(disp), np.zeros(contacts)
        stiffness = bsr(model.stiffness)  # node-by-node 3x3 blocks
        sin_n, cos_n = normal_phase(scene.vibration.normal_phase_deg)
        lift = np.tile([0.0, 0.0, 1.0], dofs // 3)       # every node's Z: the rigid bounce
        face_z = 3 * model.contact_nodes + 2             # the contact nodes' Z
        energy_vectors = [np.zeros(dofs if scene.fem.energy else 0) for _ in range(3)]
        vib, on_step = scene.vibration, first_step_on(scene)
        motion = base_table(vib, scene.omega, dt, vib.t_on, on_step, scene.steps)
        # the table's dz_b/dt half a step before the first step on (start_motion's v)
        start_vz = table_velocity_z(vib, scene.omega, (on_step - 0.5) * dt - vib.t_on)
        table = (motion.rows, motion.first_step, motion.period, table_moves_along_z(vib),
                 start_vz)
        sums = np.zeros(SUMS)

        def arguments(first, last):
            return (
                first, last, dt,
                stiffness, model.inverse_mass, model.load, model.beta,
                model.contact_nodes, model.penalty_share, model.area_share,
                model.nominal_normal, law.params, c.eta_y, sliding_length(scene),
                model.attach_nodes, model.attach_weights, scene.drive.k_d, scene.drive.v_d,
                scene.drive.prescribed,
                scene.u0, scene.omega, scene.vibration.t_on, cos_theta, sin_theta,
                scene.vibration.normal_amplitude, sin_n, cos_n, model.initial_gap,
                first_step_on(scene), start_gain(scene, model), lift, face_z, *table,
                c.F_N, scene.mu_max, normal_force_limit(scene, model), scene.fem.energy,
                model.normal0, *energy_vectors, sums,
                model.u0, u, v, work, force_sum, disp, disp_new, vel_z,
                contact.state, contact.normal, contact.friction,
                scalars, recorder.arrays, steady.arrays)

        kernel = explicit_steps.prepared(law.law, arguments(1, 0), "the explicit FE loop",
                                         direct=True)

        def steps(first, last):
            return kernel(*arguments(first, last))

        def rigid(motion):
            # u and the contact nodes' last displacements move; v and vel_z (rewritten
            # every step) stay
            return {"u": motion.copy(), "v": np.zeros(dofs),
                    "disp": motion.reshape(-1, 3)[model.contact_nodes].copy()}

        return Started(steps, lambda: (u, v), {"u": u, "v": v, "disp": disp}, rigid)
