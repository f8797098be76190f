"""A body that tips over its contact during a run.

The static check (fem/model/fe_model.py check_tipping) refuses a front-face drive that
would tip the block before any step. A user's body (its drive group high above the
contact, a slender pin, a ball not held) can still tip during the run: it turns about
the edge of its preload patch, the patch opens from the far side, and the load is
carried by the edge alone until the body falls. This module finds that state in the
contact nodes' normal forces the recorder keeps (recording.Recorder.node_normals).

A patch carries a load whose centre of pressure lies off its centroid by turning
slightly, its pressure rising toward the loaded side; an elastic rectangle's far
side opens once the centre of pressure leaves the middle third, and a body may stand
with most of its patch open. What no standing body does is carry its load on its
patch's outermost rim alone: by statics, all of the load is then at the edge it turns
about, and nothing holds the moment that turned it. So a sample is *on its edge* when
the load is carried (summed N > 0) and every closed node lies in the outer
EDGE_FRACTION of the patch's extent toward the centre of pressure:

    d = (c_N - c_0) / |c_N - c_0|      c_N the centre of pressure (N-weighted),
                                       c_0 the patch's centroid (area-weighted)
    s_i = (x_i - c_0) . d / max_j in patch (x_j - c_0) . d
    on its edge  <=>  s_i >= 1 - EDGE_FRACTION for every node i with N_i > 0

and the body *has tipped* once it stays on its edge for a whole vibration period
(the base's normal motion may open the patch for part of a cycle; a body in flight,
summed N = 0, is not on its edge). A node off the patch that closes (a ball rolling
away from it) counts with s_i > 1: a body that has rolled off its patch is reported
too.
"""

import numpy as np

from ...core.errors import BodyLeftContact

# The rim, as a fraction of the patch's extent from its centroid, inside which all
# closed nodes must lie: the outermost row of nodes, or two on a fine mesh (the coarse
# block's next row in lies at s = 0.5, 4 elements along X; 20 elements put it at 0.9).
EDGE_FRACTION = 0.1
# A patch of fewer nodes has no edge to tip about that its nodes resolve.
FEWEST_NODES = 3


def edge_samples(normals: np.ndarray, xy: np.ndarray, patch: np.ndarray,
                 area: np.ndarray) -> np.ndarray:
    """(samples,) bool: whether each sample of the nodes' normal forces ``normals``
    (samples, n) has the body on its patch's edge (module docstring); ``xy`` (n, 2) the
    nodes' plan positions, ``patch`` (n,) bool the preload's patch, ``area`` (n,) their
    areas."""
    if patch.sum() < FEWEST_NODES:
        return np.zeros(normals.shape[0], dtype=bool)
    offsets = xy - np.average(xy[patch], axis=0, weights=area[patch])
    total = normals.sum(axis=1)
    carried = total > 0.0
    centre = normals @ offsets / np.where(carried, total, 1.0)[:, None]     # c_N - c_0
    length = np.hypot(centre[:, 0], centre[:, 1])
    direction = centre / np.where(length > 0.0, length, 1.0)[:, None]
    along = direction @ offsets.T                                          # (samples, n)
    extent = along[:, patch].max(axis=1)
    rim = along >= (1.0 - EDGE_FRACTION) * extent[:, None]
    all_on_rim = np.where(normals > 0.0, rim, True).all(axis=1)
    return carried & (length > 0.0) & (extent > 0.0) & all_on_rim


def first_tipped(on_edge: np.ndarray, run_before: int, window: int) -> tuple:
    """(index, run): the first sample of ``on_edge`` that ends ``window`` samples in a row
    on the edge (counting the ``run_before`` that ended the samples scanned before), or
    None; and the run of edge samples at the end of ``on_edge``, for the next scan."""
    run = run_before
    for k, edge in enumerate(on_edge):
        run = run + 1 if edge else 0
        if run >= window:
            return k, run
    return None, run


def message(t: float, nodes_closed: int, patch_nodes: int) -> str:
    """What a run that stops on a tipped body says."""
    return (f"FE run stopped at t = {t:.6g} s: the body tipped over the edge of its contact "
            f"(for a whole vibration period its load rested on the outer "
            f"{EDGE_FRACTION:.0%} of its patch alone, {nodes_closed} of the patch's "
            f"{patch_nodes} nodes closed); attach the drive nearer the contact "
            "(drive.attach), lower the body's centre of mass or hold it "
            "(drive.holder = \"translating\")")


class TipWatch:
    """Scans the contact nodes' normal forces a run's recorder keeps, chunk by chunk, and
    raises core.errors.BodyLeftContact once the body has tipped (module docstring)."""

    def __init__(self, model, recorder, dt: float, period: float):
        self.xy = model.disc.coordinates[model.contact_nodes, :2]
        self.patch = np.asarray(model.in_contact0, dtype=bool)
        self.area = model.contact_area
        self.recorder, self.dt = recorder, dt
        self.window = max(1, int(np.ceil(period / (dt * recorder.node_stride) - 1e-9)))
        self.run = 0

    def scan(self, first: int, last: int) -> None:
        """Scan the samples kept at steps first..last (at most the recorder's ``full``
        steps since the last scan: the ring holds no more)."""
        stride = self.recorder.node_stride
        ring = self.recorder.node_ring
        kept = np.arange(-(-first // stride), last // stride + 1)
        if kept.size == 0:
            return
        normals = ring[kept % ring.shape[0]]
        on_edge = edge_samples(normals, self.xy, self.patch, self.area)
        k, self.run = first_tipped(on_edge, self.run, self.window)
        if k is not None:
            raise BodyLeftContact(message(kept[k] * stride * self.dt,
                                         int((normals[k] > 0.0).sum()), int(self.patch.sum())))
