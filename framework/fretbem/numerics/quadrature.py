"""Quadrature rules: Gauss-Legendre and log-weighted Gauss (exact for log x polynomial)."""

from __future__ import annotations

import functools

import attrs
import numpy as np

from fretbem.validators import float_array, shape


@attrs.frozen(eq=False)
class QuadratureRule:
    """Points and weights of a rule on a reference interval.

    Attributes
    ----------
    points, weights : ndarray, shape (n,)
    interval : tuple of float
        The reference interval the rule integrates over.
    """

    points: np.ndarray = attrs.field(converter=float_array, validator=shape(None))
    weights: np.ndarray = attrs.field(converter=float_array, validator=shape(None))
    interval: tuple[float, float] = (-1.0, 1.0)

    @classmethod
    def gauss_legendre(cls, n: int) -> QuadratureRule:
        """n-point Gauss-Legendre on [-1, 1]: exact for polynomials of degree 2n - 1."""
        return _gauss_legendre(int(n))

    @classmethod
    def gauss_log(cls, n: int) -> QuadratureRule:
        """n-point rule for the weight -ln(x) on [0, 1]: exact for -ln(x) x degree 2n - 1."""
        return _gauss_log(int(n))

    def mapped(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Points and weights mapped affinely onto intervals [lo, hi] (broadcast, trailing axis)."""
        a, b = self.interval
        lo, hi = np.asarray(lo, float)[..., None], np.asarray(hi, float)[..., None]
        scale = (hi - lo) / (b - a)
        return lo + (self.points - a) * scale, self.weights * scale


@functools.cache
def _gauss_legendre(n: int) -> QuadratureRule:
    points, weights = np.polynomial.legendre.leggauss(n)
    return QuadratureRule(points, weights, (-1.0, 1.0))


@functools.cache
def _gauss_log(n: int) -> QuadratureRule:
    """Modified Chebyshev algorithm (Gautschi 2004, Alg. 2.1) from shifted-Legendre moments.

    The modified moments of -ln(x) on [0, 1] against the shifted Legendre polynomials are
    known in closed form (1 for k = 0, (-1)^k / (k (k+1)) otherwise), which keeps the
    construction stable in double precision, unlike ordinary moments.
    """
    k = np.arange(2 * n)
    # monic shifted Legendre recurrence on [0, 1]: a_k = 1/2, b_k = k^2 / (4 (4k^2 - 1))
    a = np.full(2 * n, 0.5)
    b = np.zeros(2 * n)
    b[1:] = k[1:] ** 2 / (4.0 * (4.0 * k[1:] ** 2 - 1.0))
    legendre_moments = np.ones(2 * n)
    legendre_moments[1:] = (-1.0) ** k[1:] / (k[1:] * (k[1:] + 1.0))
    # monic normalisation: P*_k has leading coefficient (2k)! / (k!)^2
    lead = np.exp(
        np.array([np.sum(np.log(np.arange(kk + 1, 2 * kk + 1))) for kk in k])
        - np.array([np.sum(np.log(np.arange(1, kk + 1))) for kk in k])
    )
    moments = legendre_moments / lead
    alpha, beta = np.zeros(n), np.zeros(n)
    sigma_prev = np.zeros(2 * n)
    sigma = moments.copy()
    alpha[0] = a[0] + moments[1] / moments[0]
    beta[0] = moments[0]
    for kk in range(1, n):
        sigma_new = np.zeros(2 * n)
        ls = np.arange(kk, 2 * n - kk)
        sigma_new[ls] = (
            sigma[ls + 1]
            - (alpha[kk - 1] - a[ls]) * sigma[ls]
            - beta[kk - 1] * sigma_prev[ls]
            + b[ls] * sigma[ls - 1]
        )
        alpha[kk] = a[kk] + sigma_new[kk + 1] / sigma_new[kk] - sigma[kk] / sigma[kk - 1]
        beta[kk] = sigma_new[kk] / sigma[kk - 1]
        sigma_prev, sigma = sigma, sigma_new
    jacobi = np.diag(alpha) + np.diag(np.sqrt(beta[1:]), 1) + np.diag(np.sqrt(beta[1:]), -1)
    points, vectors = np.linalg.eigh(jacobi)
    return QuadratureRule(points, beta[0] * vectors[0] ** 2, (0.0, 1.0))
