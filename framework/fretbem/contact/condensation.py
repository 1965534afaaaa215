"""Both bodies of a contact pair condensed onto the pair unknowns x = (p, q, blocks).

Each body gives its face displacement as an affine function of the face tractions, its
block displacement and its named loads (:class:`~fretbem.body.ContactResponse`); the
pairing maps pair tractions to face tractions and face displacements to the pair points.
The result is the relative displacement (upper minus lower) in the pair frame and the
block resultants as affine maps of x and of the load amplitudes beta: all a solver needs.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, Protocol

import attrs
import numpy as np

from fretbem.numerics.blas import one_blas_thread

from . import rotation as pad_rotation
from .unknowns import PairUnknowns, UnknownLayout

if TYPE_CHECKING:  # pragma: no cover
    from .pairing import Pairing


class PairedFaces(Protocol):
    """What the condensation needs of a pair (a :class:`~fretbem.contact.pairs.ContactPair`)."""

    def pairing(self) -> Pairing: ...

    def side(self, label: str) -> tuple[Any, str]: ...


SIDES = (("upper", 1.0), ("lower", -1.0))
#: the module whose import loads numba: once it is loaded, the condensation's projection
#: runs compiled too (:func:`_add_traction_map`)
_COMPILED = "fretbem.bem.compiled_loops"


def _assembly_seconds(pair) -> float:
    return sum(b.timings.get("assembly", 0.0) for b in (pair.upper, pair.lower))


@attrs.frozen(eq=False)
class CondensedContact:
    """Relative displacements and block resultants as affine maps of x and the loads.

    With beta the load amplitudes (in ``load_names`` order)::

        relative normal     = normal_base + normal_load @ beta + normal_map @ x
        relative tangential = tangential_base + tangential_load @ beta + tangential_map @ x
        block resultants    = resultant_base + resultant_load @ beta + resultant_map @ x

    Attributes
    ----------
    pair : ContactPair
    pairing : Pairing
    layout : UnknownLayout
        The order of x.
    normal_map, tangential_map : ndarray, shape (n, n_x)
    normal_base, tangential_base : ndarray, shape (n,)
    normal_load, tangential_load : ndarray, shape (n, k)
    resultant_map : (2 m, n_x); resultant_base : (2 m,); resultant_load : (2 m, k)
        Forces the loading blocks apply to their bodies (m bodies with a block).
    lower_force_map : ndarray, shape (2, n_x)
        Resultant force of the contact tractions on the lower body per unit x.
    load_names : tuple of str
    gap : ndarray
        Initial normal gap of each pair.
    seconds : float
        Wall time of the condensation, the bodies' factorisation included (their assembly
        excluded).
    rotation : PadRotation or None
        The pad block's rotation and moment (:mod:`fretbem.contact.rotation`); None where
        the pad's body model cannot rotate its block. Its theta is in x only once
        :func:`~fretbem.contact.rotation.rotating` has put it there.
    """

    pair: PairedFaces
    pairing: Pairing
    layout: UnknownLayout
    normal_map: np.ndarray
    tangential_map: np.ndarray
    normal_base: np.ndarray
    tangential_base: np.ndarray
    normal_load: np.ndarray
    tangential_load: np.ndarray
    resultant_map: np.ndarray
    resultant_base: np.ndarray
    resultant_load: np.ndarray
    lower_force_map: np.ndarray
    load_names: tuple[str, ...]
    gap: np.ndarray
    seconds: float
    rotation: pad_rotation.PadRotation | None = None

    @classmethod
    def build(cls, pair: PairedFaces) -> CondensedContact:
        """Condense both bodies of ``pair`` through its pairing (timed), BLAS on one thread."""
        with one_blas_thread():
            return cls._build(pair)

    @classmethod
    def _build(cls, pair: PairedFaces) -> CondensedContact:
        pairing = pair.pairing()
        start, body_before = time.perf_counter(), _assembly_seconds(pair)
        responses = {label: pair.side(label)[0].contact_response(pair.side(label)[1])
                     for label, _ in SIDES}  # fmt: skip
        n = pairing.n_pairs
        blocks = tuple(label for label, _ in SIDES if responses[label].has_block)
        layout = UnknownLayout(n, blocks)
        names = tuple(
            dict.fromkeys(name for label, _ in SIDES for name in pair.side(label)[0].load_names)
        )
        normals, tangents = pairing.normals, pairing.tangents
        # traction per unit (p, q): on the lower body -p n + q t; on the upper the opposite
        normal_map = np.zeros((n, layout.size))
        tangential_map = np.zeros((n, layout.size))
        relative_base = np.zeros((n, 2))
        relative_load = np.zeros((n, 2, len(names)))
        resultant_map = np.zeros((2 * len(blocks), layout.size))
        resultant_base = np.zeros(2 * len(blocks))
        resultant_load = np.zeros((2 * len(blocks), len(names)))
        lower_force_map = np.zeros((2, layout.size))
        for label, sign in SIDES:
            body = pair.side(label)[0]
            response = responses[label]
            # the pair frame in the body's own axes (a turned pad's differ: Pairing.axes)
            body_normals, body_tangents = pairing.axes(label)
            frame = _frame(body_normals, body_tangents)
            frame = -frame if label == "upper" else frame
            load_columns = [names.index(name) for name in body.load_names]
            relative_base += sign * pairing.to_frame(label, pairing.gather(label, response.base))
            face_nodes = response.n_nodes
            directions = ((normal_map, body_normals), (tangential_map, body_tangents))
            step = _node_to_node(pairing, label, face_nodes)
            if response.traction_blocks is not None and step:
                _add_blocks(response.traction_blocks, step, sign, directions, frame, layout)
            else:
                _add_traction_map(pairing, label, response, sign, directions, frame, layout)
            relative_load[:, :, load_columns] += sign * pairing.to_frame(
                label, pairing.gather(label, response.load_map), axis=1
            )
            force = pairing.pull(label, response.contact_force.reshape(2, face_nodes, 2), axis=1)
            if label == "lower":
                lower_force_map[:, layout.tractions] = _per_pair(force, frame)
            if label in blocks:
                cols = layout.block(label)
                block_rows = slice(2 * blocks.index(label), 2 * blocks.index(label) + 2)
                block = sign * pairing.gather(label, response.block_map)  # (n, 2, 2)
                normal_map[:, cols] += np.einsum("pd,pdc->pc", body_normals, block)
                tangential_map[:, cols] += np.einsum("pd,pdc->pc", body_tangents, block)
                r_traction = pairing.pull(label, response.r_traction.reshape(2, face_nodes, 2), 1)
                resultant_base[block_rows] = response.r_base
                resultant_map[block_rows, layout.tractions] = _per_pair(r_traction, frame)
                resultant_map[block_rows, cols] = response.r_block
                resultant_load[block_rows, :] = _scatter_columns(
                    response.r_load, load_columns, names
                )
        rotation = None
        if pad_rotation.PAD in blocks and responses[pad_rotation.PAD].rotation is not None:
            # the record is in the pad's own axes (turned ones for a pad slid along an arc):
            # its traction frame too: the pair frame seen from them (the upper side's)
            pad_normals, pad_tangents = pairing.axes(pad_rotation.PAD)
            rotation = pad_rotation.condensed(
                pairing, layout, names, pair.side(pad_rotation.PAD)[0],
                responses[pad_rotation.PAD], -_frame(pad_normals, pad_tangents),
                _per_pair,
            )  # fmt: skip
        seconds = time.perf_counter() - start - (_assembly_seconds(pair) - body_before)
        return cls(
            pair=pair,
            pairing=pairing,
            layout=layout,
            normal_map=normal_map,
            tangential_map=tangential_map,
            normal_base=np.einsum("pd,pd->p", normals, relative_base),
            tangential_base=np.einsum("pd,pd->p", tangents, relative_base),
            normal_load=np.einsum("pd,pdk->pk", normals, relative_load),
            tangential_load=np.einsum("pd,pdk->pk", tangents, relative_load),
            resultant_map=resultant_map,
            resultant_base=resultant_base,
            resultant_load=resultant_load,
            lower_force_map=lower_force_map,
            load_names=names,
            gap=pairing.gap,
            seconds=max(seconds, 0.0),
            rotation=rotation,
        )

    @property
    def n_pairs(self) -> int:
        """Number of pairs."""
        return len(self.gap)

    @property
    def blocks(self) -> tuple[str, ...]:
        """Labels of the bodies with a loading block, in the order of x."""
        return self.layout.blocks

    def amplitudes(self, loads: Mapping[str, float]) -> np.ndarray:
        """beta: the load amplitudes in ``load_names`` order (0 for a load not given)."""
        return np.array([float(loads.get(name, 0.0)) for name in self.load_names])

    def bases(self, beta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Normal, tangential and resultant bases at load amplitudes beta."""
        beta = np.asarray(beta, float)
        if beta.size == 0:
            return self.normal_base, self.tangential_base, self.resultant_base
        return (
            self.normal_base + self.normal_load @ beta,
            self.tangential_base + self.tangential_load @ beta,
            self.resultant_base + self.resultant_load @ beta,
        )

    def base_at(self, kind: str, beta: np.ndarray) -> np.ndarray:
        """One of :meth:`bases` alone ("normal", "tangential" or "resultant"), the same
        numbers without forming the other two (the step records read one each)."""
        base = getattr(self, f"{kind}_base")
        beta = np.asarray(beta, float)
        if beta.size == 0:
            return base
        return base + getattr(self, f"{kind}_load") @ beta

    def relative(self, x: np.ndarray, beta: np.ndarray = ()) -> tuple[np.ndarray, np.ndarray]:
        """Relative normal and tangential displacement (upper minus lower) at x and beta."""
        normal_base, tangential_base, _ = self.bases(beta)
        return normal_base + self.normal_map @ x, tangential_base + self.tangential_map @ x

    def relative_normal(self, x: np.ndarray, beta: np.ndarray = ()) -> np.ndarray:
        """The normal one of :meth:`relative` alone: one product with a (pairs, unknowns) map
        instead of two (each reads 3.7 MB at 481 pairs)."""
        return self.base_at("normal", beta) + self.normal_map @ x

    def relative_tangential(self, x: np.ndarray, beta: np.ndarray = ()) -> np.ndarray:
        """The tangential one of :meth:`relative` alone (the slip), one product."""
        return self.base_at("tangential", beta) + self.tangential_map @ x

    def unknowns(self, x: np.ndarray) -> PairUnknowns:
        """x split by name."""
        return PairUnknowns.from_vector(x, self.layout)

    def solutions(self, x: np.ndarray, loads: Mapping[str, float]) -> dict[str, Any]:
        """Each body's fields ("upper", "lower": ``Body.solution``) at pair unknowns x."""
        unknowns = self.unknowns(x)
        lower_frame = np.stack([-self.pairing.normals, self.pairing.tangents], axis=-1)
        pair_traction = (
            lower_frame @ np.stack([unknowns.pressure, unknowns.shear], axis=-1)[..., None]
        )
        out = {}
        for label, _ in SIDES:
            body, tag = self.pair.side(label)
            on_body = pair_traction[..., 0] * (-1.0 if label == "upper" else 1.0)
            on_body = self.pairing.to_body(label, on_body)
            face = self.pairing.scatter(label, on_body, body.contact_face(tag).n_nodes)
            turned = unknowns.rotation(label)
            if turned:  # about the body's own centre: the pivot's translation moved to delta
                block, turned = self.rotation_about_centre(unknowns.block(label), turned)
                out[label] = body.solution(tag, face, block, loads, rotation=turned)
            else:
                out[label] = body.solution(tag, face, unknowns.block(label), loads)
        return out

    def rotation_about_centre(self, block: np.ndarray, theta: float) -> tuple[np.ndarray, float]:
        """The pad block's (delta, theta) about the pivot as (delta', theta) about its body's
        centre: a rotation about P is one about C plus the translation e_z x (C - P)."""
        body = self.pair.side(pad_rotation.PAD)[0]
        centre = body.contact_response(self.pair.side(pad_rotation.PAD)[1]).rotation.centre
        offset = centre - self.rotation.centre
        return np.asarray(block, float) + theta * np.array([-offset[1], offset[0]]), theta


def _add_traction_map(pairing, label, response, sign, directions, frame, layout) -> None:
    """Add one body's traction map, projected on the pair frame, to the normal and
    tangential maps: pair-point rows first, then the traction columns. Paired node to node
    in a process that has loaded numba (the compiled assembly loops), one compiled pass
    with the same arithmetic (:mod:`fretbem.contact.compiled_condensation`)."""
    n, face_nodes = pairing.n_pairs, response.n_nodes
    step = _node_to_node(pairing, label, face_nodes)
    if step and _COMPILED in sys.modules and response.traction_map.dtype == np.float64:
        from . import compiled_condensation

        targets = [target[:, layout.tractions] for target, _ in directions]
        compiled_condensation.add_traction_map(
            np.ascontiguousarray(response.traction_map), step, sign,
            [direction for _, direction in directions], frame, targets,
        )  # fmt: skip
        return
    gathered = _gather(pairing, label, response.traction_map)  # (n, 2, 2 face nodes)
    projected, term = np.empty((n, 2 * face_nodes)), np.empty((n, 2 * face_nodes))
    for target, direction in directions:
        np.multiply(sign * direction[:, 0, None], gathered[:, 0], out=projected)
        projected += np.multiply(sign * direction[:, 1, None], gathered[:, 1], out=term)
        columns = _gather(pairing, label, projected.reshape(n, face_nodes, 2), 1, pull=True)
        _per_pair(columns, frame, add_to=target[:, layout.tractions])


def _frame(normals: np.ndarray, tangents: np.ndarray) -> np.ndarray:
    """(n, 2, 2): per pair, the traction per unit (p, q) on the lower body, -n and t as
    columns (``np.stack([-normals, tangents], axis=-1)`` without its checks)."""
    frame = np.empty((len(normals), 2, 2))
    np.negative(normals, out=frame[..., 0])
    frame[..., 1] = tangents
    return frame


def _add_blocks(blocks, step: int, sign: float, directions, frame, layout) -> None:
    """``_add_traction_map`` for a map ``[[A, B], [-B, A]]`` paired node to node: the same
    products, term by term (so the same numbers), on the two (n, n) blocks in pair order;
    a term whose factor is zero at every pair (a flat face's frame) adds nothing, skipped,
    and one whose factor is 1 or -1 at every pair (the same face's other factors) is its
    block added or subtracted as it is (x * 1 is x and a + (-1 x) is a - x, bit for bit):
    the one pass over the block of a flat pair instead of three."""
    a, b = (block[::step, ::step] for block in blocks)
    n = a.shape[0]
    # which frame entries are non-zero somewhere and which are a unit everywhere, found in
    # one reduction each (not one a term)
    frame_used = np.logical_or.reduce(frame != 0.0, axis=0).tolist()
    frame_unit = _units(frame)
    for target, direction in directions:
        along_x, along_y = sign * direction[:, 0, None], sign * direction[:, 1, None]
        used_x, used_y = np.logical_or.reduce(direction != 0.0, axis=0).tolist()
        unit_x, unit_y = _units(sign * direction)
        # the projected rows per traction component j at node k: x (A, -B), y (B, A), each
        # as (rows, s): s times rows
        rows = (
            _combined(along_x, a, -along_y, b, used_x, used_y, unit_x, -unit_y),
            _combined(along_x, b, along_y, a, used_x, used_y, unit_x, unit_y),
        )
        view = target[:, layout.tractions].reshape(n, 2, n)
        for s in range(2):
            for component, projected in enumerate(rows):
                if projected is None or not frame_used[component][s]:
                    continue
                values, scale = projected
                unit = scale * frame_unit[component][s]
                if unit == 1.0:
                    view[:, s, :] += values
                elif unit == -1.0:
                    view[:, s, :] -= values
                else:  # (-1 x) f is x (-f), bit for bit
                    view[:, s, :] += values * (scale * frame[:, component, s])


def _units(factors: np.ndarray) -> list:
    """Per entry of ``factors``' trailing axes: 1.0 or -1.0 where it is that at every pair
    (the first axis), else 0.0."""
    ones = np.logical_and.reduce(factors == 1.0, axis=0)
    minus = np.logical_and.reduce(factors == -1.0, axis=0)
    return (ones.astype(float) - minus).tolist()


def _combined(first, block, second, other, first_used: bool, second_used: bool,
              first_unit: float = 0.0, second_unit: float = 0.0):  # fmt: skip
    """first * block + second * other (row factors (n, 1)) as (rows, s), s times rows: a
    term whose factors are all zero (``*_used`` False) skipped, None when both are; a lone
    term whose factors are all ``*_unit`` (1 or -1) its block uncopied, with s that unit."""
    if first_used != second_used:  # one term
        unit, factor, values = ((first_unit, first, block) if first_used
                                else (second_unit, second, other))  # fmt: skip
        return (values, unit) if unit else (factor * values, 1.0)
    out = None
    for used, factor, values in ((first_used, first, block), (second_used, second, other)):
        if used:
            term = factor * values
            out = term if out is None else np.add(out, term, out=out)
    return None if out is None else (out, 1.0)


def _node_to_node(pairing: Pairing, side: str, face_nodes: int) -> int:
    """1 (or -1) where the pairs take the face nodes one each in order (or in reverse), else 0."""
    if side in pairing.interpolation or side in pairing.transfer:
        return 0
    nodes = pairing.nodes(side)
    if nodes.size != face_nodes or not face_nodes:
        return 0
    step = 1 if nodes[0] == 0 else -1
    return step if np.array_equal(nodes, np.arange(face_nodes)[::step]) else 0


def _gather(pairing: Pairing, side: str, values: np.ndarray, axis: int = 0, pull=False):
    """``pairing.gather`` (``pull`` if asked), as a view where the pairs take the face nodes
    one each, in order or in reverse order (node to node: no copy of a face-sized operator)."""
    step = _node_to_node(pairing, side, values.shape[axis])
    if step:
        return values[(slice(None),) * axis + (slice(None, None, step),)]
    return (pairing.pull if pull else pairing.gather)(side, values, axis)


def _per_pair(operator: np.ndarray, frame: np.ndarray, add_to: np.ndarray | None = None):
    """Operator (..., n, 2) per pair traction component -> (..., 2 n) per unit (p, q); with
    ``add_to`` (a (..., 2 n) view) added into it in place instead (no (..., 2 n) temporary)."""
    shape = (*operator.shape[:-2], 2, operator.shape[-2])
    if add_to is None:
        out = np.empty(shape)
        for s in range(2):  # out[..., s, k] = sum_j operator[..., k, j] frame[k, j, s]
            np.multiply(operator[..., 0], frame[:, 0, s], out=out[..., s, :])
            out[..., s, :] += operator[..., 1] * frame[:, 1, s]
        return out.reshape(*operator.shape[:-2], -1)
    view = add_to.reshape(shape)  # splits the last axis (unit stride): a view, never a copy
    # each component gathered once into contiguous rows (the operator is often a reversed,
    # strided view: each product read it with stride 2, backwards), the products into one
    # buffer: the same operations in the same order (481 pairs: 4.5 -> 3.7 ms CPU a call)
    parts = np.empty((2, *operator.shape[:-1]))
    parts[0], parts[1] = operator[..., 0], operator[..., 1]
    product = np.empty(operator.shape[:-1])
    for s in range(2):
        for j in range(2):
            view[..., s, :] += np.multiply(parts[j], frame[:, j, s], out=product)
    return add_to


def _scatter_columns(values: np.ndarray, columns: list[int], names: tuple[str, ...]):
    out = np.zeros((values.shape[0], len(names)))
    out[:, columns] = values
    return out
