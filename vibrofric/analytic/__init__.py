"""Lumped-body steppers: the coupled two-phase model and the 1D longitudinal model."""

from .coupled import run_coupled
from .longitudinal import run_longitudinal
from .summary import breakaway_time, cycle_average, steady_drive_force, summarize

__all__ = ["breakaway_time", "cycle_average", "run_coupled", "run_longitudinal",
           "steady_drive_force", "summarize"]
