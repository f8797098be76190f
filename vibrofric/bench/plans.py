"""What one ``vibrofric bench`` run measures: the scene, the friction laws compared, the
quick and the full plan."""

from dataclasses import dataclass
from pathlib import Path

from .. import scene as scene_module

SCENE = Path(__file__).resolve().parent.parent / "scenes" / "longitudinal.toml"  # package data
EXAMPLE_LAW = Path(__file__).resolve().parent.parent.parent / "examples" / "laws" / "maxwell_slip.py"

# The friction laws the bench compares on the same scene: (label, contact.law, its parameters).
LAWS = (("Dahl, i = 1", "dahl", {}),
        ("Dahl, i = 0.5", "dahl", {"dahl_exponent": 0.5}),
        ("Dahl, i = 2", "dahl", {"dahl_exponent": 2.0}),
        ("LuGre, F_s = 1.2 F_c, v_s = 2 mm/s", "lugre", {"F_s": 6.6, "v_s": 2e-3}))
if EXAMPLE_LAW.exists():  # a checkout; an installed package has no examples/
    LAWS += (("Maxwell-slip (examples/laws)", str(EXAMPLE_LAW), {}),)

# The short run the cost growth is measured on: vibration from 1 ms, F_dv over 20 cycles.
GROWTH = {"vibration.t_on": 0.001, "time.average_cycles": 20}


@dataclass(frozen=True)
class Plan:
    """What one bench run measures."""

    T: float                   # s simulated (the Fig 7 scene)
    analytic_dts: tuple        # steps of the analytic stepper, both updates
    analytic_reference_dt: float
    fe_cases: tuple            # (integrator, mesh, dt): speed against error
    fe_reference: tuple        # (integrator, mesh, dt) of the converged FE reference
    dofs_cases: tuple          # (integrator, ((mesh, dt), ...)): cost against DOFs
    dofs_T: float              # s simulated in the DOFs cases
    time_cases: tuple          # (integrator, mesh, dt, (T, ...)): cost against simulated time
    laws: tuple = ()           # (label, law, parameters): a row per friction law (LAWS)
    law_dt: float = 1e-6       # the analytic stepper's step in the law rows
    law_fe: tuple = ()         # (integrator, mesh, dt) of the law rows' FE run; () for none
    breakdown_cases: tuple = ()  # (integrator, mesh, dt): a step's parts against the roofline
    mesh_study: tuple = ()     # (integrator, dt, (level, ...) coarse to fine): the spatial error
    periodic: bool = False     # the periodic solver against the transient (periodic_vs_transient.py)
    periodic_fe: tuple = ()    # its FE cases (periodic_vs_transient.FE_CASES' labels)
    periodic_fe_study: bool = False  # the Fig 12 FE study by orbits and stepped, both cores


_MESH_STEPS = (("tiny", 2e-6), ("coarse", 1e-6), ("medium", 5e-7))  # explicit: below each stable step

# The mesh study's levels, coarse to fine: element edges ~13, 7.5, 5 and 3.8 mm on the
# default block (FULL adds "fine", 1.9 mm).
MESH_LEVELS = ("2x3x4", "coarse", "6x8x10", "medium")

QUICK = Plan(
    T=0.3,
    analytic_dts=(1e-5, 4e-6, 2e-6, 1e-6),
    analytic_reference_dt=1e-8,
    fe_cases=(("explicit", "coarse", 1e-6),
              ("implicit", "coarse", 2e-5), ("implicit", "coarse", 1e-5),
              ("reduced", "coarse", 2e-5), ("reduced", "coarse", 1e-5),
              ("reduced", "coarse", 5e-6)),
    fe_reference=("explicit", "coarse", 5e-7),
    dofs_cases=(("explicit", _MESH_STEPS),
                ("implicit", tuple((mesh, 1e-5) for mesh, _ in _MESH_STEPS)),
                ("reduced", tuple((mesh, 1e-5) for mesh, _ in _MESH_STEPS))),
    dofs_T=0.01,
    time_cases=(("implicit", "coarse", 1e-5, (0.01, 0.02, 0.04)),
                ("reduced", "coarse", 1e-5, (0.02, 0.04, 0.08, 0.16))),
    laws=LAWS,
    law_fe=("reduced", "coarse", 1e-5),
    breakdown_cases=(("explicit", "coarse", 1e-6), ("implicit", "coarse", 1e-5),
                     ("reduced", "coarse", 1e-5)),
    mesh_study=("reduced", 1e-5, MESH_LEVELS),
    periodic=True,
    periodic_fe=("reduced",),
)

FULL = Plan(
    T=0.3,
    analytic_dts=(2e-5, 1e-5, 4e-6, 2e-6, 1e-6, 5e-7),
    analytic_reference_dt=5e-9,
    fe_cases=QUICK.fe_cases + (("explicit", "coarse", 5e-7), ("implicit", "coarse", 5e-6),
                               ("reduced", "coarse", 2.5e-6),
                               ("explicit", "medium", 5e-7), ("reduced", "medium", 1e-5)),
    fe_reference=("explicit", "medium", 2.5e-7),
    dofs_cases=(("explicit", _MESH_STEPS),
                ("implicit", tuple((mesh, 1e-5) for mesh, _ in _MESH_STEPS)),
                ("reduced", tuple((mesh, 1e-5) for mesh, _ in _MESH_STEPS) + (("fine", 1e-5),))),
    dofs_T=0.01,
    time_cases=QUICK.time_cases[:1] + (("reduced", "coarse", 1e-5, (0.02, 0.04, 0.08, 0.16, 0.32)),),
    laws=LAWS,
    law_fe=("reduced", "coarse", 1e-5),
    breakdown_cases=QUICK.breakdown_cases + (("explicit", "medium", 5e-7),
                                             ("reduced", "medium", 1e-5)),
    mesh_study=("reduced", 1e-5, MESH_LEVELS + ("fine",)),
    periodic=True,
    periodic_fe=("reduced", "implicit", "explicit", "reduced, k_t x 100", "reduced, medium mesh"),
    periodic_fe_study=True,
)



def base_scene(plan: Plan):
    """The bench's scene: every method stepped through time.T (time.method transient: the
    bench measures the steppers; its periodic rows ask for the orbit themselves)."""
    return scene_module.load(SCENE, [f"time.T={plan.T}", "fem.output_every=0",
                                     'time.method="transient"'])
