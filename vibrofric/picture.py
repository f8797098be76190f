"""A picture of the block from its ParaView series (pyvista, off-screen).

The contact face coloured by contact pressure, with the friction traction as
arrows, inside the block drawn translucent.

VTK's renderer aborts (std::bad_alloc) in a process that has loaded DOLFINx
before it, so the picture is drawn in a child process of its own, one that
``vibrofric run`` starts beside its time loop (plot_worker.py, kind
"picture"): there ``warm_up`` imports pyvista and sets up the off-screen
renderer while the run goes on, then ``render`` draws the last frame.
"""

import os

import numpy as np


def warm_up() -> None:
    """Import pyvista and draw a throwaway picture: the off-screen renderer (OSMesa)
    is set up, and the text's fonts loaded, before the run's picture is drawn."""
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
    import pyvista as pv

    plotter = pv.Plotter(off_screen=True, window_size=(64, 64))
    plotter.add_mesh(pv.Cube(), opacity=0.2)
    plotter.add_text("t", font_size=10)
    plotter.screenshot(None, return_img=True)
    plotter.close()


def last_frame(pvd_path):
    """The last time step of a .pvd series and its time."""
    import pyvista as pv

    reader = pv.get_reader(str(pvd_path))
    reader.set_active_time_point(len(reader.time_values) - 1)
    return reader.read().combine(), reader.time_values[-1]


def render(pvd_path, png_path) -> None:
    """Draw the picture in this process (one that has not loaded DOLFINx)."""
    # OSMesa (Debian's libosmesa6): no display needed.
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
    import pyvista as pv

    block, time = last_frame(pvd_path)
    z = block.points[:, 2]
    on_face = z <= z.min() + 1e-9 * np.ptp(z)
    contact = pv.PolyData(block.points[on_face])
    for name in ("contact_pressure", "friction_traction"):
        contact[name] = np.asarray(block[name])[on_face]
    bottom = contact.delaunay_2d()
    traction = np.linalg.norm(contact["friction_traction"], axis=1)
    arrow_length = 0.25 * min(np.ptp(block.points[:, 0]), np.ptp(block.points[:, 1]))
    arrows = contact.glyph(orient="friction_traction", scale=False,
                           factor=arrow_length * (traction.max() > 0))

    plotter = pv.Plotter(off_screen=True, window_size=(900, 700))
    plotter.add_mesh(block.extract_surface(algorithm="dataset_surface"), color="lightgrey", opacity=0.2)
    plotter.add_mesh(block.outline(), color="black")
    # the colour bar upright at the right edge, the block and its arrows left of it
    plotter.add_mesh(bottom, scalars="contact_pressure", cmap="viridis",
                     scalar_bar_args={"title": "contact pressure (Pa)\n", "fmt": "%.3g",
                                      "vertical": True, "position_x": 0.84, "position_y": 0.15,
                                      "width": 0.08, "height": 0.7})
    plotter.add_mesh(arrows, color="crimson")
    plotter.add_text(f"t = {time:.4g} s: contact pressure, friction traction (arrows)", font_size=10)
    plotter.view_vector((0.8, -1.2, -0.9), viewup=(0, 0, 1))  # from below, in front of the drive
    plotter.reset_camera()
    _shift_left(plotter.camera, 0.12)
    plotter.camera.zoom(0.9)
    plotter.screenshot(str(png_path))
    plotter.close()


def _shift_left(camera, fraction: float) -> None:
    """Move what the camera sees to the left by ``fraction`` of the view's width."""
    position, focus = np.array(camera.position), np.array(camera.focal_point)
    forward = focus - position
    right = np.cross(forward, np.array(camera.up))
    right /= np.linalg.norm(right)
    distance = np.linalg.norm(forward)
    width = 2.0 * distance * np.tan(np.radians(camera.view_angle) / 2.0)
    shift = fraction * width * right
    camera.position, camera.focal_point = tuple(position + shift), tuple(focus + shift)
