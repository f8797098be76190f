"""The FE time integrators, and the periodic solver built on their compiled steps.

Every integrator is a run class on time_loop.TimeLoop around a numba step:
explicit (central difference), implicit (generalized-alpha: the scheme in
generalized_alpha, the contact iteration in contact_solve) and reduced
(Craig-Bampton, in reduction); registry lists them for fem.integrator and
picks for "auto" by step_cost. A new integrator is a module here, added to
registry.INTEGRATORS and step_cost. cycle_map turns one base cycle of an
integrator's step into a map of its state, and periodic shoots on it for the
steady cycle (time.method periodic / auto). Imports the model and the outputs
subpackages, never simulate.
"""
