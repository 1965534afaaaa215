"""Collocation assembly of H and G for one body (paper eq. 8-10), vectorised.

Every (collocation point, element) pair falls in one of four classes, by the distance d
from the point to the element over the element's length h:

- far (d/h >= ``far_ratio``): a low-order Gauss rule;
- mid: a high-order Gauss rule;
- near (d/h < ``near_ratio``): a composite rule graded geometrically toward the element's
  closest point (adaptive subdivision);
- singular (the point lies on the element): the element is split at the point; G's
  ln(1/r) term by log-weighted Gauss (exact for log x polynomial), H by singularity
  subtraction with the rigid-body identity, which makes its integrand bounded.

The H rows come out already containing the free term c(x) u(x): with
H u = int T (u(x) - u(s)) dGamma, rigid translations give exactly zero (docs/theory.md).

The distance is the minimum over 9 samples of the element, decided by a bounding circle
of the samples wherever the circle is already far. :mod:`fretbem.bem.assembly` organises the
work (one basis evaluation per segment for all fixed rules); the pair loops are either
compiled (:mod:`fretbem.bem.compiled_loops`, numba: classify and integrate pair by pair straight
into H and G) or numpy (:mod:`fretbem.bem.numpy_loops`); both give the same H and G to
round-off. Loading numba costs about 0.45 s in a fresh process, so by default
(``IntegrationSettings.compiled = None``) the choice is a ski rental: the numpy loops run
until this process has spent on them ``COMPILED_MIN_PAIRS`` (collocation point, element)
pairs, about what loading numba costs; from then on, or at once for a body that large, or
once the compiled loops are loaded anyway, the compiled loops run. A one-off small run
never pays for numba; a sweep, a study or an adaptive run of many small bodies switches
after a few of them, and never loses more than twice the better choice
(docs/performance.md).
"""

from __future__ import annotations

import importlib.util
import sys
import weakref
from collections.abc import Sequence

import attrs
import numpy as np

from fretbem.basis import Basis
from fretbem.errors import ComputationError
from fretbem.validators import count_field, number_field

from . import assembly, images, numpy_loops
from .kernels import KelvinKernel


def _ratio(default: float) -> attrs.Converter:
    return number_field("a distance ratio", f"give e.g. {default:g}", low=0.0, low_open=True)


def _points(default: int) -> attrs.Converter:
    return count_field(f"give e.g. {default} (Gauss points)")


@attrs.frozen(cache_hash=True)
class IntegrationSettings:
    """Quadrature orders and distance thresholds (see module docstring).

    The hash is kept (the block store looks the settings up in its keys several hundred
    times per adaptive run).

    ``compiled``: True for the compiled (numba) assembly, False for numpy, None to choose
    by problem size (``COMPILED_MIN_PAIRS``); the two give the same H and G to round-off.
    """

    far_ratio: float = attrs.field(default=4.0, converter=_ratio(4.0))
    far_points: int = attrs.field(default=6, converter=_points(6))
    near_ratio: float = attrs.field(default=0.5, converter=_ratio(0.5))
    mid_points: int = attrs.field(default=16, converter=_points(16))
    graded_points: int = attrs.field(default=10, converter=_points(10))
    graded_ratio: float = attrs.field(default=0.5, converter=_ratio(0.5))
    singular_points: int = attrs.field(default=16, converter=_points(16))
    log_points: int = attrs.field(default=8, converter=_points(8))
    compiled: bool | None = attrs.field(
        default=None, validator=attrs.validators.optional(attrs.validators.instance_of(bool))
    )


#: (collocation point, element) pairs from which the compiled path repays loading numba in
#: a fresh process (about 0.45 s for the import and the cached kernels, against 1-2 us
#: saved per pair; benchmarks/floor.py, docs/performance.md)
COMPILED_MIN_PAIRS = 400_000


class LoopChoice:
    """The ski rental between the numpy and the compiled (numba) assembly loops.

    Loading numba is paid once per process, so the record of numpy work that decides when
    to pay it is the process's: one instance, :data:`LOOP_CHOICE`, held here beside the
    loops it chooses between. ``reset()`` starts the count again (tests, benchmarks).
    """

    def __init__(self) -> None:
        #: (collocation point, element) pairs this process has assembled with numpy loops
        self.spent = 0

    def compiled(self, pairs: int) -> bool:
        """Whether an assembly of ``pairs`` more pairs should use the compiled loops."""
        if "fretbem.bem.compiled_loops" in sys.modules:  # loaded already: its cost is paid
            return True
        return self.spent + pairs >= COMPILED_MIN_PAIRS and _numba_installed()

    def record(self, pairs: int) -> None:
        """Count an assembly done with the numpy loops."""
        self.spent += pairs

    def reset(self) -> None:
        """Forget the numpy work done so far."""
        self.spent = 0


class CompiledKernelsUnavailableError(ComputationError):
    """``IntegrationSettings(compiled=True)`` was asked for but numba is not installed."""


def _numba_installed() -> bool:
    return importlib.util.find_spec("numba") is not None


#: the process's choice of assembly loops (see :class:`LoopChoice`)
LOOP_CHOICE = LoopChoice()


@attrs.frozen(eq=False)
class Collocation:
    """Where a body collocates: per point its segment, element, local coordinate, position.

    Attributes
    ----------
    segment, element : ndarray of int
    local, parameter : ndarray
    points, normals : ndarray, shape (N, 2)
    """

    segment: np.ndarray
    element: np.ndarray
    local: np.ndarray
    parameter: np.ndarray
    points: np.ndarray
    normals: np.ndarray

    @classmethod
    def of(cls, segments: Sequence[Basis]) -> Collocation:
        """Collocation data of the discretised segments, in segment order.

        Each segment's points are evaluated once per Basis object (:data:`_SEGMENT_POINTS`):
        bodies that share segments (re-meshed on one face) share them, and a segment
        discretised as another's point image (:func:`fretbem.bem.images.source`) takes
        the other's negated.
        """
        parts = []
        for k, basis in enumerate(segments):
            own = _SEGMENT_POINTS.get(basis)
            image = images.source(basis) if own is None else None
            if image in _SEGMENT_POINTS:  # a point image's: its points and normals negated
                elements, local, parameters, points, normals = _SEGMENT_POINTS[image]
                own = _SEGMENT_POINTS[basis] = (
                    elements, local, parameters, -points + 0.0, -normals + 0.0
                )  # fmt: skip
            if own is None:
                elements, local = basis.collocation()
                points, _, _, normals = basis.geometry(elements, local)
                own = (elements, local, basis.collocation_parameters, points, normals)
                _SEGMENT_POINTS[basis] = own
            parts.append((np.full(len(own[0]), k), *own))
        return cls(*(np.concatenate(column) for column in zip(*parts, strict=True)))


#: collocation data per discretised segment (weak keys: it goes with the segment)
_SEGMENT_POINTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def offsets(segments: Sequence[Basis]) -> np.ndarray:
    """First global function index of every segment, and the total at the end."""
    return np.concatenate([[0], np.cumsum([b.n_functions for b in segments])])


class Assembler:
    """Builds H and G for a list of discretised segments of one homogeneous body.

    ``kernel`` is the fundamental solution integrated (plane strain or plane stress).
    """

    def __init__(
        self,
        segments: Sequence[Basis],
        kernel: KelvinKernel,
        settings: IntegrationSettings | None = None,
    ):
        if not isinstance(kernel, KelvinKernel):
            raise TypeError(
                f"Assembler needs a KelvinKernel (e.g. KelvinKernel.of(material)), got {kernel!r}"
            )
        self.segments = tuple(segments)
        self.kernel = kernel
        self.mu, self.nu = kernel.shear_modulus, kernel.effective_nu
        self.settings = settings or IntegrationSettings()
        self.offsets = offsets(self.segments)
        self.n = int(self.offsets[-1])
        self.colloc = Collocation.of(self.segments)

    @property
    def point_element_pairs(self) -> int:
        """Number of (collocation point, element) pairs: the assembly's work."""
        return self.n * sum(basis.n_elements for basis in self.segments)

    @property
    def uses_compiled(self) -> bool:
        """Whether :meth:`assemble` takes the compiled path (see the module docstring)."""
        choice = self.settings.compiled
        if choice is True and not _numba_installed():
            raise CompiledKernelsUnavailableError(
                "IntegrationSettings(compiled=True) needs numba, which is not installed; "
                "pip install numba, or leave compiled=None to use it only when available"
            )
        if choice is not None:
            return choice
        return LOOP_CHOICE.compiled(self.point_element_pairs)

    def assemble(self, g_free: Sequence[int] = ()) -> tuple[np.ndarray, np.ndarray]:
        """Dense H and G, rows 2 s + i (collocation point s), columns 2 b + j (function b).

        ``g_free``: segments whose G columns the caller never reads (traction-free ones in a
        solve); the numpy loops leave them at 0 and skip G's share of the kernel there.
        """
        if self.uses_compiled:
            from . import compiled_loops as loops  # numba: loaded only when chosen
        else:
            loops = numpy_loops
            LOOP_CHOICE.record(self.point_element_pairs)
        return assembly.assemble(self, self.mu, self.nu, loops, frozenset(g_free))
