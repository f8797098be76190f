"""Tangential contact laws as a per-node update: the contract (contract.py), the
built-in Dahl (dahl.py) and LuGre (lugre.py) laws, and the time loops compiled
per law (specialize.py)."""

from .contract import (Bounds, ContactLaw, FrictionLaw, LawError, Parameter, ParameterError,
                       load_law)
from .law import contact_step
from .specialize import law_kernel

__all__ = ["Bounds", "ContactLaw", "FrictionLaw", "LawError", "Parameter", "ParameterError",
           "contact_step", "law_kernel", "load_law"]
