"""Every value of a built scene checked before any work (docs/scenes.md): a physically
invalid or unrunnable one raises SceneError naming its key."""

from ..friction_law import ContactLaw, LawError, load_law
from ..meshes import level_counts
from ..sense import nonsense
from .errors import SceneError, law_refused
from .schema import CHOICES, Scene, to_dict


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
    for key in ("body.gravity",
                "vibration.k_v", "vibration.t_on", "fem.damping", "fem.output_every"):
        _positive(scene, key, allow_zero=True)
    if any(v <= 0 for v in scene.body.size):
        raise SceneError("body.size", f"every edge must be > 0, got {list(scene.body.size)}")
    if scene.body.density is not None and scene.body.density <= 0:
        raise SceneError("body.density", f"must be > 0, got {scene.body.density}")
    if not -1.0 < scene.body.nu < 0.5:
        raise SceneError("body.nu", f"must lie in (-1, 0.5), got {scene.body.nu}")
    if not 0.0 <= scene.contact.eta_y <= 1.0:
        raise SceneError("contact.eta_y", f"must lie in [0, 1], got {scene.contact.eta_y}")
    if scene.fem.penalty is not None and scene.fem.penalty <= 0:
        raise SceneError("fem.penalty", f"must be > 0, got {scene.fem.penalty}")
    if not 0.0 <= scene.fem.rho_infinity <= 1.0:
        raise SceneError("fem.rho_infinity", f"must lie in [0, 1], got {scene.fem.rho_infinity}")
    if scene.fem.cutoff < 0:
        raise SceneError("fem.cutoff", f"must be >= 0, got {scene.fem.cutoff}")
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
    try:
        level_counts(scene.fem.mesh)
    except ValueError as err:
        raise SceneError("fem.mesh", str(err)) from None
    flat = {f"{section}.{k}": v for section, keys in to_dict(scene).items() for k, v in keys.items()}
    if (refusal := nonsense(flat)) is not None:
        raise SceneError(*refusal)
    try:  # a law file's first steps at the scene's values, bounds-checked (friction_law.law_check)
        law = load_law(scene.contact.law)   # (not scene.friction: a Scene stays picklable)
        law.probe(ContactLaw(law, law.values(scene.contact.given), scene.contact.F_N),
                  scene.time.dt)
    except LawError as err:
        raise law_refused(err) from None
    if scene.vibrated:
        vib, time = scene.vibration, scene.time
        if time.T <= vib.t_on:
            raise SceneError("time.T", f"{time.T} s ends before the vibration starts "
                                       f"(vibration.t_on = {vib.t_on} s)")
        steps_per_cycle = 1.0 / (vib.f * time.dt)
        if steps_per_cycle < 10:
            raise SceneError("time.dt", f"{time.dt} s resolves a vibration cycle of 1/f = "
                                        f"{1 / vib.f:.3g} s in {steps_per_cycle:.3g} steps; "
                                        "at least 10 are needed")
        cycles = scene.averaged_cycles
        window = cycles / vib.f
        if time.T - vib.t_on < window:
            raise SceneError("time.average_cycles",
                             f"{cycles} cycles ({window:.3g} s) do not fit between "
                             f"vibration.t_on = {vib.t_on} s and time.T = {time.T} s")
