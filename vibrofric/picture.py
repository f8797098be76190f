"""A picture of the body at the run's last step (matplotlib's 3D axes, Agg).

The contact face coloured by contact pressure, with the friction traction as
arrows (their direction; the range of their magnitude is written below), inside
the body's bounding box drawn translucent, seen from below, in front of the drive,
on axes in mm. It is drawn from the node fields of the run's last step (the last
ParaView frame's: fem/outputs/paraview.py), which the command sends to its plot
process (plot_worker.py, kind "fe"), so it is drawn beside the plots with the
library already loaded there and without reading the frame back.

The job (``picture_rows``) holds only what the picture draws: the body's
bounding box, the contact nodes' positions, pressure and friction traction, and
the time.
"""

import numpy as np

DPI = 120
SIZE_IN = (900 / DPI, 700 / DPI)   # inches: 900 x 700 pixels
PNG = {"dpi": DPI, "pil_kwargs": {"compress_level": 1}}  # as plots.RUN_PNG
# Seen from below, in front of the drive: the view direction (0.8, -1.2, -0.9) as
# matplotlib's elevation and azimuth, degrees.
VIEW = {"elev": -31.6, "azim": -56.3}
AXES = (0.0, 0.08, 0.78, 0.82)        # left, bottom, width, height: fractions of the figure
COLOUR_BAR = (0.78, 0.2, 0.03, 0.56)   # left, bottom, width, height: fractions of the figure
SUBDIVISIONS = 1  # each triangle of the contact face split in 4^SUBDIVISIONS, the pressure
                  # interpolated linearly over them: a smooth map without shading support
PLAN_DIGITS = 9   # the contact nodes' plan positions, in units of the face's extent


def picture_rows(fields: dict) -> dict:
    """What the picture draws of an FE run's last step: ``fields`` as FEResult.fields
    (node fields, "coordinates", "contact_nodes", "t"), reduced to plain arrays."""
    contact = fields["contact_nodes"]
    points = np.asarray(fields["coordinates"])
    return {"t": float(fields["t"]),
            "box": (points.min(axis=0), points.max(axis=0)),
            "contact": points[contact],
            "pressure": np.asarray(fields["contact_pressure"])[contact],
            "traction": np.asarray(fields["friction_traction"])[contact, :2]}


def warm_up() -> None:
    """Import the 3D axes (done while the run steps, not after it)."""
    import mpl_toolkits.mplot3d  # noqa: F401


def _box_faces(low, high) -> list:
    """The six faces of the body's bounding box, each four corners."""
    corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1])
                        for z in (low[2], high[2])])
    faces = ((0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5))
    return [corners[list(face)] for face in faces]


def _face_triangles(contact):
    """The contact nodes' Delaunay triangulation in plan. Their positions are rounded to
    PLAN_DIGITS of the face's extent first: on a tetrahedral face the nodes along a
    straight edge are collinear but for rounding (1e-20 m off x = 0), and the slivers
    Delaunay then puts between them make matplotlib's interpolation refuse the whole
    triangulation ("Triangulation is invalid")."""
    from matplotlib.tri import Triangulation

    plan = contact[:, :2]
    scale = float(np.ptp(plan, axis=0).max()) or 1.0
    plan = np.round(plan / scale, PLAN_DIGITS) * scale
    return Triangulation(plan[:, 0], plan[:, 1])


def draw(rows: dict, png_path) -> None:
    """Draw ``rows`` (picture_rows) into ``png_path``."""
    from matplotlib import cm, colors, ticker
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.tri import UniformTriRefiner
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    (low, high), contact = rows["box"], rows["contact"]
    pressure, traction = rows["pressure"], rows["traction"]
    face_z = low[2]

    fig = Figure(figsize=SIZE_IN, dpi=DPI)
    FigureCanvasAgg(fig)
    ax = fig.add_axes(AXES, projection="3d", computed_zorder=False)
    ax.add_collection3d(Poly3DCollection(_box_faces(low, high), facecolor=(0.83, 0.83, 0.83, 0.2),
                                         edgecolor="black", linewidth=0.6))

    fine, fine_pressure = UniformTriRefiner(_face_triangles(contact)) \
        .refine_field(pressure, subdiv=SUBDIVISIONS)
    norm = colors.Normalize(pressure.min(), pressure.max())
    corners = fine.triangles
    polygons = np.stack([fine.x[corners], fine.y[corners], np.full(corners.shape, face_z)], axis=-1)
    shades = cm.viridis(norm(fine_pressure[corners].mean(axis=1)))
    # edges of the triangles' own colour: no seams between them
    ax.add_collection3d(Poly3DCollection(polygons, facecolors=shades, edgecolors=shades,
                                         linewidths=0.3))

    magnitude = np.linalg.norm(traction, axis=1)
    shown = np.vstack([low, high])
    if magnitude.max() > 0:   # arrows of one length, along the traction
        length = 0.25 * min(high[0] - low[0], high[1] - low[1])
        unit = traction / np.where(magnitude > 0, magnitude, 1.0)[:, None]
        ax.quiver(contact[:, 0], contact[:, 1], np.full(len(contact), face_z),
                  unit[:, 0], unit[:, 1], np.zeros(len(contact)), length=length,
                  color="crimson", arrow_length_ratio=0.25, linewidth=1.0)
        tips = contact[:, :2] + length * unit
        shown = np.vstack([shown, np.column_stack([tips, np.full(len(tips), face_z)])])

    lower, upper = shown.min(axis=0), shown.max(axis=0)
    ax.set(xlim=(lower[0], upper[0]), ylim=(lower[1], upper[1]), zlim=(lower[2], upper[2]))
    ax.set_box_aspect(upper - lower)
    ax.view_init(**VIEW)
    in_mm = ticker.FuncFormatter(lambda value, _: f"{value * 1e3:.3g}")
    for axis, name in ((ax.xaxis, "x"), (ax.yaxis, "y"), (ax.zaxis, "z")):
        axis.set_major_formatter(in_mm)
        axis.set_major_locator(ticker.MaxNLocator(4))
        axis.set_pane_color((1.0, 1.0, 1.0, 0.0))   # no grey walls behind the block
    ax.set_xlabel("x (mm)", fontsize=8, labelpad=-2)
    ax.set_ylabel("y (mm)", fontsize=8, labelpad=-2)
    ax.set_zlabel("z (mm)", fontsize=8, labelpad=-2)
    ax.tick_params(labelsize=7, pad=-2)
    ax.grid(False)
    # the colour bar in axes of its own at the right (no re-layout of the 3D axes)
    fig.colorbar(cm.ScalarMappable(norm, cm.viridis), cax=fig.add_axes(COLOUR_BAR), format="%.3g",
                 label="contact pressure (Pa)")
    fig.suptitle(f"t = {rows['t']:.6g} s: contact pressure, friction traction (arrows)",
                 fontsize=10)
    fig.text(0.02, 0.02, "body undeformed (its bounding box), seen from below, sliding along +x; "
             "arrows: the friction traction's direction, all one length,\n"
             f"its magnitude {magnitude.min():.3g} to {magnitude.max():.3g} Pa "
             "(the force of the body on the base, paper sign)", fontsize=8)
    fig.savefig(png_path, **PNG)
