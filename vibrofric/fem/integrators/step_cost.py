"""What a step of each integrator costs, roughly, for fem.integrator = "auto"."""

from .contact_solve import implicit_substeps
from .generalized_alpha import full_system

# What one operation costs, ns (measured on the 2-core development machine;
# only their ratios matter, for fem.integrator = "auto"): a multiply-add in a
# dense product, in a sparse product (BSR), in a sparse triangular solve; a
# vector update per DOF; one friction law update of one node.
COST = {"dense": 1.0, "sparse": 0.5, "solve": 1.6, "vector": 0.5, "friction": 60.0}
FILL = 7.0


def step_cost(system, factor_entries, contacts, substeps) -> float:
    """ns a step, roughly (COST): the solve, M and K, the non-contact rows of Z, three
    iterations (the product with G, the friction law on every node and sub-step)."""
    nc = 3 * contacts
    if system.dense:
        linear = COST["dense"] * (factor_entries + 2 * system.size ** 2)
    else:
        linear = (COST["solve"] * factor_entries + COST["sparse"] * system.stiffness.nnz
                  + COST["vector"] * 4 * system.size)
    rows = COST["dense"] * (system.size - nc) * (nc + 1)
    return linear + rows + 3 * (COST["dense"] * nc * nc + COST["friction"] * contacts * substeps)


def estimated_cost(scene, model) -> float:
    """step_cost of the full model before factorizing it: its LU (minimum degree on
    the block's hexahedral mesh) holds about FILL n^1.5 entries (measured: 139 k at
    720 DOFs, 2.4 M at 4,455)."""
    system = full_system(model)
    return step_cost(system, FILL * system.size ** 1.5, model.contact_nodes.size,
                     implicit_substeps(scene))
