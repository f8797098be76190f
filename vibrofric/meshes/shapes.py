"""The built-in bodies other than the block, drawn in gmsh (OpenCASCADE) and meshed with
first-order tetrahedra, already placed: the point or line that touches the base first
lies on z = 0, X slides, Z points up.

    cylinder  a pin standing on its flat end (radius, height), the end's edge rounded
              with edge_radius (0: a sharp edge). contact: the flat end and the
              rounding; load: the top end.
    ball      a sphere (radius); contact: the lower cap within CAP_ANGLE of the pole;
              load: the upper cap, its mirror image. With hemisphere = true the lower
              half only, pole down; load: its flat equator face.
    roller    a cylinder lying on its side, its axis along Y (radius, length): a line
              contact along Y, sliding across it in X. contact: the lower half of the
              side; load: the upper half, so that every slice along Y is loaded alike,
              as the line contact is (a load on the end faces would bend the roller
              along Y and press its line unevenly).

No shape has a ``drive`` group: the drive spring attaches to the contact candidates
(the lumped model's setting). The cut planes that separate the groups' surfaces stay
inside the volume as conforming interfaces; the volume is one physical group.
"""

import math

import numpy as np

from . import refinement

SHAPES = ("cylinder", "ball", "roller")
# the half-angle of the ball's contact cap, around the pole: its rim (R sin 30 deg = R/2
# from the axis) is far outside any elastic Hertz patch (a < R/10 below yield), so the
# patch and the base's rocking stay on the candidates
CAP_ANGLE = math.radians(30.0)

CONTACT, LOAD = 1, 2   # facet group tags
VOLUME = 1             # cell group tag


def dimensions(body) -> dict:
    """The shape's lengths from the scene's Body, by name (m)."""
    if body.shape == "cylinder":
        return {"radius": body.radius, "height": body.height, "edge_radius": body.edge_radius}
    if body.shape == "ball":
        return {"radius": body.radius, "hemisphere": bool(body.hemisphere)}
    if body.shape == "roller":
        return {"radius": body.radius, "length": body.length}
    raise ValueError(f"body.shape {body.shape!r} is not one of {', '.join(SHAPES)}")


def volume(body) -> float:
    """The shape's volume in closed form, m^3 (the meshed one is a little smaller: its
    flat facets cut the curved surface's chords)."""
    R = body.radius
    if body.shape == "ball":
        return (2.0 if body.hemisphere else 4.0) / 3.0 * math.pi * R ** 3
    if body.shape == "roller":
        return math.pi * R ** 2 * body.length
    if body.shape == "cylinder":
        # the rounding of radius r takes off the ring swept by the corner's spandrel (the
        # square r x r less a quarter disk): Pappus, its area (1 - pi/4) r^2 times the path
        # of its centroid, which lies r (10 - 3 pi) / (12 - 3 pi) in from the corner
        r = body.edge_radius
        corner_area = (1.0 - math.pi / 4.0) * r * r
        centroid = R - r * (10.0 - 3.0 * math.pi) / (12.0 - 3.0 * math.pi)
        return math.pi * R * R * body.height - 2.0 * math.pi * centroid * corner_area
    raise ValueError(f"body.shape {body.shape!r} is not one of {', '.join(SHAPES)}")


def patch_radius(body, normal_load) -> float | None:
    """The Hertz contact radius of the ball under ``normal_load`` N, m (the size field
    resolves it at "fine" and "finer": meshes/refinement.py); None otherwise. The pin's
    flat end is in contact whole. The roller's line contact is a strip whose half-width
    (refinement.hertz_line_half_width) is about 10 um under tens of N on steel: isotropic
    tetrahedra that small along its whole length would be millions, so the roller is
    refined by the level alone."""
    if normal_load is None or normal_load <= 0 or body.shape != "ball":
        return None
    return refinement.hertz_point_radius(normal_load, body.radius, body.E, body.nu)


# The distance to the points that touch first, as gmsh MathEval expressions.
_FIRST_TOUCH = {
    "ball": "Sqrt(x*x + y*y + z*z)",   # the pole, at the origin
    "roller": "Sqrt(x*x + z*z)",       # the line x = z = 0 along Y
    "cylinder": "z",                   # the flat end z = 0
}


def build(gmsh, body, level: str, normal_load=None) -> tuple:
    """Draw and mesh the shape in the current (empty) gmsh model; return (h_contact, h_body)."""
    occ, model = gmsh.model.occ, gmsh.model
    R = float(body.radius)
    if body.shape == "ball":
        _ball(occ, R, bool(body.hemisphere))
    elif body.shape == "cylinder":
        _pin(occ, R, float(body.height), float(body.edge_radius))
    elif body.shape == "roller":
        _roller(gmsh, R, float(body.length))
    else:
        raise ValueError(f"body.shape {body.shape!r} is not one of {', '.join(SHAPES)}")
    occ.synchronize()
    _groups(model, body)
    h_contact, h_body = refinement.sizes(level, R, patch_radius(body, normal_load))
    refinement.distance_field(gmsh, _FIRST_TOUCH[body.shape], h_contact, h_body)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)   # Delaunay
    gmsh.option.setNumber("Mesh.ElementOrder", 1)
    model.mesh.generate(3)
    return h_contact, h_body


def _ball(occ, R: float, hemisphere: bool) -> None:
    """A sphere (or its lower half) resting on its pole at the origin, cut by the contact
    cap's disk (and, whole, the load cap's)."""
    if hemisphere:
        sphere = occ.addSphere(0.0, 0.0, R, R, angle1=-math.pi / 2, angle2=0.0)
    else:
        sphere = occ.addSphere(0.0, 0.0, R, R)
    rim = R * math.sin(CAP_ANGLE)
    disks = [occ.addDisk(0.0, 0.0, R * (1.0 - math.cos(CAP_ANGLE)), rim, rim)]
    if not hemisphere:
        disks.append(occ.addDisk(0.0, 0.0, R * (1.0 + math.cos(CAP_ANGLE)), rim, rim))
    occ.fragment([(3, sphere)], [(2, d) for d in disks])


def _pin(occ, R: float, H: float, r: float) -> None:
    """A cylinder on its flat end at z = 0, that end's edge rounded with radius r."""
    pin = occ.addCylinder(0.0, 0.0, 0.0, 0.0, 0.0, H, R)
    if r > 0.0:
        occ.synchronize()
        edge = [c for _, c in occ.getEntities(1) if occ.getBoundingBox(1, c)[5] < 1e-3 * H]
        occ.fillet([pin], edge, [r])


def _roller(gmsh, R: float, L: float) -> None:
    """A cylinder of axis Y through (0, 0, R), cut along its horizontal and vertical
    planes through the axis, so that its bottom line x = z = 0 is an edge of the mesh."""
    occ = gmsh.model.occ
    roller = occ.addCylinder(0.0, -L / 2, R, 0.0, L, 0.0, R)
    horizontal = occ.addRectangle(-2 * R, -L, R, 4 * R, 2 * L)
    vertical = occ.addRectangle(-L, -2 * R, 0.0, 2 * L, 4 * R)   # drawn in XY, turned to YZ
    occ.rotate([(2, vertical)], 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, math.pi / 2)
    occ.translate([(2, vertical)], 0.0, 0.0, R)
    occ.fragment([(3, roller)], [(2, horizontal), (2, vertical)])
    occ.synchronize()
    # the cut planes' pieces outside the roller bound no volume
    outside = [(2, s) for _, s in gmsh.model.getEntities(2)
               if len(gmsh.model.getAdjacencies(2, s)[0]) == 0]
    occ.remove(outside, recursive=True)


def _groups(model, body) -> None:
    """The volume, and the contact and load facets among the boundary's surfaces (those
    next to one volume: the cut planes inside lie between two)."""
    volumes = [tag for _, tag in model.getEntities(3)]
    model.addPhysicalGroup(3, volumes, VOLUME)
    model.setPhysicalName(3, VOLUME, "body")
    boxes = {s: np.array(model.getBoundingBox(2, s)) for _, s in model.getEntities(2)
             if len(model.getAdjacencies(2, s)[0]) == 1}
    R = float(body.radius)
    eps = 1e-3 * R
    if body.shape == "ball":
        contact = [s for s, b in boxes.items() if b[2] < eps]
        if body.hemisphere:
            load = [s for s, b in boxes.items() if b[2] > R - eps]
        else:
            load = [s for s, b in boxes.items() if b[5] > 2 * R - eps]
    elif body.shape == "cylinder":
        contact = [s for s, b in boxes.items() if b[5] < body.edge_radius + eps]
        load = [s for s, b in boxes.items() if b[2] > body.height - eps]
    else:  # roller: the side's pieces span its length; the ends' are flat in Y
        side = {s: b for s, b in boxes.items() if b[4] - b[1] > body.length - eps}
        contact = [s for s, b in side.items() if b[5] < R + eps]
        load = [s for s, b in side.items() if b[2] > R - eps]
    for name, tag, surfaces in (("contact", CONTACT, contact), ("load", LOAD, load)):
        model.addPhysicalGroup(2, surfaces, tag)
        model.setPhysicalName(2, tag, name)
