"""The FE block's bounce frequency on its penalty springs against core/bounce.py's estimate.

The lumped model's default contact.k_n is m w_b^2 with w_b the first mode of the
block as a bar on the penalty spring (core/bounce.py). Here the FE block's own:
the modes of the preloaded block on its contact, K + P (k_pen w_i in Z, k_t w_i in X
and Y at each contact node) against the lumped mass M, the bounce being the mode
that carries the most of the block's mass in Z (its effective modal mass,
(phi^T M e_z)^2 / (phi^T M phi)).

    .venv/bin/python benchmarks/fe_bounce_frequency.py [--mesh coarse] [--stiffer 1]
"""

import argparse
import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from vibrofric.api import load_scene
from vibrofric.core.bounce import bounce_stiffness
from vibrofric.fem.model.fe_model import build_model


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", default="coarse")
    parser.add_argument("--stiffer", type=float, default=1.0)
    parser.add_argument("--modes", type=int, default=12)
    args = parser.parse_args()
    base = load_scene("longitudinal")
    scene = load_scene("longitudinal", **{"fem.mesh": args.mesh,
                                          "body.E": args.stiffer * base.body.E})
    model = build_model(scene, None)
    dofs = model.dofs
    springs = np.zeros(dofs)
    k_t = scene.law_bounds.stiffness
    for c, node in enumerate(model.contact_nodes):
        springs[3 * node] = springs[3 * node + 1] = k_t * model.area_share[c]
        springs[3 * node + 2] = model.penalty_share[c]
    K = (model.stiffness + sp.diags(springs)).tocsc()
    mass = 1.0 / model.inverse_mass
    M = sp.diags(mass)
    values, vectors = sla.eigsh(K, k=args.modes, M=M, sigma=0.0, which="LM")
    e_z = np.tile([0.0, 0.0, 1.0], dofs // 3)
    modal_mass = np.einsum("ij,i,ij->j", vectors, mass, vectors)
    participation = (vectors.T @ (mass * e_z)) ** 2 / modal_mass
    bounce = int(np.argmax(participation))
    f_fe = math.sqrt(values[bounce]) / (2 * math.pi)
    k_n = bounce_stiffness(model.block_mass, scene.body.E, model.density, scene.body.size,
                           model.penalty)
    f_bar = math.sqrt(k_n / model.block_mass) / (2 * math.pi)
    print(f"{args.mesh} block, E x {args.stiffer:g}: FE bounce {f_fe / 1e3:.4g} kHz (mode "
          f"{bounce + 1} of {args.modes}, {participation[bounce] / model.block_mass:.1%} of the "
          f"mass in Z); bar on spring (core/bounce.py) {f_bar / 1e3:.4g} kHz, "
          f"{f_bar / f_fe - 1.0:+.2%}; its k_n {k_n:.4g} N/m against m w_FE^2 "
          f"{model.block_mass * (2 * math.pi * f_fe) ** 2:.4g} N/m")


if __name__ == "__main__":
    main()
