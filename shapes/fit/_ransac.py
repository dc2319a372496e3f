"""A vectorised RANSAC loop (MSAC scoring, adaptive iteration count) and a small
Levenberg-Marquardt refiner, shared by the primitive models."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

from shapes.types import FloatArray

__all__ = ["Model", "RansacResult", "levenberg_marquardt", "ransac", "refine_if_better"]


class Model(Protocol):
    """What :func:`ransac` needs from a primitive model."""

    @property
    def name(self) -> str:
        """A short name for logs."""
        ...

    @property
    def sample_size(self) -> int:
        """Points in a minimal sample."""
        ...

    def hypotheses(
        self, points: FloatArray, normals: FloatArray, idx: npt.NDArray[np.intp]
    ) -> tuple[FloatArray, npt.NDArray[np.bool_]]:
        """Model parameters (H, k) from H minimal samples ``idx`` (H, s), and which are valid."""
        ...

    def distances(self, params: FloatArray, points: FloatArray) -> FloatArray:
        """Distances (H, n) of every point to each of H models (H, k)."""
        ...

    def refine(self, params: FloatArray, points: FloatArray, threshold: float) -> FloatArray:
        """Least-squares refinement of one model on its inliers."""
        ...

    def within_limits(self, params: FloatArray) -> bool:
        """Whether one model respects the radius or angle limits."""
        ...

    def hopeless(self, normals: FloatArray) -> bool:
        """True only when no minimal sample of points with these ``normals`` can give a valid
        hypothesis (so a search would try ``max_iterations`` samples for nothing)."""
        ...


@dataclass(frozen=True)
class RansacResult:
    """The best model found, its inlier mask, the number of hypotheses tried and the points'
    distances to the model (from which the mask was drawn)."""

    params: FloatArray
    inliers: npt.NDArray[np.bool_]
    hypotheses: int
    distances: FloatArray


def _samples(rng: np.random.Generator, n: int, size: int, count: int) -> npt.NDArray[np.intp]:
    """``count`` rows of ``size`` distinct indices below ``n``."""
    return _distinct(rng.integers(0, n, size=(count, size)))


def _distinct(idx: npt.NDArray[np.int64]) -> npt.NDArray[np.intp]:
    """The rows of ``idx`` whose indices are all different, as ``intp``."""
    if idx.shape[1] > 1:
        # Column against column: a sort and an ``all`` along rows of two to four cost more.
        ok = idx[:, 0] != idx[:, 1]
        for i, j in itertools.combinations(range(idx.shape[1]), 2):
            if j > 1:
                ok &= idx[:, i] != idx[:, j]
        idx = idx[ok]
    return idx.astype(np.intp)


def ransac(
    model: Model,
    points: FloatArray,
    normals: FloatArray,
    *,
    threshold: float,
    rng: np.random.Generator,
    max_iterations: int = 1000,
    probability: float = 0.99,
    batch: int = 64,
    refine: bool = True,
    min_iterations: int = 0,
    preview_points: int = 0,
) -> RansacResult | None:
    """Best model by MSAC cost (sum of min(d², thr²)); None if no valid hypothesis was found.

    The number of hypotheses adapts as in PCL: ``log(1 - p) / log(1 - wˢ)`` with w the best
    inlier share so far, capped by ``max_iterations`` and at least ``min_iterations`` (a wrong
    model that explains many points would otherwise stop the search early). With
    ``preview_points``, each batch is first ranked on that many fixed points and only the best
    eighth is scored on all points. The first batch holds all ``min_iterations`` hypotheses
    (at least ``batch``): they are tried whatever the first ones show, so one evaluation of
    them all costs the same arithmetic in fewer numpy calls. When ``model.hopeless(normals)``,
    the samples are drawn as the full search draws them and no hypothesis is built: the result
    (None) and the state ``rng`` is left in are the full search's. After a batch with no valid
    hypothesis, the following ones are built in one call until one holds a valid hypothesis
    (:func:`_ahead`): the same search, hypothesis for hypothesis.
    """
    n = len(points)
    if n < model.sample_size:
        return None
    best_cost = math.inf
    best: FloatArray | None = None
    best_d = np.zeros(0)
    needed, tried = max_iterations, 0
    thr2 = threshold * threshold
    preview = None
    if preview_points and n > 2 * preview_points:
        preview = points[np.sort(rng.choice(n, preview_points, replace=False))]
    hopeless = model.hopeless(normals)
    while tried < needed:
        size = max(batch, min_iterations - tried)
        idx = _samples(rng, n, model.sample_size, min(size, needed - tried))
        tried += size
        if hopeless:
            # Every batch would be drawn and found invalid: draw the same samples (cheap)
            # without building hypotheses, so ``rng`` is left as the full search leaves it.
            continue
        if len(idx):
            params, valid = model.hypotheses(points, normals, idx)
        else:
            params, valid = np.zeros((0, 1)), np.zeros(0, dtype=np.bool_)
        if not valid.any():
            # A batch with no valid hypothesis leaves ``needed`` as it was: the next batches
            # are drawn and built at once, and the search resumes at the first holding one.
            params, valid, tried = _ahead(
                model, points, normals, rng, tried, needed, batch, min_iterations
            )
        params = params[valid]
        if len(params) == 0:
            continue
        keep = max(4, size // 8)
        if preview is not None and len(params) > keep:
            # Preemptive scoring: rank the batch on a fixed subset, score the best fully.
            dp = model.distances(params, preview)
            params = params[np.argsort(np.minimum(dp * dp, thr2).sum(axis=1))[:keep]]
        d = model.distances(params, points)
        cost = np.minimum(d * d, thr2).sum(axis=1)
        k = int(np.argmin(cost))
        if cost[k] < best_cost:
            best_cost, best, best_d = float(cost[k]), params[k], d[k]
            share = float((d[k] < threshold).mean())
            if share >= 1.0:
                needed = max(tried, min_iterations)
            elif share > 0:
                wanted = math.log(1 - probability) / math.log(1 - share**model.sample_size)
                needed = min(max_iterations, max(min_iterations, math.ceil(wanted)))
    if best is None:
        return None
    if refine:
        best = refine_if_better(model, best, points, threshold)
        best_d = model.distances(best[None, :], points)[0]
    return RansacResult(best, best_d < threshold, tried, best_d)


def _ahead(
    model: Model,
    points: FloatArray,
    normals: FloatArray,
    rng: np.random.Generator,
    tried: int,
    needed: int,
    batch: int,
    min_iterations: int,
) -> tuple[FloatArray, npt.NDArray[np.bool_], int]:
    """What :func:`ransac`'s loop does from ``tried`` on while its batches hold no valid
    hypothesis (``needed`` then stays as it is), in one call of ``model.hypotheses``: the
    hypotheses and validity of the first batch that holds a valid one and the ``tried`` count
    after it, with ``rng`` left as that batch's draw leaves it (the later batches' draws are
    undone); or, when none does, an empty batch, ``tried`` at the loop's end and ``rng`` as the
    loop leaves it. Each batch is drawn by the call the loop makes (the same samples), and a
    hypothesis depends on its own sample only, so the search is the loop's, in fewer calls: a
    cluster no sphere or cone fits (a small flat patch) costs one call for all its
    ``max_iterations`` samples, not one a batch."""
    draws, states, counts = [], [], []
    while tried < needed:
        size = max(batch, min_iterations - tried)
        count = min(size, needed - tried)
        draws.append(rng.integers(0, len(points), size=(count, model.sample_size)))
        tried += size
        states.append(rng.bit_generator.state)
        counts.append(tried)
    if not draws:
        return np.zeros((0, 1)), np.zeros(0, dtype=np.bool_), tried
    # Each batch's rows as _samples keeps them, from one pass over all of them.
    batch_of = np.repeat(np.arange(len(draws)), [len(d) for d in draws])
    raw = np.concatenate(draws)
    ok = np.ones(len(raw), dtype=np.bool_)
    for i, j in itertools.combinations(range(raw.shape[1]), 2):
        ok &= raw[:, i] != raw[:, j]
    idx, batch_of = raw[ok].astype(np.intp), batch_of[ok]
    if not len(idx):
        return np.zeros((0, 1)), np.zeros(0, dtype=np.bool_), tried
    params, valid = model.hypotheses(points, normals, idx)
    hits = np.flatnonzero(valid)
    if not len(hits):
        return params[:0], valid[:0], tried
    first = int(batch_of[hits[0]])
    rng.bit_generator.state = states[first]
    rows = batch_of == first
    return params[rows], valid[rows], counts[first]


def refine_if_better(
    model: Model, params: FloatArray, points: FloatArray, threshold: float
) -> FloatArray:
    """``model.refine``, kept only if its MSAC cost is not worse (refining can drift)."""
    refined = model.refine(params, points, threshold)
    if not model.within_limits(refined):
        return params
    d = model.distances(np.stack((params, refined)), points)
    cost = np.minimum(d * d, threshold * threshold).sum(axis=1)
    return refined if np.isfinite(cost[1]) and cost[1] <= cost[0] else params


def levenberg_marquardt(
    residuals: Callable[[FloatArray], FloatArray],
    x0: FloatArray,
    *,
    iterations: int = 12,
    step: float = 1e-6,
) -> FloatArray:
    """Minimise ``sum(residuals(x)**2)`` from ``x0``.

    ``residuals`` is batched: it maps parameter rows (m, k) to residual rows (m, n), so the
    forward-difference Jacobian costs one call.
    """
    x = np.asarray(x0, dtype=np.float64).copy()
    r = residuals(x[None, :])[0]
    cost = float(r @ r)
    lam = 1e-3
    k = len(x)
    identity = np.eye(k)
    for _ in range(iterations):
        h = step * np.maximum(1.0, np.abs(x))
        jac = ((residuals(x + np.diag(h)) - r) / h[:, None]).T
        jtj, jtr = jac.T @ jac, jac.T @ r
        damping = np.diag(np.diag(jtj)) + 1e-9 * identity
        improved = False
        delta = np.zeros(k)
        for _try in range(6):
            try:
                delta = np.linalg.solve(jtj + lam * damping, -jtr)
            except np.linalg.LinAlgError:
                lam *= 10
                continue
            r_new = residuals((x + delta)[None, :])[0]
            cost_new = float(r_new @ r_new)
            if np.isfinite(cost_new) and cost_new < cost:
                improved = cost - cost_new > 1e-6 * cost
                x, r, cost = x + delta, r_new, cost_new
                lam = max(lam / 10, 1e-9)
                break
            lam *= 10
        if not improved or float(np.abs(delta).max()) < 1e-9:
            break
    return x
