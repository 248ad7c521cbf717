"""Two-sample tests over seeds: the Mann-Whitney U test and its verdict on a directed claim.

A claim such as "the single stage ends higher than the dual stage" compares two small samples
(one value per seed). The Mann-Whitney U test (Mann and Whitney 1947) asks whether one sample
tends to lie above the other without assuming a distribution; with 5 seeds a side its exact
two-sided p-value can fall to 2 / C(10, 5) = 0.008. :func:`directed_verdict` turns it into the
reproduction page's words: the claim *holds* when the difference lies in its direction with
p < ``ALPHA``, *fails* when it lies the other way with p < ``ALPHA``, and is *not shown*
otherwise.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import stats

#: the significance level of every test on the reproduction page
ALPHA = 0.05


@dataclass(frozen=True)
class Comparison:
    """Two samples, their means and the two-sided Mann-Whitney p-value (NaN when a side has
    fewer than 2 values)."""

    a: tuple[float, ...]
    b: tuple[float, ...]
    p: float

    @property
    def difference(self) -> float:
        """mean(a) - mean(b)."""
        return float(np.mean(self.a) - np.mean(self.b)) if self.a and self.b else math.nan


def compare(a: Sequence[float], b: Sequence[float]) -> Comparison:
    """The two-sided Mann-Whitney U test of ``a`` against ``b`` (exact without ties, the
    normal approximation with them; scipy's ``method="auto"``). Non-finite values are left
    out."""
    xa = tuple(float(x) for x in a if math.isfinite(x))
    xb = tuple(float(x) for x in b if math.isfinite(x))
    if len(xa) < 2 or len(xb) < 2:
        return Comparison(xa, xb, math.nan)
    if len(set(xa + xb)) == 1:  # all equal: no difference to test
        return Comparison(xa, xb, 1.0)
    p = float(stats.mannwhitneyu(xa, xb, alternative="two-sided").pvalue)
    return Comparison(xa, xb, p)


def directed_verdict(c: Comparison, a_higher: bool = True) -> str:
    """"holds", "fails" or "not shown" for the claim that ``a`` lies above ``b`` (below, with
    ``a_higher=False``), at :data:`ALPHA`; "cannot be tested" without two values a side."""
    if math.isnan(c.p):
        return "cannot be tested"
    if c.p >= ALPHA or c.difference == 0.0:
        return "not shown"
    return "holds" if (c.difference > 0.0) == a_higher else "fails"


def p_text(c: Comparison) -> str:
    """``p = 0.008`` (Mann-Whitney U, two-sided), or a dash when not computed."""
    return "p -" if math.isnan(c.p) else f"p = {c.p:.3f}"


__all__ = ["ALPHA", "Comparison", "compare", "directed_verdict", "p_text"]
