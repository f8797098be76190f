"""The holder (drive.holder = "translating", fem/model/holder.py): the shipped ball pulled
at its top, held and not, statically on its preloaded patch; the key's refusal."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from vibrofric import scene as scenes
from vibrofric.scene.errors import SceneError

SCENES = "scenes"


pytestmark = pytest.mark.usefixtures("own_model_cache")   # conftest.py


def test_a_holder_needs_an_attachment_with_a_group():
    ball = scenes.load(f"{SCENES}/ball.toml")
    with pytest.raises(SceneError) as refused:
        ball.with_values({"drive.attach": "contact-plane", "drive.holder": "translating"})
    assert refused.value.key == "drive.holder"
    with pytest.raises(SceneError) as refused:
        ball.with_values({"drive.holder": "glued"})
    assert refused.value.key == "drive.holder"


def pulled_top(model, k_t):
    """(tilt about Y, rad; mean X displacement, m) of the drive's group under a 1 N pull
    along X spread on it by its weights, the preload's patch stuck: k_t a_i / A_0 in X and
    Y, the penalty in Z (the static problem of benchmarks/fe_body_vs_lumped.py)."""
    springs = np.zeros(model.dofs)
    patch = model.contact_nodes[model.in_contact0]
    springs[3 * patch] = springs[3 * patch + 1] = k_t * model.area_share[model.in_contact0]
    springs[3 * patch + 2] = model.penalty_share[model.in_contact0]
    pull = np.zeros(model.dofs)
    pull[3 * model.attach_nodes] = model.attach_weights
    u = spla.spsolve((model.stiffness + sp.diags(springs)).tocsc(), pull)
    x = model.disc.coordinates[model.attach_nodes, 0]
    w = model.attach_weights
    # u_z = c - theta (x - x_bar) by weighted least squares: theta about Y
    centred = x - w @ x
    tilt = -(w * centred) @ u[3 * model.attach_nodes + 2] / ((w * centred) @ centred)
    return tilt, w @ u[3 * model.attach_nodes]


@pytest.mark.parametrize("holder", ["none", "translating"])
def test_a_held_ball_does_not_turn_under_a_pull_at_its_top(holder):
    pytest.importorskip("dolfinx")
    pytest.importorskip("gmsh")
    from vibrofric.fem.model import fe_model
    from vibrofric.fem.model import holder as holders

    scene = scenes.load(f"{SCENES}/ball.toml").with_values(
        {"drive.attach": "load-group", "drive.holder": holder})
    model = fe_model.build_model(scene, None)
    tilt, x_top = pulled_top(model, scene.contact.k_t)
    nodes, w = model.attach_nodes, model.attach_weights
    xyz = model.disc.coordinates[nodes]
    height = w @ xyz[:, 2]          # the pull's lever arm about the contact (z = 0)
    if holder == "none":
        # Nothing resists the moment but the patch's few penalty springs: the ball rolls
        # about its contact, and the top's X motion is its turning, height x tilt (measured
        # 99%; a ball that slid instead of rolling would give ~0)
        assert tilt * height > 0.9 * x_top
        return
    # Held, the ties carry the moment 1 N x height, together with the patch (in
    # parallel), so that the tilt is at most that moment over the ties' own tilting
    # stiffness k_hold sum w_a (x_a - x_bar)^2 (holder.py); 1.1 allows for the ball's
    # elastic compliance between the ties and its contact (measured: 0.97 of the bound,
    # 1e-3 of the unheld ball's tilt)
    unheld = scene.with_values({"drive.holder": "none"})
    k_hold = holders.hold_stiffness(fe_model.build_model(unheld, None).stiffness, nodes)
    tilting = k_hold * w @ (xyz[:, 0] - w @ xyz[:, 0]) ** 2
    assert 0.0 < tilt <= 1.1 * height / tilting


def test_the_held_bodys_turn_is_no_gauge_of_its_steady_cycle():
    """The steady-cycle solver takes out the rigid motions nothing restrains (the turn
    about Z, the translation in Y: fem/integrators/cycle_map.py). The holder's ties resist
    the turn: a rigid turn of the held ball stores energy in its stiffness (the ties'
    k_hold sum w_a r_a^2 per rad^2) and none in the unheld one's (rounding: 2e-16 of it
    measured, 1e-9 allowed), so the solver keeps the turn in the state of a held body;
    taking it out had run the held pin to a spurious orbit (F_dv/F_d0 0.063 against
    0.777)."""
    from vibrofric.fem.integrators.cycle_map import unrestrained_motions
    from vibrofric.fem.model import fe_model

    scene = scenes.load(f"{SCENES}/ball.toml")
    assert scene.drive.holder == "translating"
    assert unrestrained_motions(scene) == ("y",)
    unheld = scene.with_values({"drive.holder": "none"})
    assert unrestrained_motions(unheld) == ("y", "turn")
    energies = []
    for s in (scene, unheld):
        model = fe_model.build_model(s, None)
        xyz = model.disc.coordinates
        centre = model.attach_weights @ xyz[model.attach_nodes]
        turn = np.zeros_like(xyz)
        turn[:, 0], turn[:, 1] = -(xyz[:, 1] - centre[1]), xyz[:, 0] - centre[0]
        turn = turn.ravel()
        energies.append(turn @ (model.stiffness @ turn))
    held, free = energies
    assert held > 0.0 and abs(free) <= 1e-9 * held
