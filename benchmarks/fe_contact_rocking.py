"""How the FE block rocks on its contact once it loses it (docs/validation.md, "A base
moving along Z"): what the lumped body, one normal degree of freedom, lacks.

The block and its posing are benchmarks/fe_normal_vs_lumped.py's (``--block``,
``--contact-damping``, ``--zeta-n``, E x ``--stiffer``; ``--hold``: held at its top face
by a translating holder, which takes the rotations out). Two measurements:

  modes   the block's rocking modes on its penalty springs (about Y: front/back, about
          X: left/right; the modes carrying most of each rigid rotation about the
          contact face's centre, benchmarks/fe_bounce_frequency.py's K + P against M)
          against its bounce mode. On a block as low as it is long (I ~ m L^2 / 12, the
          rotational stiffness k_pen L^2 / 12) rocking and bounce are nearly in 1:1
          resonance, so a face that opens and lands unevenly feeds rocking from the bounce.
          Held (--hold), the holder's ties take the rigid rotations: the mode found
          carrying most of one is then the block's sway on its tangential springs
          (2.0 kHz on the paper's block), not a rocking.
  split   at each ``--levels`` fraction of A_th, the FE run's contact force's first
          moments over the face, sum_i N_i (x_i - x_c) / (L_x / 2) (front/back) and
          sum_i N_i (y_i - y_c) / (L_y / 2) (left/right), in N: the force an edge carries
          above or below a face pressed evenly (0 without rocking), over the averaging
          window's kept samples of the nodes' forces; with the fraction of the nodes out
          of contact in the front (x > x_c) and back halves.

    .venv/bin/python benchmarks/fe_contact_rocking.py --stiffer 10 --block low
        --contact-damping lumped --levels 1.0,1.006,1.02 [--kv 6] [--zeta-n 0.05]
        [--modes 12] [--hold]
"""

import argparse
import math

import numpy as np

import fe_normal_vs_lumped as comparison
from fe_bounce_frequency import contact_modes, participation

import vibrofric.fem.simulate as simulate
from vibrofric.analytic.solve import solve
from vibrofric.fem import run_fe
from vibrofric.fem.simulate import answer_ratio

# The nodes' forces over the averaging window are not part of FEResult: they are taken
# where simulate hands them to normal_force_keys (a measurement's tap, not an interface).
_window = {}
_normal_force_keys = simulate.normal_force_keys


def _tapped(f_n, node_normals):
    _window["node_normals"] = np.asarray(node_normals)
    return _normal_force_keys(f_n, node_normals)


def rocking_modes(scene, count: int) -> str:
    """One line: the bounce mode's and the two rocking modes' frequencies."""
    model, omegas, vectors, mass = contact_modes(scene, count)
    points = model.disc.coordinates
    centre = points[model.contact_nodes].mean(axis=0)
    x, y, z = (points - centre).T
    zero = np.zeros_like(x)
    motions = {"bounce": np.column_stack([zero, zero, zero + 1.0]).ravel(),
               "rocking front/back (about Y)": np.column_stack([z, zero, -x]).ravel(),
               "rocking left/right (about X)": np.column_stack([zero, -z, y]).ravel()}
    found = {}
    for name, motion in motions.items():
        share = participation(vectors, mass, motion)
        mode = int(np.argmax(share))
        found[name] = (omegas[mode] / (2 * math.pi), share[mode])
    f_b = found["bounce"][0]
    return "; ".join(f"{name} {f / 1e3:.4g} kHz ({f / f_b:.3f} of the bounce, {share:.0%} of "
                     f"the motion)" for name, (f, share) in found.items())


def split(points, contact_nodes) -> dict:
    """The front/back and left/right first moments' ranges (N) and the open fractions of
    the front and back halves, over the tapped window (``points`` the nodes' positions)."""
    node_normals = _window["node_normals"]
    face = points[contact_nodes]
    x, y = (face[:, :2] - face[:, :2].mean(axis=0)).T
    front_back = node_normals @ x / (np.ptp(x) / 2)
    left_right = node_normals @ y / (np.ptp(y) / 2)
    out_of_contact = node_normals <= 0.0
    return {"front_back": (front_back.min(), front_back.max()),
            "left_right": (left_right.min(), left_right.max()),
            "open_front": float(np.mean(out_of_contact[:, x > 0])),
            "open_back": float(np.mean(out_of_contact[:, x < 0]))}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", default="coarse")
    parser.add_argument("--cycles", type=int, default=800)
    parser.add_argument("--stiffer", type=float, default=10.0)
    parser.add_argument("--steps-per-cycle", type=int, default=200)
    parser.add_argument("--block", default="low", choices=tuple(comparison.BLOCKS))
    parser.add_argument("--contact-damping", default="lumped", choices=("fe", "lumped", "modal"))
    parser.add_argument("--levels", default="1.0,1.006,1.02")
    parser.add_argument("--kv", type=float, default=6.0)
    parser.add_argument("--modes", type=int, default=12)
    parser.add_argument("--zeta-n", type=float, default=None, help="contact.zeta_n")
    parser.add_argument("--hold", action="store_true",
                        help="FE: drive.attach = load-group, drive.holder = translating")
    args = parser.parse_args()
    posed = {"block": args.block, "damping": args.contact_damping}
    if args.zeta_n is not None:
        posed["contact.zeta_n"] = args.zeta_n
    held = comparison.HELD if args.hold else {}
    probe = comparison.stiff_scene(args.mesh, args.cycles, args.stiffer, **posed).with_values(held)
    a_th = comparison.threshold(probe)
    print(f"Block {list(probe.body.size)} m (E x {args.stiffer:g}"
          f"{', held at its top face' if args.hold else ''}), fem.damping "
          f"{probe.fem.damping:.4g} s, k_v = {args.kv:g}, A_th = {a_th:.4g} m; mesh {args.mesh}, "
          f"reduced at {args.steps_per_cycle} steps a cycle, T = t_on + {args.cycles} cycles")
    print(rocking_modes(probe, args.modes))
    print()
    print("| A_n / A_th | lumped F_dv/F_d0 | FE F_dv/F_d0 | FE - lumped | loss lumped | "
          "FE nodes open, front / back half | FE front/back split (N) | "
          "FE left/right split (N) | FE answered by |")
    print("|---|---|---|---|---|---|---|---|---|")
    simulate.normal_force_keys = _tapped
    for level in map(float, args.levels.split(",")):
        keys = {"vibration.normal_amplitude": level * a_th, "vibration.k_v": args.kv,
                "time.dt": 5e-7}
        scene = comparison.stiff_scene(args.mesh, args.cycles, args.stiffer, **posed, **keys)
        _, lumped = solve(scene.with_values({"time.method": "transient"}))
        fe_scene = scene.with_values({"time.dt": 1.0 / (args.steps_per_cycle * scene.vibration.f),
                                      **held})
        result = run_fe(fe_scene)
        fe = answer_ratio(result, fe_scene)
        s = split(result.fields["coordinates"], result.fields["contact_nodes"])
        ratio = lumped["F_dv_over_F_d0"]
        print(f"| {level:g} | {ratio:.4f} | {fe:.4f} | {(fe - ratio) / abs(ratio):+.2%} | "
              f"{lumped['contact_loss_fraction']:.3f} | {s['open_front']:.3f} / "
              f"{s['open_back']:.3f} | {s['front_back'][0]:.3g} to {s['front_back'][1]:.3g} | "
              f"{s['left_right'][0]:.3g} to {s['left_right'][1]:.3g} | "
              f"{result.info.get('periodic', {}).get('method', 'stepped')} |", flush=True)


if __name__ == "__main__":
    main()
