"""What an FE run records and reports: the rows, the checks, the judgements, the frames.

The recorded rows and the run's end state (recording), the early stop once
the cycle-averaged drive force has settled (steady), the per-step checks for
numerical trouble (trouble), the energy balance (energy), the summed normal
force judged (normal_swing), the contact patch (contact_patch) and the
ParaView frames (paraview). The
integrators call these from their loops; a new recorded quantity or output
file goes here. Imports nothing else of fem.
"""
