"""vibrofric: friction and drive force of a body sliding over an in-plane vibrating base.

    import vibrofric as vf
    scene = vf.load_scene("longitudinal", **{"time.T": 0.3})
    result = vf.run_analytic(scene)        # result.F_dv_over_F_d0, .summary, .timeseries

The API (vibrofric.api) is imported on first use of one of its names, so that
``import vibrofric`` stays light: no numpy, numba or DOLFINx until a scene is
loaded or a model runs.
"""

__version__ = "0.1.0"

__all__ = ["Result", "load_law", "load_scene", "run_analytic", "run_fe", "scene_keys",
           "scene_names", "sweep", "__version__"]


def __getattr__(name: str):
    if name in __all__:
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module 'vibrofric' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
