"""How much each contact node's normal force swings as the block pitches.

    .venv/bin/python benchmarks/normal_force_swing.py

The Fig 7 scene (Dahl, i = 1, 0.3 s, reduced integrator) on the paper's steel
block, the same block 100 times stiffer, and the stiff block 5 mm tall. The
node states are sampled every SAMPLE steps over the last 4 vibration cycles
(instead of writing ParaView frames); printed per block: the summed normal
force's swing, the largest node's swing of N_i about its mean (in percent of
its mean), the swing of the front and back rows (x = min, max), and how the
front row's N follows the summed friction force (correlation).
"""

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from mpi4py import MPI  # noqa: E402,F401  (before DOLFINx)

from vibrofric import scene as scene_module  # noqa: E402
from vibrofric.fem import simulate as fem_simulate  # noqa: E402

SAMPLE = 5            # steps between samples (50 a cycle at 4 kHz and 1e-6 s)
BODIES = {
    "steel": {},
    "stiff": {"body.E": 2.09e13},
    "flat": {"body.E": 2.09e13, "body.size": [0.03, 0.04, 0.005]},
}


class NodeSampler:
    """Stands in for paraview.FrameWriter: keeps the contact nodes' states."""

    samples = []

    def __init__(self, model, vtk_dir):
        self.model = model
        self.path = Path(vtk_dir) / "block.pvd"
        self.frames = 0
        NodeSampler.samples = []
        NodeSampler.model = model

    def __call__(self, state) -> None:
        NodeSampler.samples.append((state.t, state.normal.copy(), state.friction.copy()))
        self.frames += 1

    def close(self) -> None:
        pass


def swing(body: str, **more):
    scene = scene_module.load(ROOT / "scenes" / "longitudinal.toml").with_values(
        {"time.T": 0.3, "fem.integrator": "reduced", "fem.output_every": SAMPLE,
         **BODIES[body], **more})
    fem_simulate.FrameWriter = NodeSampler
    fem_simulate.run_fe(scene, vtk_dir=Path("/nonexistent"))
    window = 4.0 / scene.vibration.f
    t = np.array([s[0] for s in NodeSampler.samples])
    keep = t >= t[-1] - window
    normal = np.array([s[1] for s in NodeSampler.samples])[keep]
    friction = np.array([s[2][:, 0].sum() for s in NodeSampler.samples])[keep]
    model = NodeSampler.model
    x = model.disc.coordinates[model.contact_nodes, 0] if hasattr(model.disc, "coordinates") \
        else None
    mean = normal.mean(axis=0)
    relative = (normal.max(axis=0) - normal.min(axis=0)) / (2.0 * mean)
    total = normal.sum(axis=1)
    row = {"body": body, "N_sum_swing": (total.max() - total.min()) / 2.0,
           "node_swing_max": relative.max()}
    if x is not None:
        front, back = np.isclose(x, x.max()), np.isclose(x, x.min())
        row["front_swing"] = relative[front].mean()
        row["back_swing"] = relative[back].mean()
        row["front_vs_friction"] = np.corrcoef(normal[:, front].sum(axis=1), friction)[0, 1]
    return row


def main() -> int:
    print("| block | summed N swing (N) | largest node swing | front row | back row | "
          "front row N vs friction (corr.) |\n|---|---|---|---|---|---|")
    for body in BODIES:
        r = swing(body)
        print(f"| {body} | {r['N_sum_swing']:.3g} | {100 * r['node_swing_max']:.1f}% | "
              f"{100 * r.get('front_swing', np.nan):.1f}% | {100 * r.get('back_swing', np.nan):.1f}% | "
              f"{r.get('front_vs_friction', np.nan):+.2f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
