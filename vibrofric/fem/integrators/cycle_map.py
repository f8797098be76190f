"""One base cycle of an FE integrator's own compiled step, as a map of its whole state.

The state an integrator carries from step to step (time_loop.Started.carried:
implicit and reduced q, v, a and the contact iteration's last g; explicit u, v
and the contact nodes' last displacements), every contact node's friction-law
state, normal and friction force (time_loop.ContactState) and the carried
scalars (the implicit drive force) are packed into one vector z, each entry
divided by its natural size (``scales``). The map runs the integrator's compiled
step over one base cycle of n steps (steps i0 + 1 .. i0 + n, i0 a step at which
the base is at phase zero, eq 23) from z, and returns the packed state after it.

Frame. The steady state is periodic in the frame that moves with the drive: z is
the state less the drive's translation v_d t in X (the image of the rigid
translation in each carried array: Started.rigid), so Phi(z) = z on the orbit.

Gauge. Nothing restrains the block's rigid translation in Y nor its turn about
Z around the drive's attachment (the drive pulls on the attachment's mean X
only; the friction law sees increments only): shifted along those, an orbit is
still an orbit, the cycle map's Jacobian has a multiplier of exactly 1 there and
Newton's matrix is singular. They are taken out: after each cycle, z loses its
components along their images (an orthogonal projection in the scaled
variables), so that the map acts on the restrained state alone (with a prescribed
drive, which holds the attachment in Y too, only the turn). A holder
(drive.holder = "translating", fem/model/holder.py) restrains the turn: its ties
resist any turn of the held group, so the turn is no gauge there and stays in z.

A base motion given per step (core/base_table.py): its table repeats every base cycle
where the solver is asked to run it (harmonics; a periodic measured motion, whose
file spans 1/f), so each cycle reads the same rows; the cycle's start takes the
table's position at step i0 (time_loop.TimeLoop.table_row_at), and where the table
moves the base along Z the start of steady sliding puts the body on its forced
response to it too.
"""

import math

import numpy as np

from ...core.base_motion import normal_phase, vibration_axis
from ...core.base_table import table_moves_along_z
from ...core.series import RecordPlan
from ..outputs.recording import (COS, SIN, XB, YB, Recorder, initial_scalars, node_stride,
                                 scene_columns)
from ..outputs.steady import SteadyState
from .normal_start import start_gain
from .time_loop import ContactState

# The displacements' scale in F_c / k_pen. With it the cycle map's Jacobian is of order
# one on the block's elastic displacements (Fig 7, reduced: its largest multipliers by
# Arnoldi agree to 1e-3 for difference steps of 1e-5 to 1e-7; with the drive spring's
# stretch F_c / k_d as the scale, 5e5 times larger, a step of 1e-5 was already
# nonlinear and Newton-Krylov did not converge).
DEFORMATION = 10.0
# Implicit and reduced integrators carry these scalars of theirs (implicit.py: F_D, F_HOLD).
CARRIED_SCALARS = {"implicit": (8, 12), "reduced": (8, 12), "explicit": ()}


def first_cycle_step(scene, steps: int) -> int:
    """i0: the step one whole cycle after the vibration starts (the base at phase zero,
    away from its start), where every cycle the map integrates begins."""
    i_on = int(math.ceil(scene.vibration.t_on / scene.time.dt - 1e-9))
    return i_on + steps


def unrestrained_motions(scene) -> tuple:
    """The rigid motions nothing restrains (the gauge, module docstring): the translation
    in Y unless a prescribed drive holds it, and the turn about Z unless a holder does."""
    motions = () if scene.drive.prescribed else ("y",)
    if scene.drive.holder != "translating":
        motions += ("turn",)
    return motions


class FECycleMap:
    """Phi: one base cycle of the prepared integrator ``run`` (registry.py) on
    ``model`` (run.model: a reduced run's is its interface's, interface.py), for the scene
    it was prepared with (whose time.dt puts a whole number ``steps`` of steps in a cycle:
    periodic.py sees to it)."""

    def __init__(self, run, model, steps: int):
        scene = run.scene
        self.scene, self.model, self.run, self.steps = scene, model, run, steps
        self.dt = scene.time.dt
        self.i0 = first_cycle_step(scene, steps)
        self.table_start = run.table_row_at(self.i0)   # a motion given per step's row there
        law = scene.friction.law
        self.contact = ContactState.at_preload(model, law)
        self.scalars = initial_scalars(run.extra_scalars)
        self.recorder = Recorder(RecordPlan(steps, 1, 1), len(scene_columns(scene)),
                                 self.contact.normal, node_stride(scene))
        steady = SteadyState(scene)
        steady.tolerance = 0.0            # never stops early
        self.started = run.start(self.contact, self.scalars, self.recorder, steady)
        self.carried_scalars = CARRIED_SCALARS[run.name]
        self.parts = self._parts()
        self.size = sum(array.size for _, array in self.parts)
        self.preload = self._pack()       # the arrays as start() made them: the static preload
        self.translation = self._image(self._motion("x"))
        self.unrestrained = unrestrained_motions(scene)
        self.neutral = np.array([self._image(self._motion(m)) for m in self.unrestrained])
        self.scale = np.ones(self.size)
        self.scale = self._scales()
        self._neutral_scaled = None
        self.cycles = 0
        self.on_cycle = None    # if set, called with self.cycles after each cycle (progress)

    # -- the packed state --------------------------------------------------------
    def _parts(self) -> list:
        """(name, array) of everything the compiled step carries, in z's order."""
        c = self.contact
        parts = [(name, array) for name, array in self.started.carried.items()]
        parts += [("law_state", c.state), ("normal", c.normal), ("friction", c.friction)]
        return parts

    def _pack(self) -> np.ndarray:
        out = [array.ravel() for _, array in self.parts]
        out.append(self.scalars[list(self.carried_scalars)])
        return np.concatenate(out)

    def _unpack(self, z: np.ndarray) -> None:
        k = 0
        for _, array in self.parts:
            array.ravel()[:] = z[k:k + array.size]     # every carried array is contiguous
            k += array.size
        self.scalars[list(self.carried_scalars)] = z[k:]

    @property
    def full_size(self) -> int:
        return self.size + len(self.carried_scalars)

    def _motion(self, kind: str) -> np.ndarray:
        """A rigid node motion (dofs,): unit translation in X, Y or Z, or a unit turn about Z
        around the drive's attachment's weighted centre (1 m of X per m of Y)."""
        model = self.model
        motion = np.zeros(model.dofs).reshape(-1, 3)
        if kind == "x":
            motion[:, 0] = 1.0
        elif kind == "y":
            motion[:, 1] = 1.0
        elif kind == "z":
            motion[:, 2] = 1.0
        else:
            xyz = model.disc.coordinates
            centre = model.attach_weights @ xyz[model.attach_nodes]
            motion[:, 0] = -(xyz[:, 1] - centre[1])
            motion[:, 1] = xyz[:, 0] - centre[0]
        return motion.ravel()

    def _image(self, motion: np.ndarray) -> np.ndarray:
        """The packed image of a rigid motion: how z moves when every node moves by it."""
        moved = self.started.rigid(motion)
        out = [np.asarray(moved.get(name, np.zeros(array.shape)), dtype=float).ravel()
               for name, array in self.parts]
        out.append(np.zeros(len(self.carried_scalars)))
        return np.concatenate(out)

    def _scales(self) -> np.ndarray:
        """Each entry's natural size: displacements DEFORMATION times the contact's
        normal compliance under the Coulomb force, F_c / k_pen (the block's elastic
        deformation; its rigid drift on the drive spring, ~10^5 times more, is the
        slow direction newton_picard treats apart), velocities the fastest sliding
        v_a + v_d, accelerations that times w, forces a node's share of F_N
        (friction: of F_c), the law's state its size after a start (set_law_scale),
        the carried g by its rigid image (l q_c)."""
        scene, model = self.scene, self.model
        F_c = scene.F_c if scene.F_c > 0 else scene.contact.F_N
        length = DEFORMATION * F_c / model.penalty
        speed = scene.v_a + scene.drive.v_d
        share = float(model.normal0.max())
        scale = []
        for name, array in self.parts:
            if name in ("q", "u", "disp"):
                s = np.full(array.size, length)
            elif name == "v":
                s = np.full(array.size, speed)
            elif name == "a":
                s = np.full(array.size, speed * scene.omega)
            elif name == "g_prev":
                s = np.full(array.size, share)
            elif name == "friction":
                s = np.full(array.size, share * max(scene.mu_max, 1e-3))
            elif name == "normal":
                s = np.full(array.size, share)
            else:                              # the law's state: set_law_scale
                s = np.ones(array.size)
            scale.append(s)
        scale.append(np.full(len(self.carried_scalars), F_c))
        scale = np.concatenate(scale)
        k = 0
        for name, array in self.parts:          # g = f_c + l q_c: its rigid image's size
            if name == "g_prev":
                image = np.abs(self.translation[k:k + array.size]) * length
                scale[k:k + array.size] += image
            k += array.size
        return scale

    def set_law_scale(self, z_raw: np.ndarray) -> None:
        """The law's state scaled by each component's largest modulus over the nodes in
        ``z_raw`` (an unscaled state after a few cycles; 1 where it is zero everywhere):
        Dahl's length by the sliding length, its direction by 1."""
        k = 0
        for name, array in self.parts:
            if name == "law_state":
                block = np.abs(z_raw[k:k + array.size].reshape(array.shape))
                size = block.max(axis=0)
                size[size == 0.0] = 1.0          # a component that is zero everywhere
                self.scale[k:k + array.size] = np.tile(size, array.shape[0])
            k += array.size
        self._neutral_scaled = None

    # -- the map ----------------------------------------------------------------
    def _set_base(self) -> None:
        """The base at step i0 (eqs 23-25), as the compiled step carries it."""
        scene = self.scene
        phase = scene.omega * (self.i0 * self.dt - scene.vibration.t_on)
        cos_theta, sin_theta = vibration_axis(scene.vibration.theta_deg)
        s, c = math.sin(phase), math.cos(phase)
        self.scalars[SIN], self.scalars[COS] = s, c
        self.scalars[XB] = scene.u0 * s * cos_theta
        self.scalars[YB] = scene.u0 * s * sin_theta
        if scene.vibration.sampled:     # the motion given per step, added
            self.scalars[XB] += self.table_start[0]
            self.scalars[YB] += self.table_start[1]

    def load(self, z_raw: np.ndarray) -> None:
        """Set the integrator's arrays to the unscaled co-moving state ``z_raw`` at step
        i0 (the drive's translation v_d t added back), the base at its phase then."""
        v_d = self.scene.drive.v_d
        t0 = self.i0 * self.dt
        self._unpack(np.concatenate([z_raw[:self.size] + v_d * t0 * self.translation[:self.size],
                                     z_raw[self.size:]]))
        self._set_base()
        self.recorder.count[0] = 0

    def raw_cycle(self, z_raw: np.ndarray, rows: bool = False):
        """One cycle from the unscaled co-moving state ``z_raw``: the unscaled co-moving
        state after it (NaNs where the stepper failed), and with ``rows`` the cycle's
        recorded rows (recording.columns)."""
        self.cycles += 1
        if self.on_cycle is not None:
            self.on_cycle(self.cycles)
        self.load(z_raw)
        t1 = (self.i0 + self.steps) * self.dt
        failed, code, _ = self.started.steps(self.i0 + 1, self.i0 + self.steps)
        if code != 0:
            return np.full(self.full_size, np.nan), None
        end = self._pack()
        end[:self.size] -= self.scene.drive.v_d * t1 * self.translation[:self.size]
        table = self.recorder.strided[:self.steps].copy() if rows else None
        return end, table

    def gauge(self, x: np.ndarray) -> np.ndarray:
        """x (scaled) less its components along the neutral motions' images."""
        if not self.unrestrained:      # a held body under a prescribed drive: no gauge
            return x
        if self._neutral_scaled is None:
            G = self.neutral / self.scale
            Q, _ = np.linalg.qr(G.T)
            self._neutral_scaled = Q
        Q = self._neutral_scaled
        return x - Q @ (Q.T @ x)

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Phi in scaled variables, gauged: what core.shooting.newton_picard iterates."""
        end, _ = self.raw_cycle(x * self.scale)
        return self.gauge(end / self.scale)

    def slow_directions(self) -> tuple:
        """(S, steps): the map's slow directions, S (scaled size, p) gauged and each of
        unit norm, and the difference step along each (newton_picard's ``slow`` and
        ``slow_step``).

        The directions: the block's rigid translation in X and its velocity, the drive
        mode (the block on the drive spring k_d), the map's slowest (0.985 a cycle on
        Fig 7); and where the base moves in Y, the velocities of the rigid motions
        nothing but friction restrains (the translation in Y and the turn about Z, whose
        positions the gauge takes out), slow too (docs/performance.md, "Design choices
        measured").

        The steps: a rigid shift of 1e-3 of the drive spring's stretch under F_c (57 nm
        on Fig 7): linear, and far above the contact iteration's tolerance (1e-6 of
        F_N / k_t, 0.7 pm); the velocity the drive mode has at that amplitude, the shift
        times its angular frequency sqrt(k_d / m) (25 um/s on Fig 7, 5% of v_d); and that
        speed in Y and as a turn rate over the block's length. The same scaled step in
        the first two (a velocity of 0.17 m/s on Fig 7, 340 v_d) made the Newton
        matrix's velocity column a difference across the contact's kinks: from steady
        sliding its residual was 8000 against 120 at the start."""
        scene = self.scene
        kinds = ("x",) + (self.unrestrained if self._base_moves_in_y() else ())
        directions = np.column_stack([self.gauge(self.translation / self.scale)]
                                     + [self.gauge(self._velocity_image(kind) / self.scale)
                                        for kind in kinds])     # of a unit motion each
        norms = np.linalg.norm(directions, axis=0)
        F_c = scene.F_c if scene.F_c > 0 else scene.contact.F_N
        shift = 1e-3 * F_c / scene.drive.k_d
        speed = shift * math.sqrt(scene.drive.k_d / scene.body.mass)
        turn_rate = speed / self.model.length
        steps = [shift] + [turn_rate if kind == "turn" else speed for kind in kinds]
        return directions / norms, np.array(steps) * norms

    def _base_moves_in_y(self) -> bool:
        _, sin_theta = vibration_axis(self.scene.vibration.theta_deg)
        return abs(sin_theta) > 1e-9

    def _velocity_image(self, kind: str) -> np.ndarray:
        """The packed state of a unit rigid velocity of ``kind`` (_motion) and nothing else."""
        velocity = np.zeros(self.full_size)
        moved = self.started.rigid(self._motion(kind))
        k = 0
        for name, array in self.parts:
            if name == "v":
                velocity[k:k + array.size] = np.asarray(moved["q" if "q" in moved else "u"]).ravel()
            k += array.size
        return velocity

    def initial_state(self, drive_force: float) -> np.ndarray:
        """The unscaled co-moving state of steady sliding before any transient: the preload,
        the whole block moving at v_d and set back by the drive spring's stretch under
        ``drive_force`` (F_d = k_d (v_d t - x_A), eq 17), the laws at rest, the carried
        scalars' drive force ``drive_force``; where the base moves along Z, the body
        moved rigidly onto its forced response to the base at the cycle's start
        (normal_start.start_gain; the base at its phase phi there: started at the
        preload, a base at its crest would be A_n into the body, and the first cycle
        diverged)."""
        scene = self.scene
        z = self.preload.copy()
        stretch = 0.0 if scene.drive.prescribed else drive_force / scene.drive.k_d
        z[:self.size] -= stretch * self.translation[:self.size]
        velocity = self.started.rigid(self._motion("x"))
        k = 0
        for name, array in self.parts:
            if name == "v":
                z[k:k + array.size] = scene.drive.v_d * np.asarray(
                    velocity["q" if "q" in velocity else "u"]).ravel()
            k += array.size
        amplitude = scene.vibration.normal_amplitude
        if amplitude > 0.0:
            face, speed = start_gain(scene, self.model)
            sin_n, cos_n = normal_phase(scene.vibration.normal_phase_deg)
            z[:self.size] += (face * amplitude * sin_n * self._image(self._motion("z"))[:self.size]
                              + speed * amplitude * scene.omega * cos_n
                              * self._velocity_image("z")[:self.size])
        if table_moves_along_z(scene.vibration):   # the table's z_b and dz_b/dt too
            face, speed = start_gain(scene, self.model)
            z_b, vz_b = self.table_start[2], self.table_start[5]
            z[:self.size] += (face * z_b * self._image(self._motion("z"))[:self.size]
                              + speed * vz_b * self._velocity_image("z")[:self.size])
        if self.carried_scalars:
            z[self.size] = drive_force
        return z

