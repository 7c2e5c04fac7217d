"""The look's formulas (projgrid_addon/water_model.py) evaluated in NumPy, with Blender's Math
node's semantics, for the tests: the same formulas the water group's node tree is built from."""

import numpy as np

from projgrid_addon import look, water_model


class NumPyMaths:
    """water_model's maths on floats and arrays (float64)."""

    max, min, abs = staticmethod(np.maximum), staticmethod(np.minimum), staticmethod(np.abs)
    exp, cos, sin = staticmethod(np.exp), staticmethod(np.cos), staticmethod(np.sin)

    @staticmethod
    def clamp(x):
        return np.clip(x, 0.0, 1.0)

    @staticmethod
    def log(x):
        return np.log(x)

    @staticmethod
    def sqrt(x):
        return np.sqrt(np.maximum(x, 0.0))

    @staticmethod
    def pow(a, b):
        return np.power(np.asarray(a, dtype=np.float64), b)

    @staticmethod
    def less(a, b):
        return np.where(np.asarray(a) < b, 1.0, 0.0)

    @staticmethod
    def greater(a, b):
        return np.where(np.asarray(a) > b, 1.0, 0.0)

    @staticmethod
    def mix(t, a, b):
        return a + t * (b - a)


NUMPY = NumPyMaths()


def group_inputs(filtering, **values):
    """The water group's float inputs for `filtering` (shading.Filtering), others by name."""
    defaults = {name: v for name, v in water_model.DEFAULTS.items() if not hasattr(v, "__len__")}
    return {**defaults, **water_model.values(filtering), **values}


def footprint_log(f, distance, cos_view=1.0):
    """ln L_p at `distance` (m), the view at `cos_view` to the sea plane, for Filtering `f`."""
    d = np.asarray(distance, dtype=np.float64)
    return water_model.footprint(NUMPY, group_inputs(f), d, np.asarray(cos_view, float))[0]


def grain_facs_at(ranks):
    """The Fac of a grain noise whose CDF is the water group's (look.FOAM_RANK, spread
    look.FOAM_GRAIN_STD) at its `ranks` (0 to 1): the CDF inverted."""
    z = np.linspace(-12.0, 12.0, 200_001)
    cdf = water_model.grain_rank(NUMPY, 0.5 + z * look.FOAM_GRAIN_STD)
    return 0.5 + look.FOAM_GRAIN_STD * np.interp(ranks, cdf, z)


def even_ranks(n):
    """n ranks evenly over 0 to 1, each in the middle of its n-th."""
    return (np.arange(n) + 0.5) / n


def grain_facs(n, seed):
    """Fac samples of the grain noise (`grain_facs_at`): inverse transform sampling."""
    return grain_facs_at(np.random.default_rng(seed).uniform(size=n))
