"""The stiff blocks on which the FE and lumped models are compared losing contact
(benchmarks/fe_normal_vs_lumped.py --contact-damping lumped, docs/validation.md "A base
moving along Z"), at a cheap timing for the tests: the low, wide block (--block low) and
the paper's block (--block paper, held at its top face with --hold)."""

import math

from vibrofric.analytic.normal import contact_damping
from vibrofric.api import load_scene
from vibrofric.core.bounce import bounce_stiffness, default_penalty

SIZE = (0.06, 0.08, 0.005)   # m: 5 mm tall, the paper's mass (0.5 kg: 20,800 kg/m^3)
STIFFER = 10.0               # body.E x 10: its own compliance out of the bounce
T_ON, CYCLES = 0.05, 200     # s, cycles after it (the benchmark: 0.14 s, 800)


def loss_threshold(scene) -> float:
    """A_th: the amplitude at which the forced swing m w^2 A / (1 - r^2) reaches F_N."""
    m, w = scene.body.mass, scene.omega
    return scene.contact.F_N * (1.0 - w * w * m / scene.normal_stiffness) / (m * w * w)


def low_block_scene(level: float, k_v: float, zeta_n: float, **keys):
    """stiff_block_scene on the low block (SIZE)."""
    return stiff_block_scene(SIZE, level, k_v, zeta_n, **keys)


def stiff_block_scene(size, level: float, k_v: float, zeta_n: float,
                      stiffer: float = STIFFER, **keys):
    """The longitudinal scene on a block of ``size`` (m; the paper's: meshes.DEFAULT_SIZE)
    and the paper's mass, E x ``stiffer``, its base moving along Z at ``level`` times A_th
    from T_ON: the FE penalty the paper's block's, the lumped k_n the block's bounce on
    it (core/bounce.py), contact.zeta_n = ``zeta_n`` and fem.damping
    c_n / k_pen, so that the FE nodes' penalty dashpots sum to the lumped one's; the
    reduced FE integrator at 200 steps a cycle answering by its steady cycle where it
    finds one (time.method auto), the lumped time.dt 5e-7 s (``keys`` override)."""
    size = tuple(size)
    base = load_scene("longitudinal")
    penalty = default_penalty(base.body.E, base.body.size)
    mass = base.body.mass
    k_n = bounce_stiffness(mass, stiffer * base.body.E, mass / math.prod(size), size, penalty)
    f = base.vibration.f
    values = {"body.E": stiffer * base.body.E, "body.size": list(size), "fem.penalty": penalty,
              "contact.k_n": k_n, "contact.zeta_n": zeta_n, "fem.mesh": "coarse",
              "fem.integrator": "reduced", "vibration.k_v": k_v, "vibration.t_on": T_ON,
              "time.T": T_ON + CYCLES / f, "time.dt": 5e-7, "time.average_cycles": 20,
              "time.method": "auto", "time.error_estimate": False, "fem.output_every": 0}
    scene = load_scene("longitudinal", **values)
    scene = scene.with_values({"vibration.normal_amplitude": level * loss_threshold(scene),
                               "fem.damping": contact_damping(scene) / penalty})
    return scene.with_values(keys)
