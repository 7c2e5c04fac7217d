"""Argument checks shared by the core: every bad input becomes a ValueError naming the parameter."""

import numpy as np


def matrix4(name, value):
    """Return `value` as a finite, invertible 4x4 float64 matrix and its inverse.

    Invertible means a condition number (infinity norm, from the inverse that callers need
    anyway) below 1e15.
    """
    try:
        m = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: not a 4x4 matrix of numbers") from None
    if m.shape != (4, 4):
        raise ValueError(f"{name}: expected a 4x4 matrix, got shape {m.shape}")
    if not np.all(np.isfinite(m)):
        raise ValueError(f"{name}: contains NaN or infinity")
    try:
        inv = np.linalg.inv(m)
    except np.linalg.LinAlgError:
        raise ValueError(f"{name}: matrix is singular") from None
    with np.errstate(over="ignore", invalid="ignore"):
        cond = np.abs(m).sum(axis=1).max() * np.abs(inv).sum(axis=1).max()
    if not np.isfinite(cond) or cond > 1e15:
        raise ValueError(f"{name}: matrix is singular")
    return m, inv


def finite(name, value):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: not a number: {value!r}") from None
    if not np.isfinite(v):
        raise ValueError(f"{name}: must be finite, got {v}")
    return v


def non_negative(name, value):
    v = finite(name, value)
    if v < 0:
        raise ValueError(f"{name}: must be >= 0, got {v}")
    return v


def positive(name, value):
    v = finite(name, value)
    if v <= 0:
        raise ValueError(f"{name}: must be > 0, got {v}")
    return v


def integer(name, value, lo, hi):
    if isinstance(value, bool) or not float(value).is_integer():
        raise ValueError(f"{name}: must be an integer, got {value!r}")
    v = int(value)
    if not lo <= v <= hi:
        raise ValueError(f"{name}: must be in [{lo}, {hi}], got {v}")
    return v
