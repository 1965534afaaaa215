"""Mortar against node-to-segment on the reference scene: accuracy and cost, to choose one.

The mortar variant (measured here, not shipped) keeps node-to-segment's pairs, frame and
conservative traction transfer, and replaces the pointwise contact conditions at the slave
nodes by weak ones: the gap and the relative displacement of pair k are averages weighted
by the pair traction's own shape function phi_k (the slave face's cardinal function),
g_k = int phi_k g ds / int phi_k ds, integrated on sub-intervals between both faces'
breakpoints. Printed: e_p and e_q max over the reference cycle against Mindlin-Deresiewicz
and the pairing's and the whole cycle's time, for matching and mismatched faces.

    OPENBLAS_NUM_THREADS=1 python benchmarks/pairing_mortar.py
"""

from __future__ import annotations

import statistics
import time

import attrs
import numpy as np

from fretbem.contact.faces import FaceField
from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.contact.pairing import Pairing
from fretbem.numerics.quadrature import QuadratureRule
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run


@attrs.frozen(eq=False)
class MortarPair(NodeToSegmentPair):
    """Node-to-segment with the contact conditions weighted by the slave shape functions."""

    def _pair_up(self) -> Pairing:
        base = super()._pair_up()
        slave = self.slave_side()
        if slave != "lower":
            raise NotImplementedError("the measured variant has the lower face as slave")
        tangent, normal = base.tangents[0], base.normals[0]
        lower, upper = (
            FaceField.of(self.lower, self.lower_tag),
            FaceField.of(self.upper, self.upper_tag),
        )
        order = np.asarray(base.lower_nodes)
        rule = QuadratureRule.gauss_legendre(8)
        upper_breaks = np.concatenate(
            [b.curve.points(np.unique(b.element_bounds)) @ tangent for b in upper.segments]
        )
        rows_s, rows_m, weights, gaps = [], [], [], []
        for index, basis in enumerate(lower.segments):
            seg, params = lower.locate(upper_breaks, tangent)
            cuts = np.unique(
                np.concatenate([np.unique(basis.element_bounds), params[seg == index]])
            )
            lo, hi = cuts[:-1], cuts[1:]
            s = (lo[:, None] + 0.5 * (rule.points[None, :] + 1.0) * (hi - lo)[:, None]).ravel()
            w = (0.5 * rule.weights[None, :] * (hi - lo)[:, None]).ravel()
            points = basis.curve.points(s)
            weights.append(w * basis.curve.jacobians(s))
            rows_s.append(lower.interpolation(np.full(s.shape, index), s))
            m_seg, m_par = upper.locate(points @ tangent, tangent)
            rows_m.append(upper.interpolation(m_seg, m_par))
            gaps.append((upper.points(m_seg, m_par) - points) @ normal)
        phi_s, phi_m = np.concatenate(rows_s), np.concatenate(rows_m)
        w, gap = np.concatenate(weights), np.concatenate(gaps)
        phi_k = phi_s[:, order] * w[:, None]  # (q, n): weight of pair k at each point
        scale = phi_k.sum(axis=0)
        select = np.zeros((lower.n_nodes, len(order)))
        select[order, np.arange(len(order))] = 1.0
        return attrs.evolve(
            base,
            gap=np.maximum((phi_k.T @ gap) / scale, 0.0),
            interpolation={
                "lower": (phi_k.T @ phi_s) / scale[:, None],
                "upper": (phi_k.T @ phi_m) / scale[:, None],
            },
            transfer={"lower": select, "upper": base.transfer["upper"]},
        )


def measure(kind: type, upper: tuple[str, int], lower: tuple[str, int], rounds: int = 3):
    """(e_p, e_q) max over the cycle, median pairing time and median cycle time."""
    simulation = cattaneo_mindlin(pairs=lower[1], basis=lower[0])
    pad = cattaneo_mindlin(pairs=upper[1], basis=upper[0]).pair.upper
    pairing_times, cycle_times, errors = [], [], None
    for _ in range(rounds):
        pair = kind(pad, simulation.pair.lower)
        tic = time.perf_counter()
        pair.pairing()
        pairing_times.append(time.perf_counter() - tic)
        tic = time.perf_counter()
        result = run(attrs.evolve(simulation, pair=pair), check=False)
        cycle_times.append(time.perf_counter() - tic + pairing_times[-1])
        errors = [max(s.errors[k] for s in result.steps) for k in ("e_p_max", "e_q_max")]
    return errors, statistics.median(pairing_times), statistics.median(cycle_times)


def main() -> int:
    cases = [
        (("nurbs", 61), ("nurbs", 61)),
        (("nurbs", 97), ("nurbs", 61)),
        (("lagrange2", 61), ("nurbs", 61)),
        (("lagrange2", 97), ("nurbs", 61)),
        (("lagrange2", 61), ("lagrange2", 61)),
    ]
    print(f"{'pad':<14} {'specimen':<14} {'pairing':<16} {'e_p %':>7} {'e_q %':>7} "
          f"{'pairing s':>10} {'cycle s':>8}")  # fmt: skip
    for upper, lower in cases:
        for kind, label in ((NodeToSegmentPair, "node-to-segment"), (MortarPair, "mortar")):
            (e_p, e_q), t_pair, t_cycle = measure(kind, upper, lower)
            print(f"{upper[0]} {upper[1]:<5} {lower[0]} {lower[1]:<5} {label:<16} "
                  f"{100 * e_p:7.3f} {100 * e_q:7.3f} {t_pair:10.4f} {t_cycle:8.3f}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
