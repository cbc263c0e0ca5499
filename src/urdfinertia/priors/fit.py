"""Fitting the density model and its bands: weighted ridge regression, one package out.

Pure numpy. ``scripts/bench_priors.py`` calls these on the measured CAD links to write the
data file; the tests call them on the saved sample to check that the file's figures are
reproduced by its own held-out folds.

Every link of a package is weighted ``1 / sqrt(n)`` (n: the package's links), so that a
package of 300 links counts for more than one of 9, but not 33 times more. Numeric terms
are standardised before the ridge penalty and the coefficients returned in raw units.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from urdfinertia.priors.terms import NUMERIC


def terms_of(rows: Sequence[dict[str, float]]) -> list[str]:
    """The model's terms present in ``rows``: intercept, numeric, then categories sorted."""
    seen = {name for row in rows for name in row}
    categories = sorted(name for name in seen if ":" in name)
    return ["intercept", *[n for n in NUMERIC if n in seen], *categories]


def design(rows: Sequence[dict[str, float]], terms: Sequence[str]) -> np.ndarray:
    """(n, len(terms)) matrix of the rows' term values (absent terms are 0)."""
    return np.array([[row.get(t, 0.0) for t in terms] for row in rows], dtype=np.float64)


def package_weights(groups: Sequence[str]) -> np.ndarray:
    """``1 / sqrt(n)`` for each row of a package of n rows."""
    names, inverse, counts = np.unique(np.asarray(groups), return_inverse=True,
                                       return_counts=True)
    return 1.0 / np.sqrt(counts[inverse].astype(np.float64))


def fit_ridge(rows: Sequence[dict[str, float]], y: np.ndarray, weights: np.ndarray,
              ridge: float) -> dict[str, float]:
    """Coefficients by term minimising ``sum w (y - X b)^2 + ridge |b|^2`` (intercept and
    standardised numeric terms; the intercept is not penalised)."""
    terms = terms_of(rows)
    x = design(rows, terms)
    y = np.asarray(y, dtype=np.float64)
    w = np.asarray(weights, dtype=np.float64)
    numeric = np.array([t in NUMERIC for t in terms])
    mean = np.where(numeric, np.average(x, axis=0, weights=w), 0.0)
    sd = np.sqrt(np.average((x - mean) ** 2, axis=0, weights=w))
    scale = np.where(numeric & (sd > 1e-12), sd, 1.0)
    z = (x - mean) / scale
    z[:, 0] = 1.0  # the intercept column
    penalty = np.full(len(terms), float(ridge))
    penalty[0] = 0.0
    a = z.T @ (w[:, None] * z) + np.diag(penalty) * float(w.sum())
    b = np.linalg.solve(a, z.T @ (w * y))
    raw = b / scale
    raw[0] = b[0] - float(np.sum(raw[1:] * mean[1:]))
    return {t: float(v) for t, v in zip(terms, raw, strict=True)}


def predict(rows: Sequence[dict[str, float]], coefficients: dict[str, float]) -> np.ndarray:
    """The model's value for each row (terms without a coefficient add nothing)."""
    return np.array([sum(coefficients.get(t, 0.0) * v for t, v in row.items())
                     for row in rows], dtype=np.float64)


def held_out(rows: Sequence[dict[str, float]], y: np.ndarray, groups: Sequence[str],
             ridge: float, fit_mask: np.ndarray | None = None,
             keys: Sequence[object] | None = None) -> np.ndarray:
    """Each row predicted by the model fitted on the other groups (leave one group out).

    ``fit_mask``: only these rows are fitted on (all rows are predicted), e.g. the
    de-duplicated links while every link of a robot is predicted for its total.
    ``keys``: what identifies a link across groups; a row whose key is also in the held-out
    group is not fitted on (the same link in two packages would leak into its own fold).
    """
    names = np.asarray(groups)
    y = np.asarray(y, dtype=np.float64)
    mask = np.ones(len(rows), bool) if fit_mask is None else np.asarray(fit_mask, bool)
    out = np.full(len(rows), np.nan)
    for g in np.unique(names):
        train = mask & (names != g)
        if keys is not None:
            held = {keys[int(i)] for i in np.flatnonzero(names == g)}
            train &= np.array([k not in held for k in keys])
        if not train.any():
            continue
        idx = [int(i) for i in np.flatnonzero(train)]
        coefficients = fit_ridge([rows[i] for i in idx], y[idx],
                                 package_weights(list(names[idx])), ridge)
        test = [int(i) for i in np.flatnonzero(names == g)]
        out[test] = predict([rows[i] for i in test], coefficients)
    return out


def quantile_band(residuals: np.ndarray, level: float) -> tuple[float, float]:
    """The central interval holding ``level`` of the residuals (equal tails)."""
    r = np.asarray(residuals, dtype=np.float64)
    r = r[np.isfinite(r)]
    if not len(r):
        raise ValueError("no residuals")
    lo, hi = np.quantile(r, [(1 - level) / 2, (1 + level) / 2])
    return float(lo), float(hi)


def nested_coverage(residuals: np.ndarray, groups: Sequence[str], level: float,
                    ) -> dict[str, np.ndarray]:
    """Per group, whether each residual lies in the band fitted on the other groups'
    residuals: the honest coverage of a band calibrated on held-out errors."""
    names = np.asarray(groups)
    r = np.asarray(residuals, dtype=np.float64)
    out: dict[str, np.ndarray] = {}
    for g in np.unique(names):
        other = r[(names != g) & np.isfinite(r)]
        mine = r[names == g]
        if not len(other):
            continue
        lo, hi = quantile_band(other, level)
        out[str(g)] = (mine >= lo) & (mine <= hi)
    return out
