"""The finite-element model: an elastic block on a vibrating rigid base (DOLFINx 0.5.2 to 0.11).

The open counterpart of the paper's Abaqus/Explicit model with a VFRIC
friction subroutine (docs/model.md section 5). Three subpackages, importing
one way (tests/test_layers.py): model <- outputs <- integrators <- simulate.

model/        the block as plain arrays: mesh to matrices, contact, drive, loads
    dolfinx_adapter  DOLFINx itself: mesh from gmsh, vector Q1 space, K, lumped mass,
                 face areas, VTK frames (detects what the installed version offers)
    assembly     the elastic block as arrays: K, lumped mass, face areas
    model_cache  the assembled block kept on disk, so a repeat run skips DOLFINx
    loads        gravity + top pressure, sized to the normal reaction F_N
    contact      penalty normal contact and the per-node friction law (VFRIC analogue)
    drive        the drive spring k_d and where it attaches
    preload      the static equilibrium every run starts from
    stability    the highest frequency, default damping, explicit stable step
    fe_model     a scene's FE model as plain arrays (all of the above, once per run)
    linalg       products and factorized solves inside the numba loops
    simd         four-lane vectors of doubles for the product with K (llvmlite)

outputs/      what a run records and reports, step by step and at its end
    recording    the recorded rows (a run may end early), the run's end state
    steady       early steady state: stop once the cycle-averaged F_d has settled
    trouble      numerical trouble: the per-step checks and their messages
    energy       the energy balance of an implicit run (fem.energy)
    normal_swing the summed normal force judged: steady, rocking, a transient, ringing
    paraview     the .pvd frame series (VTK XML, from the model's arrays)

integrators/  the time integrators that step the model, and the periodic solver on them
    registry     the registry fem.integrator selects from, and "auto"
    time_loop    what every integrator's run does around its compiled step
    explicit     central-difference time loop (numba), the baseline integrator
    implicit     generalized-alpha, the linear operator factorized once, the contact
                 and friction solved in the step (numba)
    generalized_alpha  the scheme's coefficients, the linear system, the contact tangent
    contact_solve  the contact inside an implicit step: forces at a trial state, the iteration
    anderson     Anderson acceleration of that iteration, where it would crawl
    borrowed     arrays without reference counts, for the compiled loops
    step_cost    what a step of each integrator costs, for "auto"
    reduction    Craig-Bampton reduction of the block to its contact face, and its
                 measured error; the reduced integrator
    cycle_map    one base cycle of an integrator's compiled step as a map of its state,
                 in the drive's frame, its unrestrained rigid motions gauged out
    periodic     the steady cycle directly (time.method periodic / auto): shooting on it

simulate.py   run_fe(scene, comm, vtk_dir, progress, start) -> FEResult: one FE run;
              answer_ratio(result, scene): its F_dv/F_d0
step_error.py the answer's time-step error (dt and dt/2), and the step "auto" takes by it

Only model/dolfinx_adapter imports DOLFINx, UFL and petsc4py.
"""

from .simulate import FEResult, answer_ratio, run_fe

__all__ = ["FEResult", "answer_ratio", "run_fe"]
