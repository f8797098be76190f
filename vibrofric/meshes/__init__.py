"""Meshes for the finite-element model: the body on the base (body.py), of which the
block (block.py, hexahedral and cached) is one instance."""

from .block import (BACK, BLOCK, CONTACT, DEFAULT_SIZE, FACES, FRONT, LEFT, LEVELS, RIGHT,
                    TOP, block_mesh_file, block_mesh_model, default_cache_dir, describe,
                    gmsh_model, level_counts)
from .body import BLOCK_GROUPS, BodyMesh, block_body

__all__ = ["BACK", "BLOCK", "BLOCK_GROUPS", "BodyMesh", "block_body", "CONTACT", "DEFAULT_SIZE", "FACES", "FRONT", "LEFT", "LEVELS",
           "RIGHT", "TOP", "block_mesh_file", "block_mesh_model", "default_cache_dir",
           "describe", "gmsh_model", "level_counts"]
