"""Irregularity realisations: the one rule by which a study (service or the paper report) runs
``N`` independent samples of a random track.

Realisation ``k`` (1 … N) sets the seed of every random irregularity of the scenario to its
own seed + k − 1: realisation 1 is the scenario as given (for the paper presets, seed 1), the
others draw new samples of the same spectrum. Excitations that are not random (corrugation,
settlement, measured profiles) are unchanged; a scenario without a random one has a single
realisation (:func:`is_random`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["MAX_SERVICE_SEEDS", "SEED_AXIS", "is_random", "realisations", "seed_overrides"]

MAX_SERVICE_SEEDS = 20
"""Most realisations per condition a service study may ask for (``seeds``)."""

SEED_AXIS = "seed"
"""Name of the realisations axis in a study job's ``axes``."""


def _random(exc: Any) -> bool:
    return isinstance(exc, Mapping) and exc.get("kind", "random") == "random"


def is_random(excitation: Sequence[Any]) -> bool:
    """Whether a scenario's ``excitation`` list (mappings) holds a random irregularity."""
    return any(_random(e) for e in excitation or ())


def seed_overrides(excitation: Sequence[Any], k: int) -> dict[str, int]:
    """Dotted-path overrides that make realisation ``k`` of a scenario.

    Parameters
    ----------
    excitation : sequence of mapping
        The scenario's ``excitation`` list (JSON form; a random entry's ``seed`` defaults to 1).
    k : int
        Realisation number, 1 … N (1: the scenario's own seeds).

    Returns
    -------
    dict of str to int
        ``{"excitation.<i>.seed": seed_i + k − 1}`` for every random entry ``i``.
    """
    if k < 1:
        raise ValueError(f"realisation numbers start at 1, got {k}")
    return {f"excitation.{i}.seed": int(e.get("seed", 1)) + k - 1
            for i, e in enumerate(excitation or ()) if _random(e)}


def realisations(n: int) -> list[int]:
    """Realisation numbers 1 … ``n``."""
    return list(range(1, n + 1))
