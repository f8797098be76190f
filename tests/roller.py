"""The roller (meshes' "roller" shape: a cylinder on its side, axis along Y, centred on
y = 0) pressed on the base, its line contact at mid-length against plane-strain Hertz
(tests/test_curved_contacts.py, benchmarks/roller_hertz.py).

Material and load make the strip resolvable: R = 5 mm, L = 10 mm, P = 100 N (P' = P / L =
1e4 N/m), E = 0.2 GPa, nu = 0.3 (Hertz is linear elastic: any E gives the same shape):
a = 2 sqrt(P' R / pi E*) = 0.54 mm (Johnson eq 4.43), a / R = 0.11.
"""

import math

import numpy as np

from vibrofric import scene as scenes
from vibrofric.analytic import contact_mechanics as cm

RADIUS, LENGTH, LOAD, E, NU = 5e-3, 1e-2, 100.0, 2e8, 0.3
# the slice at mid-length that is read: 1 mm, a tenth of the length, 4.5 mm (8 a) from
# either end, where the ends' own stress field (Johnson section 4.3, the edge effects of
# a finite cylinder reach ~ a few a) has died out
BAND = 1e-3
# the nodes the fit reads: nodal pressure above this fraction of the slice's largest (as
# tests/hemisphere.py INNER: the edge nodes' tributary areas are cut by the strip's edge)
INNER = 0.3
SCENE = "scenes/longitudinal.toml"


def roller_scene(root, level):
    return scenes.load(f"{root}/{SCENE}").with_values({
        "body.shape": "roller", "body.radius": RADIUS, "body.length": LENGTH, "body.E": E,
        "body.nu": NU, "body.density": 7850.0, "body.gravity": 0.0, "contact.F_N": LOAD,
        "fem.mesh": level})


def hertz():
    """(a, p0) of the line contact at P' = P / L (Johnson eq 4.43)."""
    return (cm.line_half_width(LOAD / LENGTH, RADIUS, E, NU),
            cm.line_peak_pressure(LOAD / LENGTH, RADIUS, E, NU))


def mid_length_fit(model):
    """(a, p0) of the field p(x)^2 = p0^2 (1 - x^2 / a^2) closest (least squares in p^2
    against x^2) to the preload's nodal pressures N_i / a_i of the nodes within BAND / 2
    of y = 0 whose pressure is above INNER of the slice's largest."""
    xyz = model.disc.coordinates[model.contact_nodes]
    pressure = model.normal0 / model.contact_area
    mid = np.abs(xyz[:, 1]) < BAND / 2
    inner = mid & (pressure > INNER * pressure[mid].max())
    slope, intercept = np.polyfit(xyz[inner, 0] ** 2, pressure[inner] ** 2, 1)
    return math.sqrt(-intercept / slope), math.sqrt(intercept)
