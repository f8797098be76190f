"""The FE model as plain arrays: mesh to matrices, contact, drive, loads.

What a scene's block is before any time step: the mesh and its DOLFINx
assembly (dolfinx_adapter, the only module that imports DOLFINx; assembly,
model_cache), the normal load (loads), the penalty contact and the per-node
friction law (contact), the drive spring (drive), the static preload
(preload), the stable step and damping (stability), all of them gathered once
per run (fe_model.build_model), and the products and solves with the
matrices that the compiled loops call (linalg, simd). A new physical part of
the model (a load, a boundary condition, a contact law's arrays) goes here.
Imports nothing else of fem.
"""
