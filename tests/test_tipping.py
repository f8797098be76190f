"""A body that tips over its contact during a run stops with one line
(fem/outputs/tipping.py): the rule on made-up patches, and a tall user body pulled
from its top."""

import re
import textwrap

import numpy as np
import pytest

from vibrofric.fem.outputs import tipping


def square_patch(n=11, half=0.01):
    """An n x n grid of nodes over a square 2 half wide, all in the patch, equal areas."""
    x = np.linspace(-half, half, n)
    xy = np.array([(a, b) for a in x for b in x])
    return xy, np.ones(len(xy), dtype=bool), np.ones(len(xy))


def test_a_standing_patch_is_not_on_its_edge():
    """Uniform pressure, and a linear one whose back half is open (the centre of pressure
    a third of the way to the front: a body standing under a moment), are not on the edge;
    neither is a body in flight (no load)."""
    xy, patch, area = square_patch()
    uniform = np.ones(len(xy))
    x = xy[:, 0] / 0.01
    linear = np.clip(x, 0.0, None)     # closed over the front half only
    flight = np.zeros(len(xy))
    assert not tipping.edge_samples(np.array([uniform, linear, flight]), xy, patch, area).any()


@pytest.mark.parametrize("direction", [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0)])
def test_a_load_on_the_outer_row_alone_is_on_its_edge(direction):
    """Only the outermost row toward ``direction`` closed: on the edge, whichever edge;
    with the next row closed too (20% of the extent in), not."""
    xy, patch, area = square_patch()
    along = xy @ np.array(direction) / 0.01
    row = np.where(along > 0.999, 1.0, 0.0)
    two_rows = np.where(along > 0.799, 1.0, 0.0)
    assert tipping.edge_samples(np.array([row, two_rows]), xy, patch, area).tolist() == [True,
                                                                                        False]


def test_a_body_rolled_off_its_patch_is_on_its_edge():
    """Nodes beyond the patch carrying the load (a ball rolled away from its preload's
    patch) count as past the edge."""
    xy, _, area = square_patch()
    patch = np.abs(xy).max(axis=1) <= 0.004
    beyond = np.where(xy[:, 0] > 0.006, 1.0, 0.0)
    assert tipping.edge_samples(beyond[None, :], xy, patch, area).tolist() == [True]


def test_tipping_needs_a_whole_period_on_the_edge():
    """first_tipped counts runs across scans, and a sample off the edge restarts it."""
    edge = np.array([True, True, False, True, True, True])
    assert tipping.first_tipped(edge, 0, 3) == (5, 3)
    assert tipping.first_tipped(edge[:2], 0, 3) == (None, 2)
    assert tipping.first_tipped(edge[:1], 2, 3) == (0, 3)


TALL = """\
// a tall steel box, its drive and load on its top face
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.02, 0.02, 0.08};
Physical Volume("part") = {1};
Physical Surface("contact") = {5};
Physical Surface("load") = {6};
Physical Surface("drive") = {6};
"""


def test_a_tall_body_pulled_from_its_top_tips_and_stops_with_one_line(tmp_path, capsys):
    """A 20 x 20 x 80 mm box pulled from its top (drive.attach = "drive-group") with mu =
    0.8: the drive's moment about the front edge, F_d 0.08 m, passes the load's F_N 0.01 m
    at F_d = F_N / 8, far below the sliding force 0.8 F_N, so the box tips before it
    slides. The run stops with one line naming it, exit 3, nothing written."""
    pytest.importorskip("dolfinx")
    from vibrofric.cli import EXIT_NUMERICAL, main

    (tmp_path / "tall.geo").write_text(textwrap.dedent(TALL))
    scene = tmp_path / "tall.toml"
    scene.write_text(textwrap.dedent("""\
        [body]
        mesh = "tall.geo"
        mass = 0.2512            # kg: steel, 7850 kg/m^3 x 3.2e-5 m^3
        [contact]
        law = "dahl"
        mu = 0.8
        F_N = 20.0
        k_t = 80e6
        [drive]
        attach = "drive-group"
        k_d = 96068.0
        v_d = 0.05               # m/s: F_d reaches F_N / 8 = 2.5 N after 0.5 ms
        [vibration]
        f = 4000.0
        k_v = 0.0
        [time]
        T = 0.01
        dt = 1e-7
        method = "transient"
        error_estimate = false
        """))
    out = tmp_path / "never"
    code = main(["run", str(scene), "--set", "fem.integrator=explicit", "--out", str(out)])
    err = [line for line in capsys.readouterr().err.splitlines()
           if line.startswith("vibrofric:") and "compiling" not in line]
    assert code == EXIT_NUMERICAL and not out.exists()
    assert len(err) == 1 and "tipped over the edge of its contact" in err[0], err
    stopped = float(re.search(r"t = ([0-9.e+-]+) s", err[0]).group(1))
    assert 5e-4 < stopped < 1e-2
