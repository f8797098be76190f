"""Every value of a built scene checked before any work (docs/scenes.md): a physically
invalid or unrunnable one raises SceneError naming its key."""

import math
from pathlib import Path

from ..core.base_table import (WHOLE_STEPS, check_closed, check_harmonics, moves_along_z,
                               plane_speed, read_motion, table_moves_along_z, table_speed_z,
                               whole_steps)
from ..core.errors import BadBaseMotion, BadBody
from ..friction_law import LawError
from ..meshes import MESH_SUFFIXES, level_counts
from ..meshes import checks as mesh_checks
from ..meshes import refinement, shapes
from ..sense import nonsense
from ..core.law_limits import NORMAL_LIMIT
from ..core.series import shortest_stepped_T
from .errors import SceneError, law_refused, refused
from .schema import CHOICES, SHAPE_KEYS, Body, Scene, to_dict


# The base's velocity amplitude v_a = k_v v_d is refused beyond this fraction of the
# speed of sound in the body, c = sqrt(E / rho). A plane wave of particle velocity v
# strains a solid by v / c (and stresses it by rho c v): at v_a = 0.1 c the strain is
# 10%, beyond the elastic limit of any solid the models are for (metals yield at
# 0.1-1%), where neither the rigid lumped body nor the linear elastic FE block holds.
# Steel (209 GPa, 7850 kg/m^3): c = 5.2 km/s, v_a up to 516 m/s (the paper's scenes:
# 0.01 m/s). k_v = 1e20 on the Fig 7 scene (v_a = 5e16 m/s) answered a negative F_dv.
BASE_SPEED_BOUND = 0.1


def body_density(scene):
    """The body's density: body.density, or its mass over its volume (the block's, a shape's
    in closed form); None for a user's mesh without body.density (its volume is known once
    the mesh is read: meshes.body_mesh checks it then)."""
    body = scene.body
    if body.density is not None:
        return body.density
    if body.mesh is not None:
        return None
    if body.shape != "block":
        return body.mass / shapes.volume(body)
    a, b, c = body.size
    return body.mass / (a * b * c)


# the shape-specific keys of [body], and the value each has when not set
_SHAPE_DEFAULTS = {name: getattr(Body(), name) for name in
                   ("size", "radius", "height", "length", "edge_radius", "hemisphere")}


def _check_body(scene) -> None:
    """The body's shape or mesh file and the keys that describe it: each shape's required
    keys set and > 0, no key of another shape set (never silently ignored), a mesh file of a
    known kind that exists, and a shape whose mass over its volume is a real solid's
    density (meshes/checks.py: a ball of radius 10 m and 0.5 kg was drawn in mm)."""
    body = scene.body
    if body.mesh is not None:
        if body.shape != "block":
            raise SceneError("body.shape", f"{body.shape!r} and body.mesh {body.mesh!r} both name "
                                           "the body: give one")
        kind, needed, optional = "body.mesh", (), ()
        if Path(body.mesh).suffix.lower() not in MESH_SUFFIXES:
            raise SceneError("body.mesh", f"{body.mesh!r} is not a mesh or geometry file gmsh is "
                                          f"asked to read here (use {', '.join(MESH_SUFFIXES)})")
        if not Path(body.mesh).expanduser().is_file():
            raise SceneError("body.mesh", f"{body.mesh}: no such file")
    else:
        kind = f'body.shape "{body.shape}"'
        needed, optional = SHAPE_KEYS[body.shape]
    for name, unset in _SHAPE_DEFAULTS.items():
        value = getattr(body, name)
        if name in needed:
            if value is None:
                raise SceneError(f"body.{name}", f"{kind} needs it (m)")
            if name != "size" and not value > 0:
                raise SceneError(f"body.{name}", f"must be > 0, got {value}")
        elif name not in optional and value != unset:
            uses = [s for s, keys in SHAPE_KEYS.items() if name in keys[0] + keys[1]]
            raise SceneError(f"body.{name}", f"{kind} takes no {name} (it is the key of "
                                             f"{', '.join(uses)}): remove it")
    if body.shape == "cylinder" and not 0.0 <= body.edge_radius < min(body.radius, body.height):
        raise SceneError("body.edge_radius", f"must lie in [0, {min(body.radius, body.height):g}) "
                                             f"(below the radius and the height), got {body.edge_radius}")
    if not body.is_block:
        try:
            refinement.check_level(scene.fem.mesh)
        except ValueError as err:
            raise SceneError("fem.mesh", str(err)) from None
    if body.mesh is None and body.shape != "block" and body.density is None:
        volume = shapes.volume(body)
        try:
            mesh_checks.check_density(body.mass, volume, kind,
                                      mesh_checks.density_key(body.mass, volume, "body.radius"))
        except BadBody as err:
            raise SceneError(err.key, str(err)) from None


def _positive(scene, key, allow_zero=False):
    value = scene.get(key)
    if value < 0 or (value == 0 and not allow_zero):
        raise SceneError(key, f"must be {'>= 0' if allow_zero else '> 0'}, got {value}")


def validate(scene: Scene) -> None:
    """Refuse physically invalid or unrunnable values (docs/scenes.md)."""
    for key, choices in CHOICES.items():
        if scene.get(key) not in choices:
            raise SceneError(key, f"must be one of {', '.join(choices)}, got {scene.get(key)!r}")
    for key in ("body.mass", "body.E", "contact.F_N", "drive.k_d", "drive.v_d",
                "vibration.f", "time.T", "time.dt", "time.series_dt"):
        _positive(scene, key)
    for key in ("body.gravity", "vibration.normal_amplitude",
                "vibration.k_v", "vibration.t_on", "fem.damping", "fem.output_every"):
        _positive(scene, key, allow_zero=True)
    _check_body(scene)
    if any(v <= 0 for v in scene.body.size):
        raise SceneError("body.size", f"every edge must be > 0, got {list(scene.body.size)}")
    if scene.body.density is not None and scene.body.density <= 0:
        raise SceneError("body.density", f"must be > 0, got {scene.body.density}")
    if not -1.0 < scene.body.nu < 0.5:
        raise SceneError("body.nu", f"must lie in (-1, 0.5), got {scene.body.nu}")
    if not 0.0 <= scene.contact.eta_y <= 1.0:
        raise SceneError("contact.eta_y", f"must lie in [0, 1], got {scene.contact.eta_y}")
    if scene.contact.k_n is not None and scene.contact.k_n <= 0:
        raise SceneError("contact.k_n", f"must be > 0, got {scene.contact.k_n}")
    if not scene.contact.zeta_n >= 0.0:
        raise SceneError("contact.zeta_n", f"must be >= 0, got {scene.contact.zeta_n}")
    if moves_along_z(scene.vibration) and scene.contact.k_n is None and not scene.body.is_block:
        raise SceneError("contact.k_n", "needed for a base moving along Z under a body other "
                                        "than the block: its default is matched to the FE "
                                        "block's bounce (core/bounce.py)")
    if scene.vibration.normal_phase_deg is not None and scene.vibration.normal_amplitude == 0.0:
        raise SceneError("vibration.normal_phase_deg",
                         f"{scene.vibration.normal_phase_deg:g} deg is the phase of a normal motion "
                         "the scene does not have: set vibration.normal_amplitude > 0")
    _check_base_table(scene)
    if scene.fem.penalty is not None and scene.fem.penalty <= 0:
        raise SceneError("fem.penalty", f"must be > 0, got {scene.fem.penalty}")
    if scene.fem.contact_stiffness is not None and scene.fem.contact_stiffness <= 0:
        raise SceneError("fem.contact_stiffness", f"must be > 0, got {scene.fem.contact_stiffness}")
    if scene.fem.penalty is not None and scene.fem.contact_stiffness is not None:
        raise SceneError("fem.contact_stiffness", "give the penalty once: fem.penalty (N/m, the "
                         "whole contact) or fem.contact_stiffness (Pa/m, per unit area)")
    if scene.drive.holder != "none" and scene.drive.attach == "contact-plane":
        raise SceneError("drive.holder", f"{scene.drive.holder!r} holds the drive's attachment "
                         "group, and drive.attach = \"contact-plane\" attaches to the contact "
                         "itself: use \"load-group\", \"drive-group\" or \"front-face\"")
    if not 0.0 <= scene.fem.rho_infinity <= 1.0:
        raise SceneError("fem.rho_infinity", f"must lie in [0, 1], got {scene.fem.rho_infinity}")
    if scene.fem.cutoff < 0:
        raise SceneError("fem.cutoff", f"must be >= 0, got {scene.fem.cutoff}")
    reach = scene.fem.interface_reach
    if reach != "all" and (isinstance(reach, str) or not reach > 0):
        raise SceneError("fem.interface_reach", f"must be a number > 0 or \"all\", got {reach!r}")
    if not 0.0 < scene.time.accuracy < 1.0:
        raise SceneError("time.accuracy", f"must lie in (0, 1), got {scene.time.accuracy}")
    if scene.time.error_estimate not in (True, False, "auto"):
        raise SceneError("time.error_estimate",
                         f"must be true, false or \"auto\", got {scene.time.error_estimate!r}")
    if not 0.0 < scene.fem.accuracy < 1.0:
        raise SceneError("fem.accuracy", f"must lie in (0, 1), got {scene.fem.accuracy}")
    if scene.time.steady_tolerance < 0:
        raise SceneError("time.steady_tolerance", f"must be >= 0, got {scene.time.steady_tolerance}")
    if scene.time.steady_cycles < 0:
        raise SceneError("time.steady_cycles", f"must be >= 0, got {scene.time.steady_cycles}")
    if scene.time.average_cycles < 0:
        raise SceneError("time.average_cycles", f"must be >= 0, got {scene.time.average_cycles}")
    if scene.time.dt > scene.time.T:
        raise SceneError("time.dt", f"{scene.time.dt} is longer than time.T = {scene.time.T}")
    if scene.time.series_dt > scene.time.T:
        raise SceneError("time.series_dt", f"{scene.time.series_dt} s is longer than time.T = "
                                           f"{scene.time.T} s: the time series would hold no row")
    if not 0.0 < scene.time.settle_tolerance < 1.0:
        raise SceneError("time.settle_tolerance",
                         f"must lie in (0, 1), got {scene.time.settle_tolerance}")
    if not 0.0 < scene.time.accuracy < 1.0:
        raise SceneError("time.accuracy", f"must lie in (0, 1), got {scene.time.accuracy}")
    try:
        level_counts(scene.fem.mesh)
    except ValueError as err:
        raise SceneError("fem.mesh", str(err)) from None
    flat = {f"{section}.{k}": v for section, keys in to_dict(scene).items() for k, v in keys.items()}
    if (refusal := nonsense(flat)) is not None:
        raise SceneError(*refusal)
    try:  # a law file's first steps at the scene's values, bounds-checked (friction_law.law_check)
        contact_law = scene.friction
        law = contact_law.law
        law.probe(contact_law, scene.time.dt)
        sliding_force = contact_law.steady_sliding_force(scene.contact.F_N, scene.drive.v_d)
    except LawError as err:
        raise law_refused(err) from None
    if sliding_force <= 0.0:   # mu = 0: F_d0 = 0, nothing for the vibration to reduce
        key = "contact.mu" if "mu" in law.parameters else "contact.law"
        raise SceneError(key, f"{scene.get(key) if key == 'contact.mu' else scene.contact.law} "
                              "gives no friction (F_d0 = 0): F_dv/F_d0 is undefined")
    density = body_density(scene)
    body_sound_speed = math.sqrt(scene.body.E / density) if density is not None else math.inf
    if scene.v_a > BASE_SPEED_BOUND * body_sound_speed:
        raise SceneError("vibration.k_v",
                         f"{scene.vibration.k_v:g} makes the base's velocity amplitude k_v v_d = "
                         f"{scene.v_a:.3g} m/s, beyond {BASE_SPEED_BOUND:g} of the speed of "
                         f"sound in the body sqrt(E/rho) = {body_sound_speed:.4g} m/s: no "
                         "solid carries that motion elastically")
    speed = table_plane_speed(scene) if scene.vibration.sampled else 0.0
    if speed > BASE_SPEED_BOUND * body_sound_speed:
        raise SceneError(table_key(scene),
                         f"moves the base at up to {speed:.3g} m/s in the plane, beyond "
                         f"{BASE_SPEED_BOUND:g} of the speed of sound in the body sqrt(E/rho) = "
                         f"{body_sound_speed:.4g} m/s: no solid carries that motion elastically")
    if scene.vibrated:
        vib, time = scene.vibration, scene.time
        steps_per_cycle = 1.0 / (vib.f * time.dt)
        if steps_per_cycle < 10:
            raise SceneError("time.dt", f"{time.dt} s resolves a vibration cycle of 1/f = "
                                        f"{1 / vib.f:.3g} s in {steps_per_cycle:.3g} steps; "
                                        "at least 10 are needed")
        # periodic and auto answer by the orbit, if they can (a base moving along Z too);
        # a measured motion that ends has no orbit: auto steps it
        if time.method == "transient" or not vib.repeats:
            _check_averaging_window(scene)


def table_key(scene) -> str:
    """The key that gives the base's motion per step: vibration.motion or .harmonics."""
    return "vibration.motion" if scene.vibration.motion is not None else "vibration.harmonics"


def table_plane_speed(scene) -> float:
    """The base's largest in-plane speed, m/s, where its motion is given per step
    (core.base_table.plane_speed)."""
    return plane_speed(scene.vibration, scene.omega, scene.v_a)


def _check_base_table(scene) -> None:
    """A base motion given per step (core/base_table.py): a measured motion file that
    reads (and closes on itself where periodic), alone in moving the base, with a method
    that can run it; harmonics of positive integer orders."""
    vib = scene.vibration
    try:
        check_harmonics(vib.harmonics)
    except BadBaseMotion as err:
        raise refused(err) from None
    n = max((h.order for h in vib.harmonics), default=0)
    if n and 1.0 / (n * vib.f * scene.time.dt) < 10:   # as the base cycle's (validate)
        raise SceneError("vibration.harmonics", f"order {n} runs at {n * vib.f:g} Hz, whose cycle "
                                                f"time.dt = {scene.time.dt:g} s resolves in "
                                                f"{1 / (n * vib.f * scene.time.dt):.3g} steps; at "
                                                "least 10 are needed")
    if vib.motion is None:
        if vib.motion_periodic:
            raise SceneError("vibration.motion_periodic", "says how a measured motion repeats: "
                                                          "set vibration.motion")
        return
    for key, given in (("vibration.k_v", vib.k_v > 0.0),
                       ("vibration.normal_amplitude", vib.normal_amplitude > 0.0),
                       ("vibration.harmonics", bool(vib.harmonics))):
        if given:
            raise SceneError(key, f"vibration.motion {vib.motion!r} moves the base alone: "
                                  f"remove {key} (or vibration.motion)")
    try:
        motion = read_motion(vib.motion)
        if vib.motion_periodic:
            check_closed(motion, vib.motion)
    except BadBaseMotion as err:
        raise refused(err) from None
    if not vib.motion_periodic and scene.time.method == "periodic":
        raise SceneError("time.method", "\"periodic\" needs a motion that repeats: the measured "
                                        "motion holds its last position after it ends "
                                        "(vibration.motion_periodic false); use \"transient\" or "
                                        "\"auto\"")
    if (vib.motion_periodic and scene.time.method == "periodic"
            and whole_steps(motion.span, scene.time.dt) is None):
        raise SceneError("time.dt", f"{scene.time.dt:g} s does not divide the measured motion's "
                                    f"period {motion.span:g} s into whole steps (to "
                                    f"{WHOLE_STEPS:g} relative), as time.method \"periodic\" "
                                    "needs")


def check_fe_scene(scene) -> None:
    """Refuse, before any work, a scene the FE model cannot run: a base moving along Z
    faster than its step resolves (normal_step_bound; on the block, whose penalty is
    known before its mesh is: another body's run stops at the first step past
    the normal-force limit, fem/outputs/trouble.py), the speed along Z of a base motion
    given per step (core/base_table.py) bounded alike."""
    if scene.vibration.normal_amplitude > 0.0 and (scene.body.is_block
                                                   or scene.fem.penalty is not None):
        bound = normal_step_bound(scene)
        if scene.vibration.normal_amplitude > bound:
            approach = scene.vibration.normal_amplitude * scene.omega * scene.time.dt
            taken = NORMAL_LIMIT * scene.contact.F_N / scene.block_penalty
            raise SceneError("vibration.normal_amplitude",
                             f"{scene.vibration.normal_amplitude:g} m moves the base into the body "
                             f"by up to A_n w dt = {approach:.3g} m a step, more than the penalty "
                             f"takes in one ({NORMAL_LIMIT:g} F_N / k_pen = {taken:.3g} m): use "
                             f"vibration.normal_amplitude <= {bound:.3g} m or a smaller time.dt")
    if table_moves_along_z(scene.vibration) and (scene.body.is_block
                                                 or scene.fem.penalty is not None):
        speed = scene.vibration.normal_amplitude * scene.omega + table_speed_z(scene.vibration,
                                                                               scene.omega)
        taken = NORMAL_LIMIT * scene.contact.F_N / scene.block_penalty
        if speed * scene.time.dt > taken:
            raise SceneError(table_key(scene),
                             f"moves the base into the body at up to {speed:.3g} m/s, by "
                             f"{speed * scene.time.dt:.3g} m a step, more than the penalty takes "
                             f"in one ({NORMAL_LIMIT:g} F_N / k_pen = {taken:.3g} m): a smaller "
                             "motion along Z or a smaller time.dt")


def normal_step_bound(scene) -> float:
    """The largest vibration.normal_amplitude A_n the FE model takes at time.dt:

        A_n w dt <= NORMAL_LIMIT F_N / k_pen

    The base's approach in one step is at most A_n w dt (its speed amplitude times the
    step). The penalty reacts to it only at the step's end, so a step's approach is a
    jump of the face's normal force by k_pen A_n w dt (the body itself moves little in
    a step). NORMAL_LIMIT F_N (core/law_limits.py) is the largest summed normal force a
    run carries before it is judged diverging (fem/outputs/trouble.py): beyond the bound
    one step of the base alone drives the penalty past it, an impact the step does not
    resolve, and the run would stop at its first such step after all the work before it.
    (The explicit step is stable for the penalty's own frequency whatever A_n; what this
    bounds is how far the motion's sampling lets the base run into the body.) On the
    paper's block (k_pen = 4.8e10 N/m, F_N = 55 N) at 4 kHz and dt = 1e-6 s: A_n <= 4.6e-7 m,
    2.7 times the amplitude at which the lumped body starts to lose contact."""
    return NORMAL_LIMIT * scene.contact.F_N / (scene.block_penalty * scene.omega * scene.time.dt)


def _check_averaging_window(scene) -> None:
    """A stepped run (time.method transient) averages F_dv over its last averaged_cycles
    cycles, all after vibration.t_on. (Under auto or periodic the steady cycle is solved
    for directly and needs no window; core.series.check_stepped_window refuses the run
    where they fall back to stepping.) The message says what T is for and the shortest
    T that works; it names time.average_cycles where the scene sets it, time.T where it
    is the default."""
    vib, time = scene.vibration, scene.time
    cycles = scene.averaged_cycles
    window = cycles / vib.f
    if time.T - vib.t_on >= window * (1.0 - 1e-9):   # (a window that fits to rounding fits)
        return
    shortest = shortest_stepped_T(scene)
    why = (f"a stepped run averages F_dv over its last {cycles} vibration cycles "
           f"({window:.3g} s), all after vibration.t_on = {vib.t_on:g} s")
    key = "time.average_cycles" if time.average_cycles else "time.T"
    named = "" if key == "time.T" else "time.T = "
    raise SceneError(key, f"{named}{time.T:g} s is too short: {why}; the shortest T that "
                          f"works is {shortest:g} s (or a smaller vibration.t_on or "
                          "time.average_cycles)")
