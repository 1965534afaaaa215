"""Sums scattered into a new array: ``np.add.at`` on zeros, at a fraction of its cost."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["added_at"]


def added_at(shape: int | tuple[int, ...], index, values) -> np.ndarray:
    """``np.add.at(np.zeros(shape), index, values)``: the same sums in the same order.

    ``index`` is one array of non-negative indices (a one-dimensional result) or a tuple of
    them, one per axis, broadcast together with ``values`` as ``np.add.at`` does. Through
    ``np.bincount``, which adds the values one after another in their C order as
    ``np.add.at`` does (so the numbers are bit-identical), at about a sixth of its cost for
    the few thousand terms of a face's integrals or collocation matrix.
    """
    shape = (shape,) if isinstance(shape, int | np.integer) else tuple(shape)
    index = index if isinstance(index, tuple) else (index,)
    values = np.asarray(values, dtype=float)
    size = math.prod(shape)
    flat = _flat_without_broadcast(index, shape, values)
    if flat is None:
        *index, values = np.broadcast_arrays(*index, values)
        try:
            flat = index[0] if len(index) == 1 else np.ravel_multi_index(tuple(index), shape)
        except ValueError:
            raise IndexError(f"an index lies outside the result's shape {shape}") from None
    if len(index) == 1 and flat.size and not (flat.min() >= 0 and flat.max() < size):
        # (several indices: ravel_multi_index has checked each against its axis)
        raise IndexError(f"an index lies outside the result's shape {shape}")
    return np.bincount(flat.ravel(), weights=values.ravel(), minlength=size).reshape(shape)


def _flat_without_broadcast(index: tuple, shape: tuple, values: np.ndarray):
    """The flat index when the indices need no broadcasting against ``values`` (the usual
    call: one index array of the values' shape, or several whose broadcast is that shape,
    which ``ravel_multi_index`` forms itself); None otherwise (or on an index outside)."""
    if len(index) == 1:
        first = index[0]
        return first if isinstance(first, np.ndarray) and first.shape == values.shape else None
    try:
        flat = np.ravel_multi_index(index, shape)
    except (ValueError, TypeError):
        return None
    return flat if flat.shape == values.shape else None
