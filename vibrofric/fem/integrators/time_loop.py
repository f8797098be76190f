"""What every integrator's run does around its compiled step.

An integrator (explicit.py, implicit.py, reduction.py) is a TimeLoop prepared
once per run. It supplies its preparation (its ``__init__``: checks, a
factorization, a reduction) and, through ``start``, its compiled step over a
range of steps; the TimeLoop owns the rest, the same for all of them:

    the initial state    the static preload, the friction law's states at rest
                         (ContactState), the carried scalars, the recorder and
                         the early-steady-state detector
    the chunks           between ParaView frames and progress reports
                         (recording.run_in_chunks)
    the failures         a trouble code from the compiled step becomes a
                         NumericalError with the integrator's hint (outputs/trouble.py);
                         a body that tips over its contact stops the run (outputs/tipping.py)
    the statistics       the loop's, the integrator's own, the early stop's

    run.name, run.info, run.choice, run.cost_per_step  (registry.py)
    run.integrate(plan, frame=None, every=0, progress=None) -> recording.Integration
"""

import math
from dataclasses import dataclass

import numpy as np

from ...core.base_motion import first_step_on
from ...core.base_table import TABLE_COLUMNS, base_table, table_row
from ...core.series import averaging_steps
from ..outputs import trouble
from ..outputs.tipping import TipWatch
from ..model.linalg import one_blas_thread
from ..outputs.recording import (XB, YB, Integration, Recorder, State, initial_scalars,
                                 loop_stats, node_stride, run_in_chunks, scene_columns)
from ..outputs.steady import SteadyState


@dataclass
class ContactState:
    """Every contact node's friction-law state and forces, carried from step to step."""

    state: np.ndarray       # (contacts, the law's STATE_SIZE)
    normal: np.ndarray      # (contacts,) normal force N_i
    friction: np.ndarray    # (contacts, 2) friction force F_i (acts on the body as -F_i)

    @classmethod
    def at_preload(cls, model, law) -> "ContactState":
        """The preload's normal forces; the law's states at rest (friction_law.FrictionLaw)."""
        contacts = model.contact_nodes.size
        return cls(law.initial_state(contacts), model.normal0.copy(), np.zeros((contacts, 2)))


@dataclass
class Started:
    """What an integrator's ``start`` hands back to the TimeLoop.

    steps(first, last) -> (failed step, trouble code, stop step): the compiled
        step over steps first..last, on the arrays start() made
    fields() -> (u, v): the node displacement (with the preload) and velocity now
    carried  {name: array}: the integrator's own state that the compiled step carries
        from step to step (beside the ContactState and the scalars); written in
        place, it sets the state the next ``steps`` call starts from (cycle_map.py)
    rigid(pattern) -> {name: array}: how each carried array changes when every node
        moves by the rigid displacement ``pattern`` (dofs,): the drive's translation
        and the motions nothing restrains, taken out in cycle_map.py
    """

    steps: object
    fields: object
    carried: dict
    rigid: object


class TimeLoop:
    """The common part of an integrator's run (see the module); subclasses set
    ``name``, ``hint`` and ``extra_scalars`` and implement ``start`` (and
    ``stats`` for statistics of their own)."""

    name = ""
    choice = None
    extra_scalars = 0        # scalars the compiled step carries beyond recording's

    @property
    def hint(self) -> str:
        """What to change when the compiled step reports trouble."""
        return "try a smaller time.dt"

    def start(self, contact: ContactState, scalars, recorder: Recorder,
              steady: SteadyState) -> Started:
        raise NotImplementedError

    def stats(self, scalars, last: int) -> dict:
        """The integrator's own statistics of a run that ended at step ``last``."""
        return {}

    def full_state(self, state: State) -> State:
        """A state of the run on every contact candidate of the scene's model: here the
        run's own (a reduced run's interface may hold fewer: interface.py)."""
        return state

    def full_normals(self, node_normals: np.ndarray) -> np.ndarray:
        """Recorder.node_normals on every contact candidate (as full_state)."""
        return node_normals

    def table_row_at(self, i: int) -> np.ndarray:
        """The row (core/base_table.py TABLE_COLUMNS) of the base motion given per step
        that the compiled step reads at the end of step i, zeros where the sine alone
        moves the base: here the table at every step (explicit.py); the implicit
        integrators read theirs at the friction sub-steps (implicit.py)."""
        scene = self.scene
        vib = scene.vibration
        if not vib.sampled:
            return np.zeros(len(TABLE_COLUMNS))
        table = base_table(vib, scene.omega, scene.time.dt, vib.t_on,
                           first_step_on(vib.t_on, scene.time.dt), scene.steps)
        k = table_row(table.rows, table.first_step, table.period, i)
        return table.rows[k].copy() if k >= 0 else np.zeros(len(TABLE_COLUMNS))

    def integrate(self, plan, frame=None, every=0, progress=None) -> Integration:
        """Run ``plan.steps`` steps of time.dt from the static preload (fewer once
        settled, outputs/steady.py), keep the rows ``plan`` (core.series.RecordPlan) asks
        for, call ``frame(state)`` at t = 0, every ``every`` steps and at the end
        and ``progress(step, steps)`` now and then (recording.run_in_chunks);
        raise core.errors.NumericalError on numerical trouble."""
        scene = self.scene
        dt = scene.time.dt
        law = scene.friction.law
        contact = ContactState.at_preload(self.model, law)
        scalars = initial_scalars(self.extra_scalars)
        recorder = Recorder(plan, len(scene_columns(scene)), contact.normal,
                            node_stride(scene))
        steady = SteadyState(scene)
        started = self.start(contact, scalars, recorder, steady)
        tipping = TipWatch(self.model, recorder, dt, 1.0 / scene.vibration.f)

        def state(step):
            u, v = started.fields()
            return self.full_state(State(step, step * dt, u, v, contact.state.copy(),
                                         law.deformation(contact.state), contact.normal,
                                         contact.friction, scalars[XB], scalars[YB]))

        def advance(first, last):
            failed, code, stop = started.steps(first, last)
            if code != trouble.OK:
                raise trouble.failure(failed, code, scene, self.hint)
            tipping.scan(first, stop or last)
            return stop

        onset = math.floor(scene.vibration.t_on / dt) + 1   # the first step the base vibrates in
        with one_blas_thread():
            last, loop_time = run_in_chunks(plan.steps, frame, every, state, advance, progress,
                                            onset, longest=recorder.full)
        stats = {**loop_stats(scalars, loop_time), **self.stats(scalars, last),
                 **steady.report(last)}
        window = min(averaging_steps(scene), recorder.full, last)
        return Integration(recorder.table(last), state(last), stats,
                           self.full_normals(recorder.node_normals(last, window)))
