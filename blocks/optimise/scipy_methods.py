"""scipy's Nelder-Mead and differential evolution behind the Complex method's interface, for comparison.

Both minimise over the same box as the Complex method, get the same ``evaluate(points, info)`` batch
function and return the same :class:`~blocks.optimise.complex.OptimiseResult`.

- Nelder-Mead (``scipy.optimize.minimize(method="Nelder-Mead")`` with bounds, which clips its simplex into
  the box): one evaluation at a time by nature, so it never uses more than one worker. Start: a point
  drawn uniformly in the box from the seed, or ``x0``. Stops: ``xatol``/``fatol`` (scipy's absolute
  tolerances, on coordinates as the method sees them) or the budget.
- Differential evolution (``scipy.optimize.differential_evolution``, ``updating="deferred"``): each
  generation is evaluated as one batch (in parallel); seeded; no gradient polish unless asked (the
  polish's evaluations would not be counted in the budget otherwise -- here they are, and stop it).
  Stops: scipy's ``tol``/``atol`` on the population's costs, or the budget (the generations are limited
  to what it allows; a generation that would overrun it is cut short with the budget stop).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from blocks.optimise.complex import OptimiseResult


@dataclass
class NelderMeadSettings:
    max_evaluations: int = 500
    xatol: float = 1e-4
    fatol: float = 1e-6
    x0: list[float] | None = None
    adaptive: bool = False


@dataclass
class DESettings:
    max_evaluations: int = 1000
    popsize: int = 15  # scipy's multiplier: popsize * n designs per generation
    tol: float = 0.01
    atol: float = 0.0
    mutation: tuple[float, float] | float = (0.5, 1.0)
    recombination: float = 0.7
    strategy: str = "best1bin"
    polish: bool = False


def de_generations(s: DESettings, n: int) -> int:
    """The generations after the initial population of popsize * n designs that the budget allows (scipy's
    ``maxiter``); 0: the method only samples its initial population (Latin hypercube) and evolves nothing."""
    return max(0, s.max_evaluations // (s.popsize * n) - 1)


class _Budget(Exception):
    pass


class _Counter:
    """Counts evaluations, stops at the budget, remembers the best point seen."""

    def __init__(self, evaluate: Callable, budget: int, lower, upper):
        self.evaluate, self.budget, self.count = evaluate, budget, 0
        self.lower, self.upper = lower, upper
        self.best_x, self.best_f = None, np.inf
        self.generation = 0

    def batch(self, points: list[np.ndarray], step: str) -> list[float]:
        room = self.budget - self.count
        if room <= 0:
            raise _Budget
        points = [np.clip(np.asarray(p, float), self.lower, self.upper) for p in points]
        cut = len(points) > room
        points = points[:room]
        costs = list(self.evaluate(points, [{"step": step, "iteration": self.generation, "n_rep": 0}] * len(points)))
        self.count += len(points)
        for p, c in zip(points, costs):
            if c < self.best_f:
                self.best_x, self.best_f = p.copy(), float(c)
        if cut:
            raise _Budget
        return costs


def nelder_mead(evaluate: Callable, lower, upper, settings: NelderMeadSettings | None = None,
                seed: int = 0) -> OptimiseResult:
    from scipy.optimize import minimize

    s = settings or NelderMeadSettings()
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    x0 = np.asarray(s.x0, float) if s.x0 is not None else \
        lower + np.random.default_rng([seed, 0]).random(len(lower)) * (upper - lower)
    counter = _Counter(evaluate, s.max_evaluations, lower, upper)

    def f(x):
        counter.generation += 1
        return counter.batch([x], "simplex")[0]

    try:
        res = minimize(f, x0, method="Nelder-Mead", bounds=list(zip(lower, upper)),
                       options={"maxfev": s.max_evaluations, "xatol": s.xatol, "fatol": s.fatol,
                                "adaptive": s.adaptive})
        reason = "converged" if res.success else f"stopped: {res.message}"
        iterations = int(res.nit)
    except _Budget:
        reason, iterations = "budget", counter.generation
    if counter.count >= s.max_evaluations and reason != "converged":
        reason = "budget"
    return OptimiseResult(counter.best_x, counter.best_f, counter.count, iterations, reason)


def differential_evolution(evaluate: Callable, lower, upper, settings: DESettings | None = None,
                           seed: int = 0) -> OptimiseResult:
    from scipy.optimize import differential_evolution as scipy_de

    s = settings or DESettings()
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    n = len(lower)
    counter = _Counter(evaluate, s.max_evaluations, lower, upper)
    size = s.popsize * n
    if s.max_evaluations < size:
        raise ValueError(f"max_evaluations = {s.max_evaluations} is fewer than one generation "
                         f"(popsize * n = {size})")

    def mapper(func, iterable):  # scipy hands a whole generation over at once (updating="deferred")
        counter.generation += 1
        return counter.batch(list(iterable), "generation")

    try:
        res = scipy_de(lambda x: counter.batch([x], "polish")[0], list(zip(lower, upper)), strategy=s.strategy,
                       maxiter=de_generations(s, n), popsize=s.popsize, tol=s.tol, atol=s.atol,
                       mutation=s.mutation, recombination=s.recombination, seed=seed, polish=s.polish,
                       updating="deferred", workers=mapper)
        reason = "converged" if res.success else "budget"
        iterations = int(res.nit)
    except _Budget:
        reason, iterations = "budget", counter.generation
    return OptimiseResult(counter.best_x, counter.best_f, counter.count, iterations, reason)
