"""A hemisphere, pole down, as a meshes.BodyMesh: the Hertz check's ball (tests and
benchmarks/hertz_ball.py) until vibrofric.meshes has shapes of its own.

gmsh (OpenCASCADE): a sphere of radius R cut by a box to its lower half, meshed in
first-order tetrahedra of size ``pole_size`` within ``fine_radius`` of the pole,
growing linearly to ``size`` at twice that distance; placed with the pole on z = 0.
Groups: "contact" the spherical face, "load" the flat top face (z = R), the volume.

A ``ring`` (Ring) refines further along a circle of the spherical face around the pole,
or along a band between two such circles: the contact patch's edge r = a, or Mindlin's
slipping annulus c < r < a (Johnson, "Contact Mechanics", 1985, eq 7.40:
c = a (1 - Q / mu P)^(1/3), the annulus a - c 0.11 a wide at Q = 0.3 mu P, 0.26 a at 0.6,
0.54 a at 0.9), without refining the whole pole region.
"""

import math
from dataclasses import dataclass
from pathlib import Path

from vibrofric import meshes
from vibrofric.meshes.refinement import GRADING


@dataclass(frozen=True)
class Ring:
    """A refinement along the circle of radius ``radius`` (m, from the pole's axis) on the
    spherical face, or with ``inner`` along the band of that face between the circles of
    radii ``inner`` and ``radius``: the element edge is ``size`` within ``half_width`` of
    the circle or band (the distance in 3-D; inside the band, the depth below the face)
    and grows beyond it by meshes.refinement's GRADING per unit distance (neighbours ~25%
    apart: well-shaped tetrahedra), up to the pole's size."""

    radius: float
    size: float
    half_width: float
    inner: float | None = None

    def name(self) -> str:
        return (f"ring-{self.radius:g}-{self.size:g}-{self.half_width:g}"
                + ("" if self.inner is None else f"-from-{self.inner:g}"))

    def distance(self, sphere_radius) -> str:
        """gmsh's MathEval expression of a point's distance to the circle (or band), m,
        on the sphere of radius ``sphere_radius`` centred at z = R (pole at z = 0): to the
        face's point at the nearest radius rho_c within the band, at the height
        z_c = R - sqrt(R^2 - rho_c^2)."""
        R, rho = sphere_radius, self.radius
        if self.inner is None:
            z_c = R - math.sqrt(R * R - rho * rho)
            return f"Sqrt((Sqrt(x*x + y*y) - {rho!r})^2 + (z - {z_c!r})^2)"
        nearest = f"Min(Max(Sqrt(x*x + y*y), {self.inner!r}), {rho!r})"
        return (f"Sqrt((Sqrt(x*x + y*y) - {nearest})^2 + "
                f"(z - {R!r} + Sqrt({R * R!r} - {nearest}^2))^2)")


def hemisphere(directory, radius=0.01, pole_size=4e-5, fine_radius=4e-4, size=None, order=1,
               drive=False, ring=None):
    """A BodyMesh of the hemisphere written to ``directory``/hemisphere-....msh (its cells
    of gmsh's ``order``: 2 for the refusal of second-order cells). With ``drive`` the flat
    top is also the "drive" group (drive.attach = "drive-group"): the tangential load of
    the Cattaneo-Mindlin checks acts where the normal load does, far from the contact.
    ``ring`` (a Ring, or None) refines along a circle or band around the pole as well."""
    size = radius / 4 if size is None else size
    name = (f"hemisphere-{radius:g}-{pole_size:g}-{fine_radius:g}-{size:g}-{order}"
            + (f"-{ring.name()}" if ring else ""))
    path = Path(directory) / f"{name}.msh"
    with meshes.gmsh_model("hemisphere") as gmsh:
        occ = gmsh.model.occ
        ball = occ.addSphere(0.0, 0.0, radius, radius)     # centre at z = R: pole at z = 0
        box = occ.addBox(-radius, -radius, radius, 2 * radius, 2 * radius, radius)
        occ.cut([(3, ball)], [(3, box)])
        occ.synchronize()
        (_, volume), = gmsh.model.getEntities(3)
        faces = [tag for _, tag in gmsh.model.getBoundary([(3, volume)], oriented=False)]
        flat = [tag for tag in faces
                if abs(gmsh.model.occ.getCenterOfMass(2, tag)[2] - radius) < 1e-9 * radius]
        curved = [tag for tag in faces if tag not in flat]
        pole = [tag for _, tag in gmsh.model.getEntities(0)
                if abs(gmsh.model.getValue(0, tag, [])[2]) < 1e-12]
        for dim, tags, tag, group in ((2, curved, 1, "contact"), (2, flat, 2, "load"),
                                      (3, [volume], 1, "body")):
            gmsh.model.addPhysicalGroup(dim, tags, tag)
            gmsh.model.setPhysicalName(dim, tag, group)
        field = gmsh.model.mesh.field
        distance = field.add("Distance")
        if pole:
            field.setNumbers(distance, "PointsList", pole)
        threshold = field.add("Threshold")
        field.setNumber(threshold, "InField", distance)
        field.setNumber(threshold, "SizeMin", pole_size)
        field.setNumber(threshold, "SizeMax", size)
        field.setNumber(threshold, "DistMin", fine_radius)
        field.setNumber(threshold, "DistMax", 2 * fine_radius + size)
        if ring is None:
            field.setAsBackgroundMesh(threshold)
        else:
            distance = ring.distance(radius)
            band = field.add("MathEval")
            field.setString(band, "F", f"{ring.size!r} + {GRADING!r} * "
                                       f"Max(0, {distance} - {ring.half_width!r})")
            finest = field.add("Min")
            field.setNumbers(finest, "FieldsList", [threshold, band])
            field.setAsBackgroundMesh(finest)
        for option in ("MeshSizeFromPoints", "MeshSizeFromCurvature", "MeshSizeExtendFromBoundary"):
            gmsh.option.setNumber(f"Mesh.{option}", 0)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(order)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    assert pole, "the sphere's pole is no vertex of its OpenCASCADE surface"
    groups = {"contact": 1, "load": 2, **({"drive": 2} if drive else {})}
    return meshes.BodyMesh(path=path, facet_groups=groups, cell_group=1,
                           volume=2.0 / 3.0 * math.pi * radius ** 3,
                           key=name + ("-drive" if drive else ""),
                           description=f"hemisphere R = {radius:g} m, {pole_size:g} m at its pole"
                                       + (f", {ring.size:g} m within {ring.half_width:g} m of "
                                          + (f"r = {ring.radius:g} m" if ring.inner is None
                                             else f"{ring.inner:g} m < r < {ring.radius:g} m")
                                          if ring else ""))


def hertz(E, nu, radius, load):
    """(a, p0): the Hertz contact radius and peak pressure of a ball of radius R pressed
    by P on a rigid flat (Johnson, "Contact Mechanics", CUP 1985, eqs 4.22-4.23):
    a = (3 P R / 4 E*)^(1/3), p0 = 3 P / (2 pi a^2), E* = E / (1 - nu^2)."""
    e_star = E / (1.0 - nu * nu)
    a = (3.0 * load * radius / (4.0 * e_star)) ** (1.0 / 3.0)
    return a, 3.0 * load / (2.0 * math.pi * a * a)


# The nodes the fit reads: nodal pressure above this fraction of the largest. A node
# near the patch's edge carries the pressure of only part of its tributary area
# (the edge cuts it), so its N_i / a_i falls below the field's; the inner ones do not.
INNER = 0.3


def hertz_fit(model):
    """(a, p0) of the Hertz field p(r)^2 = p0^2 (1 - r^2 / a^2) closest (least squares in
    p^2 against r^2, a straight line) to the preload's nodal pressures N_i / a_i of the
    nodes whose pressure is above INNER of the largest, r measured from the pole
    (x = y = 0): the patch's edge a where the line reaches 0, its centre p0."""
    import numpy as np

    xy = model.disc.coordinates[model.contact_nodes, :2]
    r2 = (xy ** 2).sum(axis=1)
    pressure = model.normal0 / model.contact_area
    inner = pressure > INNER * pressure.max()
    slope, intercept = np.polyfit(r2[inner], pressure[inner] ** 2, 1)
    return math.sqrt(-intercept / slope), math.sqrt(intercept)


def ball_model(body, scene):
    """fe_model.build_model of ``scene`` with ``body`` (a BodyMesh) as its body: the
    model's one switch of body (fe_model.body_of, block_size) pointed at it meanwhile."""
    from vibrofric.fem.model import fe_model

    saved = fe_model.body_of, fe_model.block_size
    fe_model.body_of = lambda scene, level=None: body
    fe_model.block_size = lambda scene: None
    try:
        return fe_model.build_model(scene, None)
    finally:
        fe_model.body_of, fe_model.block_size = saved
