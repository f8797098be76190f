"""fem.mesh levels as element sizes for meshes gmsh draws freely (the built-in shapes, a
user's .geo or STEP file), and the size field that refines them toward the contact.

The block keeps its element counts (block.LEVELS). Any other body gets two sizes from
a level and the body's length scale ``scale`` (a shape's radius; for a user's part,
half the cube root of its bounding box's volume):

    h_body     the element edge away from the contact, scale / BODY_DIVISIONS[level]
    h_contact  the edge at the points that touch the base first, scale /
               CONTACT_DIVISIONS[level]; at "fine" and "finer", where the normal load
               is known, small enough for PATCH_ELEMENTS elements across the Hertz
               contact radius a as the edge grows (``patch_size``; Johnson, Contact Mechanics, 1985, eqs 4.22-4.23 and 4.45-4.48: a
               patch resolved by about 5 elements across its radius gives the Hertz
               pressure's resultant and peak within a few per cent)

and the edge grows from h_contact with the distance d from those points at the rate
GRADING, up to h_body: h(d) = min(h_body, h_contact + GRADING d). "coarse" is
quick (a 10 mm ball: about 1,000 nodes); "fine" resolves the patch.
"""

import contextlib
import math

# element edges per length scale, away from the contact and at it
BODY_DIVISIONS = {"tiny": 1, "coarse": 3, "medium": 6, "fine": 12, "finer": 24}
CONTACT_DIVISIONS = {"tiny": 2, "coarse": 12, "medium": 24, "fine": 48, "finer": 96}
# elements across the Hertz contact radius at the levels that resolve the patch
PATCH_ELEMENTS = {"fine": 5, "finer": 10}
# the element edge grows by at most this much per unit distance from the contact (a
# neighbour at most ~25 % larger: gmsh's tetrahedra stay well shaped)
GRADING = 0.25


def level_key(level: str) -> str:
    """``level`` and what the tables above make of it, for a meshed body's cache key
    (meshes/body.py): a changed table gives a new mesh, not the cached one. A level the
    tables do not hold (a .geo that meshes itself may be given any) is itself alone."""
    if level not in BODY_DIVISIONS:
        return str(level)
    return (f"{level} divisions {BODY_DIVISIONS[level]}/{CONTACT_DIVISIONS[level]} "
            f"patch {PATCH_ELEMENTS.get(level)} grading {GRADING!r}")


def check_level(level: str) -> str:
    """The level, or ValueError naming it: a free mesh takes the named levels only
    (explicit element counts "NXxNYxNZ" are the block's)."""
    if level not in BODY_DIVISIONS:
        raise ValueError(f"mesh level {level!r}: a body other than the block takes one of "
                         f"{', '.join(BODY_DIVISIONS)} (element counts such as '4x4x6' are the "
                         "block's)")
    return level


def sizes(level: str, scale: float, patch_radius=None) -> tuple:
    """(h_contact, h_body), m, of a level on a body of length scale ``scale`` whose contact
    patch has the radius ``patch_radius`` (None: unknown)."""
    check_level(level)
    h_body = scale / BODY_DIVISIONS[level]
    h_contact = scale / CONTACT_DIVISIONS[level]
    if patch_radius is not None and level in PATCH_ELEMENTS:
        h_contact = min(h_contact, patch_size(patch_radius, PATCH_ELEMENTS[level]))
    return h_contact, h_body


def patch_size(radius: float, elements: int) -> float:
    """The edge at the first-touch point that puts ``elements`` elements across a patch of
    ``radius`` while the edge grows as h(d) = h_c + GRADING d: the count is the integral of
    dd / h(d) over [0, radius], ln(1 + GRADING radius / h_c) / GRADING, so
    h_c = GRADING radius / (exp(GRADING elements) - 1)."""
    return GRADING * radius / math.expm1(GRADING * elements)


def contact_modulus(E: float, nu: float) -> float:
    """E* of the body on the rigid base: E / (1 - nu^2) (Johnson eq 4.22 with a rigid
    counterface)."""
    return E / (1.0 - nu * nu)


def hertz_point_radius(load: float, radius: float, E: float, nu: float) -> float:
    """The contact radius a = (3 F R / 4 E*)^(1/3) of a sphere on a rigid flat (Johnson eq 4.22)."""
    return (3.0 * load * radius / (4.0 * contact_modulus(E, nu))) ** (1.0 / 3.0)


def hertz_line_half_width(load: float, radius: float, length: float, E: float, nu: float) -> float:
    """The half-width b = sqrt(4 F R / (pi L E*)) of a cylinder's line contact on a rigid flat
    (Johnson eq 4.45 with the load per length F / L)."""
    return math.sqrt(4.0 * load * radius / (math.pi * length * contact_modulus(E, nu)))


def distance_field(gmsh, distance: str, h_contact: float, h_body: float) -> None:
    """Make h(d) = min(h_body, h_contact + GRADING d) the mesh size, ``distance`` being a gmsh
    MathEval expression in x, y, z of the distance to the points that touch first."""
    field = gmsh.model.mesh.field
    tag = field.add("MathEval")
    field.setString(tag, "F", f"Min({h_body!r}, {h_contact!r} + {GRADING!r} * ({distance}))")
    field.setAsBackgroundMesh(tag)
    _size_from_field_only(gmsh)


def surface_distance_field(gmsh, surfaces, h_contact: float, h_body: float) -> None:
    """The same grading from the distance to ``surfaces`` (gmsh's Distance and Threshold
    fields), for a user's part whose contact group is known only as surfaces."""
    field = gmsh.model.mesh.field
    distance = field.add("Distance")
    # (gmsh renamed options: 4.8's name, then newer versions')
    _set(field.setNumbers, distance, ("FacesList", "SurfacesList"), list(surfaces))
    _set(field.setNumber, distance, ("NNodesByEdge", "Sampling"), 40)
    threshold = field.add("Threshold")
    _set(field.setNumber, threshold, ("IField", "InField"), distance)
    field.setNumber(threshold, "SizeMin", h_contact)
    field.setNumber(threshold, "SizeMax", h_body)
    field.setNumber(threshold, "DistMin", 0.0)
    field.setNumber(threshold, "DistMax", (h_body - h_contact) / GRADING)
    field.setAsBackgroundMesh(threshold)
    _size_from_field_only(gmsh)


def _set(setter, tag, names, value) -> None:
    """Set a field's option under whichever of its ``names`` this gmsh knows."""
    for name in names:
        try:
            setter(tag, name, value)
            return
        except Exception:
            continue
    raise RuntimeError(f"gmsh knows none of the field options {names}")


# The global gmsh options the meshing of a body sets (gmsh_options puts them back).
OPTIONS = ("Mesh.MeshSizeExtendFromBoundary", "Mesh.MeshSizeFromPoints",
           "Mesh.MeshSizeFromCurvature", "Mesh.Algorithm3D", "Mesh.ElementOrder",
           "Mesh.MshFileVersion")


@contextlib.contextmanager
def gmsh_options(gmsh):
    """Put back OPTIONS as they were (gmsh's options outlive a model: a caller's session,
    and the block meshed after a body in it, keep their own)."""
    kept = {name: gmsh.option.getNumber(name) for name in OPTIONS}
    try:
        yield
    finally:
        for name, value in kept.items():
            gmsh.option.setNumber(name, value)


def _size_from_field_only(gmsh) -> None:
    """Let the field alone set the sizes (not the points' sizes, the curvature or the
    boundary's sizes extended inward)."""
    for option in ("Mesh.MeshSizeExtendFromBoundary", "Mesh.MeshSizeFromPoints",
                   "Mesh.MeshSizeFromCurvature"):
        gmsh.option.setNumber(option, 0)
