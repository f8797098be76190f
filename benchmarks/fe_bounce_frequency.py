"""The FE block's bounce frequency on its penalty springs against core/bounce.py's estimate.

The lumped model's default contact.k_n is m w_b^2 with w_b the first mode of the
block as a bar on the penalty spring (core/bounce.py). Here the FE block's own:
the modes of the preloaded block on its contact, K + P (k_pen w_i in Z, k_t w_i in X
and Y at each contact node) against the lumped mass M, the bounce being the mode
that carries the most of the block's mass in Z (its effective modal mass,
(phi^T M e_z)^2 / (phi^T M phi)).

    .venv/bin/python benchmarks/fe_bounce_frequency.py [--mesh coarse] [--stiffer 1]
        [--size 0.06,0.08,0.005] [--penalty 4.73e10]
        (--size: another block of the same mass; --penalty: fem.penalty, else its default)
"""

import argparse
import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from vibrofric.api import load_scene
from vibrofric.core.bounce import bounce_stiffness
from vibrofric.fem.model.fe_model import build_model


def contact_modes(scene, count: int):
    """The ``count`` lowest modes of the scene's FE block preloaded on its contact (the
    module docstring's K + P against M): (model, angular frequencies (count,), mode
    shapes (dofs, count), the lumped masses (dofs,))."""
    model = build_model(scene, None)
    dofs = model.dofs
    springs = np.zeros(dofs)
    k_t = scene.law_bounds.stiffness
    for c, node in enumerate(model.contact_nodes):
        springs[3 * node] = springs[3 * node + 1] = k_t * model.area_share[c]
        springs[3 * node + 2] = model.penalty_share[c]
    K = (model.stiffness + sp.diags(springs)).tocsc()
    mass = 1.0 / model.inverse_mass
    values, vectors = sla.eigsh(K, k=count, M=sp.diags(mass), sigma=0.0, which="LM")
    return model, np.sqrt(np.abs(values)), vectors, mass


def participation(vectors, mass, motion) -> np.ndarray:
    """Each mode's effective modal mass along the rigid ``motion`` (dofs,),
    (phi^T M motion)^2 / (phi^T M phi), over motion^T M motion: 1 for a mode that is
    that motion."""
    modal_mass = np.einsum("ij,i,ij->j", vectors, mass, vectors)
    return (vectors.T @ (mass * motion)) ** 2 / modal_mass / (motion @ (mass * motion))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", default="coarse")
    parser.add_argument("--stiffer", type=float, default=1.0)
    parser.add_argument("--modes", type=int, default=12)
    parser.add_argument("--size", default=None, help="the block's X,Y,Z edges (m)")
    parser.add_argument("--penalty", type=float, default=None, help="fem.penalty (N/m)")
    args = parser.parse_args()
    base = load_scene("longitudinal")
    values = {"fem.mesh": args.mesh, "body.E": args.stiffer * base.body.E}
    if args.size is not None:
        values["body.size"] = [float(edge) for edge in args.size.split(",")]
    if args.penalty is not None:
        values["fem.penalty"] = args.penalty
    scene = load_scene("longitudinal", **values)
    model, omegas, vectors, mass = contact_modes(scene, args.modes)
    in_z = participation(vectors, mass, np.tile([0.0, 0.0, 1.0], model.dofs // 3))
    bounce = int(np.argmax(in_z))
    f_fe = omegas[bounce] / (2 * math.pi)
    k_n = bounce_stiffness(model.block_mass, scene.body.E, model.density, scene.body.size,
                           model.penalty)
    f_bar = math.sqrt(k_n / model.block_mass) / (2 * math.pi)
    print(f"{args.mesh} block, E x {args.stiffer:g}: FE bounce {f_fe / 1e3:.4g} kHz (mode "
          f"{bounce + 1} of {args.modes}, {in_z[bounce]:.1%} of the "
          f"mass in Z); bar on spring (core/bounce.py) {f_bar / 1e3:.4g} kHz, "
          f"{f_bar / f_fe - 1.0:+.2%}; its k_n {k_n:.4g} N/m against m w_FE^2 "
          f"{model.block_mass * (2 * math.pi * f_fe) ** 2:.4g} N/m")


if __name__ == "__main__":
    main()
