"""The pair unknowns x = (p, q, block displacements, block rotations): the one place that
knows their order.

Solvers work on the flat vector x; everything else reads it through :class:`PairUnknowns`
(pressure, shear and each loaded body's block displacement by name), so the order lives
in :class:`UnknownLayout` only.
"""

from __future__ import annotations

from collections.abc import Mapping

import attrs
import numpy as np

from fretbem.errors import InputError


class UnknownsLayoutError(InputError):
    """A pair-unknowns vector or record that does not fit its layout."""


@attrs.frozen
class UnknownLayout:
    """Order of x: n pressures, n shears, (dx, dy) of each body with a loading block, then
    the rotation of each rotating block.

    Attributes
    ----------
    n_pairs : int
    blocks : tuple of str
        Labels ("upper", "lower") of the bodies with a loading block, in the order of x.
    rotations : tuple of str
        Labels of the blocks whose rotation is an unknown (the pad's, when it rotates).
    """

    n_pairs: int
    blocks: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    rotations: tuple[str, ...] = attrs.field(default=(), converter=tuple)

    @property
    def size(self) -> int:
        """Length of x."""
        return 2 * self.n_pairs + 2 * len(self.blocks) + len(self.rotations)

    @property
    def pressure(self) -> slice:
        """Where p sits in x."""
        return slice(0, self.n_pairs)

    @property
    def shear(self) -> slice:
        """Where q sits in x."""
        return slice(self.n_pairs, 2 * self.n_pairs)

    @property
    def tractions(self) -> slice:
        """Where (p, q) sit in x."""
        return slice(0, 2 * self.n_pairs)

    def block(self, label: str) -> slice:
        """Where the block displacement of body ``label`` sits in x."""
        if label not in self.blocks:
            raise UnknownsLayoutError(
                f"body {label!r} has no loading block among the pair unknowns "
                f"(blocks: {list(self.blocks)}); only a body with a LoadingBlock has one"
            )
        start = 2 * self.n_pairs + 2 * self.blocks.index(label)
        return slice(start, start + 2)

    def rotation(self, label: str) -> int:
        """Where the block rotation of body ``label`` sits in x."""
        if label not in self.rotations:
            raise UnknownsLayoutError(
                f"body {label!r} has no block rotation among the pair unknowns (rotations: "
                f"{list(self.rotations)}); only a rotating pad block has one"
            )
        return 2 * self.n_pairs + 2 * len(self.blocks) + self.rotations.index(label)


@attrs.frozen(eq=False)
class PairUnknowns:
    """The pair unknowns by name.

    Attributes
    ----------
    pressure, shear : ndarray, shape (n,)
        p and q at each pair (the traction of the upper body on the lower one: -p n + q t).
    blocks : mapping of str to ndarray (2,)
        Block displacement of each body with a loading block, in the layout's order.
    rotations : mapping of str to float
        Block rotation (rad, counterclockwise, about the rig's pivot) of each rotating block.
    """

    pressure: np.ndarray
    shear: np.ndarray
    blocks: Mapping[str, np.ndarray] = attrs.field(factory=dict)
    rotations: Mapping[str, float] = attrs.field(factory=dict)

    @property
    def layout(self) -> UnknownLayout:
        """The layout this record flattens to."""
        return UnknownLayout(len(self.pressure), tuple(self.blocks), tuple(self.rotations))

    @property
    def vector(self) -> np.ndarray:
        """x = (p, q, block displacements, block rotations in layout order)."""
        parts = [self.pressure, self.shear, *(np.asarray(b, float) for b in self.blocks.values())]
        parts += [np.atleast_1d(np.asarray(r, float)) for r in self.rotations.values()]
        return np.concatenate([np.asarray(p, float).ravel() for p in parts])

    def block(self, label: str) -> np.ndarray:
        """Block displacement of ``label``; zeros for a body without a loading block."""
        return np.asarray(self.blocks.get(label, np.zeros(2)), float)

    def rotation(self, label: str) -> float:
        """Block rotation of ``label``; 0 for a block that does not rotate."""
        return float(self.rotations.get(label, 0.0))

    @classmethod
    def from_vector(cls, x, layout: UnknownLayout) -> PairUnknowns:
        """Split x by ``layout`` (views into x)."""
        x = np.asarray(x, float)
        if x.shape != (layout.size,):
            raise UnknownsLayoutError(
                f"pair unknowns of shape {x.shape} do not fit a layout of {layout.n_pairs} "
                f"pairs, blocks {list(layout.blocks)} and rotations {list(layout.rotations)} "
                f"(length {layout.size})"
            )
        return cls(
            x[layout.pressure],
            x[layout.shear],
            {label: x[layout.block(label)] for label in layout.blocks},
            {label: float(x[layout.rotation(label)]) for label in layout.rotations},
        )
