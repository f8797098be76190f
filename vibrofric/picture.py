"""A picture of the block from its ParaView series (pyvista, off-screen).

The contact face coloured by contact pressure, with the friction traction as
arrows, inside the block drawn translucent.

VTK's renderer aborts (std::bad_alloc) in a process that has loaded DOLFINx
before it, so ``block_picture`` renders in a child process of its own:
``python -m vibrofric.picture SERIES.pvd PICTURE.png``.
"""

import os
import subprocess
import sys

import numpy as np


def block_picture(pvd_path, png_path) -> None:
    """Contact pressure and friction traction of the series' last frame, as PNG."""
    subprocess.run([sys.executable, "-m", "vibrofric.picture", str(pvd_path), str(png_path)],
                   check=True, capture_output=True)


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


if __name__ == "__main__":
    render(*sys.argv[1:3])
