"""A scene value that cannot be run (SceneError, naming its key), and the model's own
refusals (core.errors) translated into the scene key a user changes."""

from ..core import errors
from ..friction_law import LawError


class SceneError(ValueError):
    """A scene value that cannot be run; the message names the key. ``detail``: a longer
    explanation behind the one line, where there is one (numba's message for a law)."""

    __module__ = "vibrofric.scene"   # its public name, as tracebacks show it

    def __init__(self, key: str, message: str, detail: str = ""):
        super().__init__(f"{key}: {message}")
        self.key = key
        self.detail = detail


def law_refused(err: LawError) -> SceneError:
    """A friction law's failure as the scene's: under contact.law, numba's message kept."""
    return SceneError("contact.law", str(err), getattr(err, "detail", ""))


# The scene key a user changes when the model refuses a scene (core.errors):
# the numerics say what is wrong in the model's terms, the scene names the key.
REFUSAL_KEYS = {
    errors.StepTooLong: "time.dt",
    errors.NormalLoadTooSmall: "contact.F_N",
    errors.DriveTipsBlock: "drive.attach",
    errors.DriveHasNoAttachment: "drive.attach",
    errors.PatchUnresolved: "fem.mesh",
    errors.NoEnergyBalance: "fem.energy",
    errors.ReductionFailed: "fem.cutoff",
    errors.WindowDoesNotFit: "time.average_cycles",
    errors.BadBody: "body.mesh",
    errors.BadBaseMotion: "vibration.motion",
}


def refused(refusal: errors.Refusal) -> SceneError:
    """The model's refusal as a SceneError naming the key to change."""
    return SceneError(getattr(refusal, "key", None) or REFUSAL_KEYS[type(refusal)], str(refusal))
