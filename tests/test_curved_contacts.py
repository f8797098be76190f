"""The FE model against the closed forms of curved elastic contacts (vibrofric/analytic/
contact_mechanics.py; docs/validation.md, "Curved contacts"): a held hemisphere pulled
tangentially (Cattaneo-Mindlin: tests/pulled_ball.py), cycled (Mindlin-Deresiewicz), and
the roller's line contact (Hertz). On the coarse meshes; benchmarks/cattaneo_mindlin.py,
benchmarks/mindlin_deresiewicz.py and benchmarks/roller_hertz.py refine them."""

import pytest

pytest.importorskip("dolfinx")

import pulled_ball as pb  # noqa: E402

from vibrofric.analytic import contact_mechanics as cm  # noqa: E402

# The fast mesh: 150 um at the pole within 1.2 mm (a = 0.515 mm: 3.4 elements across the
# patch's radius, ~40 nodes closed), 1644 nodes, 2.1e-8 s steps.
POLE = 1.5e-4


pytestmark = pytest.mark.usefixtures("own_model_cache")   # conftest.py


@pytest.fixture(scope="module")
def body(tmp_path_factory):
    """The hemisphere on the fast mesh, its top the drive group."""
    return pb.ball(tmp_path_factory.mktemp("ball"), POLE)


@pytest.fixture(scope="module")
def pulls(body):
    """(body, stuck, pulled): the held ball's stuck pull (mu = 10) and its pull at mu = 0.5."""
    dt = pb.stable_step(POLE)
    stuck = pb.run(body, pb.pull_scene(pb.STUCK_MU, pb.PULL_TIME, dt))
    pulled = pb.run(body, pb.pull_scene(pb.MU, pb.PULL_TIME, dt))
    return body, stuck, pulled


@pytest.mark.slow
def test_the_held_ball_s_displacement_is_cattaneo_mindlin_s(pulls):
    """x(Q) - (C_stuck - C_0) Q against delta(Q) on the quasi-static curves
    (tests/pulled_ball.py delta_errors) within Cattaneo-Mindlin's 5% on the coarse mesh
    (measured -1.4%, -1.7%, -0.8% at q = 0.3, 0.6, 0.9; without averaging out the ball's
    ringing, -6.7% at 0.3); and the slip's own part x(Q) - C_stuck Q within 10% at q = 0.9
    (measured -3.3%; at 0.3 and 0.6 the coarse mesh's discrete slip front is 25% and 13%
    short of Mindlin's thin annulus: benchmarks/cattaneo_mindlin.py)."""
    _, stuck, pulled = pulls
    # the stuck contact is Mindlin's no-slip one plus the bulk's shear: C_stuck above C_0,
    # by the bulk's share of the 10 mm hemisphere (measured 10.0%): 25% would be a mesh
    # whose stuck patch is much softer than Mindlin's
    assert 1.0 < pb.stuck_compliance(stuck) / pb.no_slip_compliance() < 1.25
    errors = pb.delta_errors(pulled, stuck, (0.3, 0.6, 0.9))
    for q, (total, _) in errors.items():
        assert abs(total) < 0.05, (q, total)
    assert abs(errors[0.9][1]) < 0.10, errors[0.9]


@pytest.mark.slow
def test_the_held_ball_s_stick_radius_is_cattaneo_mindlin_s(pulls):
    """The stick radius at the pull's end (Q = 0.94 mu P, c = 0.4 a) and at Q = 0.5 mu P
    (c = 0.79 a) against a (1 - q)^(1/3): read from the nodes' states
    (pulled_ball.stick_radius) within half a node spacing (75 um, 0.15 a), the rule's
    resolution (measured -1.0% and -1.1%, 4 and 3 um, at q = 0.5 and 0.8); and at
    Q = 0.5 mu P from the stuck nodes' tractions (pulled_ball.stick_radius_fit) within
    Cattaneo-Mindlin's 5% (measured -4.8% on this mesh, benchmarks/cattaneo_mindlin.py:
    the bound is the requirement's, met with little to spare), the fitted field's slope
    within 30% of Mindlin's -1 (measured -1.26)."""
    body, _, pulled = pulls
    a = pb.hertz_radius()
    Q = pb.MU * pb.LOAD * 0.5
    to_q = pb.run(body, pb.pull_scene(pb.MU, pb.time_at(pulled, Q), pb.stable_step(POLE)))
    for run in (pulled, to_q):
        Q_end = float(run.series.F_d[-1])
        c = cm.stick_radius(Q_end, pb.MU, pb.LOAD, a)
        assert abs(pb.stick_radius(run) - c) < 0.5 * POLE, (Q_end, pb.stick_radius(run), c)
        assert 0.0 < pb.stick_radius(run) < a
    c = cm.stick_radius(float(to_q.series.F_d[-1]), pb.MU, pb.LOAD, a)
    c_fit, slope = pb.stick_radius_fit(to_q)
    assert c_fit == pytest.approx(c, rel=0.05)
    assert -1.3 < slope < -0.7


@pytest.mark.slow
def test_the_roller_s_strip_at_mid_length_is_hertz_s():
    """Plane-strain Hertz's half-width at mid-length within 3% (the closed form's
    criterion) at fem.mesh = "medium" (a = 0.54 mm, the contact edge R / 24 = 0.21 mm):
    measured -2.8%, from -16% at "coarse" (benchmarks/roller_hertz.py); the peak pressure
    within 5% (measured +2%): the strip's centre node carries the field's top."""
    import roller
    from vibrofric.fem.model import fe_model

    a, p0 = roller.hertz()
    model = fe_model.build_model(roller.roller_scene(".", "medium"), None)
    a_fit, p0_fit = roller.mid_length_fit(model)
    assert a_fit == pytest.approx(a, rel=0.03)
    assert p0_fit == pytest.approx(p0, rel=0.05)


@pytest.mark.slow
def test_the_held_ball_s_cycle_dissipates_mindlin_deresiewicz_s_energy(body):
    """The loop's area over a steady cycle at Q* ~ 0.6 mu P against Johnson's eq 7.59 at
    the measured Q* (pulled_ball.cycle_scene, cycle_dissipation). This fast mesh does NOT
    meet the closed form's 10%: it dissipates 30% more at Q* = 0.59 mu P, under one of its
    elements across Mindlin's 136 um slipping annulus. Meshes refined over the annulus
    (pulled_ball.ball's ring, over the whole annulus with annulus_q) converge within it
    (benchmarks/mindlin_deresiewicz.py --ring --annulus,
    docs/validation.md): at Q* = 0.57 mu P +5.5%, +3.8%, +2.7% and +1.7% with 70, 50, 35
    and 25 um across the annulus; at 0.88, +0.6%, -0.0% and +0.1% (70, 50, 35 um); at
    0.28 (the ring at r = a) +10.9%, +6.8% and +5.1% with 35, 25 and 20 um, 2 to 11
    minutes a run. The bounds hold this mesh's measured state, the loop above eq 7.59 and
    within 50% of it, so that a change to the contact that moves the loop shows; a loop
    below eq 7.59 would be a contact that sticks where Mindlin's slips."""
    result = pb.run(body, pb.cycle_scene(0.6, pb.stable_step(POLE)))
    Q, W = pb.cycle_dissipation(result)
    assert 0.5 < Q / (pb.MU * pb.LOAD) < 1.0      # the cycle's amplitude as aimed
    closed = cm.mindlin_deresiewicz_dissipation(Q, pb.MU, pb.LOAD, pb.hertz_radius(), pb.E, pb.NU)
    assert closed < W < 1.5 * closed


def contact_face_edges(body):
    """(edge, r): the mean edge (m) of each triangle of ``body``'s contact face and its
    centre's radius from the pole's axis (m)."""
    import meshio
    import numpy as np

    mesh = meshio.read(body.path)
    triangles = np.concatenate([cells.data for cells, tags in
                                zip(mesh.cells, mesh.cell_data["gmsh:physical"])
                                if cells.type == "triangle" and tags[0] == 1])
    corners = mesh.points[triangles]
    edges = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2).mean(axis=1)
    return edges, np.hypot(*corners.mean(axis=1)[:, :2].T)


def test_a_ring_refines_the_ball_s_contact_face_along_the_patch_s_edge(tmp_path):
    """pulled_ball.ball with a ring (hemisphere.Ring): the contact face's triangles within
    the ring's band about r = a take the ring's size; the pole's stay the pole's. Only gmsh
    and meshio run (seconds)."""
    a, ring = pb.hertz_radius(), 5e-5
    half_width = pb.RING_HALF_WIDTH * a

    def mean_edges(body):
        """(in the band, near the pole): the contact face's mean triangle edge, m."""
        edges, r = contact_face_edges(body)
        return edges[abs(r - a) < half_width].mean(), edges[r < 0.3 * a].mean()

    band, pole = mean_edges(pb.ball(tmp_path, POLE, ring))
    plain_band, _ = mean_edges(pb.ball(tmp_path, POLE))
    # gmsh's edges scatter about the size asked for (+-20-30%); the ring's band is a third
    # of the pole's size, the pole beyond the ring's grading (0.25 per unit distance from
    # the band: >= 0.12 mm at r < 0.3 a) at least twice the ring's
    assert band < 1.3 * ring < 0.5 * plain_band
    assert pole > 2.0 * ring


def test_a_ring_over_the_annulus_refines_the_whole_of_mindlin_s_slipping_annulus(tmp_path):
    """pulled_ball.ball with a ring over the annulus at q = 0.9 (annulus_q: the band from
    Mindlin's stick radius c = a (1 - q)^(1/3) = 0.46 a to a): the contact face's
    triangles across the whole annulus take the ring's size, where the ring at r = a alone
    (0.88 a to 1.12 a) leaves its inner part graded up towards the pole's. Only gmsh and
    meshio run (seconds)."""
    a, ring, q = pb.hertz_radius(), 5e-5, 0.9
    c = cm.stick_radius(q * pb.MU * pb.LOAD, pb.MU, pb.LOAD, a)

    def inner_annulus(body):
        """The mean triangle edge between c and 0.7 a (beyond the ring at r = a's reach), m."""
        edges, r = contact_face_edges(body)
        return edges[(r > c) & (r < 0.7 * a)].mean()

    over_annulus = inner_annulus(pb.ball(tmp_path, POLE, ring, q))
    # gmsh's edges scatter about the size asked for (+-20-30% each; the mean of the
    # hundreds of triangles here within 5%: measured 49 um for 50 um asked); the ring at
    # r = a alone grades up from 50 um at 0.88 a by 0.25 per unit distance (measured 78 um)
    assert over_annulus < 1.2 * ring
    assert inner_annulus(pb.ball(tmp_path, POLE, ring)) > 1.4 * ring
