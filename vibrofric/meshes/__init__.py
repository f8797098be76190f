"""Meshes for the finite-element model: the block, hexahedral and cached."""

from .block import (BACK, BLOCK, CONTACT, DEFAULT_SIZE, FACES, FRONT, LEFT, LEVELS, RIGHT,
                    TOP, block_mesh_file, block_mesh_model, default_cache_dir, describe,
                    gmsh_model, level_counts)

__all__ = ["BACK", "BLOCK", "CONTACT", "DEFAULT_SIZE", "FACES", "FRONT", "LEFT", "LEVELS",
           "RIGHT", "TOP", "block_mesh_file", "block_mesh_model", "default_cache_dir",
           "describe", "gmsh_model", "level_counts"]
