"""Tangential contact laws (Dahl, LuGre) as a per-node two-phase update."""

from .kernels import DAHL, EXACT, LUGRE, PAPER, node_step, relax_length
from .law import AsperityState, FrictionLaw, contact_step

__all__ = ["DAHL", "EXACT", "LUGRE", "PAPER", "AsperityState", "FrictionLaw", "contact_step", "node_step", "relax_length"]
