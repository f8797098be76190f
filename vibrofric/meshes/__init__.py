"""Meshes for the finite-element model: the body on the base as one idea (body.py: a
placed mesh with named groups, ``body_mesh`` making it from a scene's [body]), of which
the block (block.py, hexahedral and cached) is one instance, the built-in shapes
(shapes.py) others and the user's own file (user_mesh.py) the last; levels as sizes
toward the contact (refinement.py), the placement on the base (placement.py), the checks
a body must pass (checks.py), a mesh as arrays (mesh_data.py)."""

from .block import (BACK, BLOCK, CONTACT, DEFAULT_SIZE, FACES, FRONT, LEFT, LEVELS, RIGHT,
                    TOP, block_mesh_file, block_mesh_model, default_cache_dir, describe,
                    gmsh_model, level_counts)
from .body import BLOCK_GROUPS, BodyMesh, block_body, body_mesh
from .shapes import SHAPES
from .user_mesh import SUFFIXES as MESH_SUFFIXES

__all__ = ["BACK", "BLOCK", "BLOCK_GROUPS", "BodyMesh", "block_body", "body_mesh", "CONTACT",
           "DEFAULT_SIZE", "FACES", "FRONT", "LEFT", "LEVELS", "MESH_SUFFIXES", "RIGHT",
           "SHAPES", "TOP", "block_mesh_file", "block_mesh_model", "default_cache_dir",
           "describe", "gmsh_model", "level_counts"]
