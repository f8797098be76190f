"""The errors of the numerics, in the model's own terms.

The numerics never name scene keys: the scene layer maps each refusal to the
key a user changes (scene.REFUSAL_KEYS), and the command line reports both
kinds in words (cli.py). BadBody alone carries its key: the body's meshes
(vibrofric/meshes) are made from the scene's [body] and know which of its keys
(or fem.mesh) made the body what it is.
"""


class NumericalError(RuntimeError):
    """A run whose numbers went wrong (NaN, a diverging update); never written as results."""


class BodyLeftContact(NumericalError):
    """A run stopped because the body tipped over the edge of its contact patch
    (fem/outputs/tipping.py). Physics, not numbers; stopped and reported like numerical
    trouble (nothing written)."""


class ContactBeyondInterface(NumericalError):
    """A reduced run stopped because a contact candidate it left out of its interface
    (fem/integrators/interface.py) reached the base: its answer would hold a contact it
    cannot see. Stopped and reported like BodyLeftContact (nothing written)."""


class Refusal(ValueError):
    """A model that cannot run the scene as given, refused before any work."""


class StepTooLong(Refusal):
    """The time step is above what the integrator can take (stability, contact iteration)."""


class NormalLoadTooSmall(Refusal):
    """The normal load cannot hold the body on the base (below its weight, no node in contact,
    or a body without a load surface whose weight is not F_N)."""


class DriveTipsBlock(Refusal):
    """The drive's line of action would tip the block over."""


class DriveHasNoAttachment(Refusal):
    """The drive's attachment names a facet group the body's mesh lacks."""


class PatchUnresolved(Refusal):
    """The static preload's contact patch does not settle: the mesh is too coarse where
    the body touches the base."""


class NoEnergyBalance(Refusal):
    """An energy balance asked of an integrator that keeps none."""


class ReductionFailed(Refusal):
    """The reduced model could not be checked against the full one."""


class WindowDoesNotFit(Refusal):
    """A scene to be stepped whose averaging window does not fit between the
    vibration's onset and its end (core.series.check_stepped_window)."""


class BadBody(Refusal):
    """A body the FE model cannot take (meshes/): a mesh without a contact group, not
    three-dimensional, inverted, starting inside the base, drawn in other units, too
    large for the memory. ``key`` names the scene key to change (body.mesh, body.mass,
    fem.mesh)."""

    def __init__(self, message: str, key: str = "body.mesh"):
        super().__init__(message)
        self.key = key


class BadBaseMotion(Refusal):
    """A base motion given per step (core/base_table.py) that cannot be sampled: a measured
    motion file unreadable, short, not finite or not increasing in time, a harmonic's
    order not a positive integer, a period not a whole number of steps. ``key`` names the
    scene key to change (vibration.motion, vibration.harmonics, time.dt)."""

    def __init__(self, message: str, key: str = "vibration.motion"):
        super().__init__(message)
        self.key = key
