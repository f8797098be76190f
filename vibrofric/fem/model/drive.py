"""The drive: a spring k_d from the point B moving at v_d to the body (eq 17).

The spring attaches to a set of nodes A with weights w_a (sum 1). Its length
change is the weighted mean X displacement of those nodes since the preloaded
state, and its force is spread over the same nodes by the same weights:

    x_A = sum_a w_a (u_x,a - u0_x,a),      F_d = k_d (v_d t - x_A)      (eq 17)
    f_x,a = w_a F_d

(the same weights both ways make the spring the symmetric rank-one stiffness
k_d w w^T: it stores energy k_d (v_d t - x_A)^2 / 2 and nothing else).

With drive.mode = "velocity" (prescribed sliding, as the lumped model's
prescribed mode and the closed-form literature) there is no spring: x_A = v_d t
exactly (after a start, prescribed_position), and F_d is the constraint's
force, spread by the same weights (each integrator solves for it: integrators/explicit.py,
contact_solve.contact_residual).

Where it attaches (scene drive.attach, docs/model.md section 5), a facet group
of the body's mesh (meshes/body.py), its nodes weighted by tributary area:

contact-plane
    the group "contact", the contact candidates: on the block a uniform
    traction on the plane z = 0, where the friction acts too, so the drive and
    friction make no tilting moment: the lumped model's setting, used to validate.
front-face
    the group "front", the block's front face (x = L_x): a uniform traction
    whose resultant acts at the face's centre, mid-height L_z / 2; with the
    friction at z = 0 it tilts the block and makes the contact pressure
    non-uniform, which the lumped model lacks.
drive-group
    the mesh's own group "drive", wherever its author put it.
load-group
    the group "load", where the normal load presses: a tribometer's holder, which
    presses the body down and pulls it along at the same place (the built-in
    shapes' top; with drive.holder = "translating" it moves without turning,
    holder.py).
"""

import numpy as np
from numba import njit

from ...core.errors import DriveHasNoAttachment
from ...friction_law.contract import FASTMATH

ATTACH_GROUPS = {"contact-plane": "contact", "front-face": "front", "drive-group": "drive",
                 "load-group": "load"}

# A prescribed drive reaches v_d in this time, at constant acceleration. Started
# at v_d in one step, the block is given v_d / dt: at 1e-6 s a force of 250 N on
# the 0.5 kg block, at the contact plane while its inertia sits at mid-height,
# which tipped a 100x stiffer block off its contact within 10 us. Over
# START_TIME the push is m v_d / START_TIME = 2.5 N, below its friction (5.5 N),
# and the start spans ten periods of such a block's 100 kHz rocking. The lumped
# stepper's rigid body starts at v_d (analytic/coupled.py); both slide at v_d
# long before the vibration starts (scene vibration.t_on).
START_TIME = 1e-4


@njit(cache=True, error_model="numpy")
def prescribed_position(t, v_d):
    """x_A(t) of a prescribed drive: v_d t^2 / (2 START_TIME) up to START_TIME, then
    v_d (t - START_TIME / 2)."""
    if t < START_TIME:
        return 0.5 * v_d * t * t / START_TIME
    return v_d * (t - 0.5 * START_TIME)


def attachment(scene, face_area: dict, body: str = ""):
    """(nodes, weights) of the drive's attachment: its group's nodes by area share.
    Refuses (DriveHasNoAttachment) a body whose mesh lacks the group (``body`` names it)."""
    group = ATTACH_GROUPS[scene.drive.attach]
    if group not in face_area:
        raise DriveHasNoAttachment(f"the body's mesh ({body}) has no facet group {group!r} for "
                                   f"drive.attach = {scene.drive.attach!r}; use \"contact-plane\"")
    area = face_area[group]
    nodes = np.flatnonzero(area > 0.0).astype(np.int64)
    return nodes, area[nodes] / area[nodes].sum()


@njit(cache=True, error_model="numpy")
def attachment_position(u, reference, nodes, weights):
    """(x_A, y_A): the weighted mean X and Y displacement of the attachment nodes,
    measured from the ``reference`` (the preloaded state)."""
    x = y = 0.0
    for k in range(nodes.shape[0]):
        d = 3 * nodes[k]
        x += weights[k] * (u[d] - reference[d])
        y += weights[k] * (u[d + 1] - reference[d + 1])
    return x, y


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def attachment_xy(q, index, weights_x, weights_y):
    """(x_A, y_A) = (d_x^T q, d_y^T q) in a system's coordinates (generalized_alpha.LinearSystem:
    the drive's entries of q and their weights in X and Y)."""
    x = y = 0.0
    for k in range(index.shape[0]):
        x += weights_x[k] * q[index[k]]
        y += weights_y[k] * q[index[k]]
    return x, y


def drive_stiffness_action(k_d, nodes, weights, dofs):
    """The drive spring's stiffness k_d w w^T as a function u -> K_d u (for the stable step)."""
    index = 3 * nodes

    def action(u):
        out = np.zeros(dofs)
        out[index] = k_d * weights * np.dot(weights, u[index])
        return out

    return action
