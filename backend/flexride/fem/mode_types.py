"""The names of car-body mode types: one vocabulary for the classifier and for typed targets.

:func:`flexride.fem.classify.classify_mode` builds every name it returns from the constants
here, and calibration targets (``5.03:torsion``, ``8.84:first vertical bending``) are parsed
against the same constants, so a target can only ask for a type the classifier can name.

A classifier name is one type or two joined by ``" + "`` (a cross-section deformation with a
beam-like part, ``floor local + first vertical bending``). Beam-like types carry an order
(``first``, ``second``, ``third``, ``fourth``, then ``5th``, ``6th`` …); the classifier calls
the first torsion mode ``torsion``. A wanted type without an order matches any order.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from flexride.errors import FEModelError

VERTICAL_BENDING = "vertical bending"
LATERAL_BENDING = "lateral bending"
TORSION = "torsion"
RHOMBIC = "rhombic"
SIDE_WALL_BREATHING = "breathing (side walls)"
SIDE_WALLS_LATERAL = "side walls lateral"
ROOF_FLOOR_BREATHING = "roof–floor breathing"
FLOOR_LOCAL = "floor local"
ROOF_LOCAL = "roof local"
SECTION_DEFORMATION = "cross-section deformation"
UNCLASSIFIED = "unclassified"

#: Mode types the classifier names, with what each means (x along the body, y lateral, z up).
MODE_TYPES: dict[str, str] = {
    VERTICAL_BENDING: "beam-like: the cross-sections move rigidly up and down along x",
    LATERAL_BENDING: "beam-like: the cross-sections move rigidly sideways along x",
    TORSION: "beam-like: the cross-sections twist rigidly about x",
    RHOMBIC: "the cross-section shears in its plane (its rectangle becomes a rhombus: one "
             "diagonal lengthens, the other shortens, the roof sways against the floor)",
    SIDE_WALL_BREATHING: "the side walls move laterally against each other",
    SIDE_WALLS_LATERAL: "the side walls move laterally together, the section deforming",
    ROOF_FLOOR_BREATHING: "roof and floor move vertically against each other",
    FLOOR_LOCAL: "the floor deforms most",
    ROOF_LOCAL: "the roof deforms most",
    SECTION_DEFORMATION: "the cross-section deforms (models without named regions)",
}
#: Types that have an order along the body (first, second … from the sign changes along x).
ORDERED_TYPES: frozenset[str] = frozenset({VERTICAL_BENDING, LATERAL_BENDING, TORSION})

_ORDINALS = ("first", "second", "third", "fourth")
_NUMBERED = re.compile(r"^(\d+)(st|nd|rd|th)$")


def ordinal(order: int) -> str:
    """Spelled order: ``first`` … ``fourth``, then ``5th``, ``6th`` and so on."""
    return _ORDINALS[order - 1] if 1 <= order <= len(_ORDINALS) else f"{order}th"


def beam_mode_name(kind: str, order: int) -> str:
    """Name of a beam-like mode of ``kind`` (one of :data:`ORDERED_TYPES`) and ``order``
    (1, 2 …): ``torsion`` for the first torsion mode, else ``<ordinal> <kind>``.
    """
    if kind == TORSION and order <= 1:
        return TORSION
    return f"{ordinal(order)} {kind}"


@dataclass(frozen=True)
class ModeType:
    """A mode type: one of :data:`MODE_TYPES`, with an order for the beam-like types.

    Attributes
    ----------
    base : str
        A key of :data:`MODE_TYPES`.
    order : int or None
        Order along the body (1 = first) of a beam-like type; None for the others, and for a
        wanted type that accepts any order.
    """

    base: str
    order: int | None = None

    def __str__(self) -> str:
        """Canonical spelling, as the classifier writes it (``first vertical bending``)."""
        return self.base if self.order is None else beam_mode_name(self.base, self.order)

    def matches(self, found: ModeType) -> bool:
        """Whether the type ``found`` in a model mode is this wanted type (same base; the same
        order unless this one has none).
        """
        return self.base == found.base and (self.order is None or self.order == found.order)


def _key(text: str) -> str:
    """Spelling-tolerant form: lower case, single spaces, en dash as a hyphen."""
    return " ".join(text.lower().replace("–", "-").split())


_BY_KEY = {_key(name): name for name in MODE_TYPES}


def _allowed() -> str:
    return (", ".join(f"'{name}'" for name in MODE_TYPES)
            + "; bending and torsion may start with an order (first, second, third, 5th …)")


def parse_mode_type(text: str) -> ModeType:
    """A mode type from its spelling (case, spaces and ``-`` for ``–`` are forgiven).

    Parameters
    ----------
    text : str
        E.g. ``torsion``, ``rhombic``, ``first vertical bending``, ``roof-floor breathing``.

    Returns
    -------
    ModeType

    Raises
    ------
    FEModelError
        If the text names no type of :data:`MODE_TYPES` (the message lists them).
    """
    key = _key(text)
    if key in _BY_KEY:
        return ModeType(_BY_KEY[key])
    first, _, rest = key.partition(" ")
    order = _order(first)
    base = _BY_KEY.get(rest)
    if order is not None and base in ORDERED_TYPES:
        return ModeType(base, order)
    raise FEModelError(f"unknown mode type {text.strip()!r}: use one of {_allowed()}")


def _order(word: str) -> int | None:
    """The order a word spells (``first`` → 1, ``5th`` → 5), None if it spells none."""
    if word in _ORDINALS:
        return _ORDINALS.index(word) + 1
    m = _NUMBERED.match(word)
    return int(m.group(1)) if m and int(m.group(1)) > 0 else None


def name_types(name: str) -> tuple[ModeType, ...]:
    """The types in a classifier's name, the dominant one first (``floor local + first
    vertical bending`` → floor local, first vertical bending); none for ``unclassified``.

    Raises
    ------
    FEModelError
        If a part of the name is not in the vocabulary (a classifier out of step with it).
    """
    if name == UNCLASSIFIED:
        return ()
    out = []
    for part in name.split(" + "):
        t = parse_mode_type(part)
        out.append(ModeType(t.base, 1) if t.base == TORSION and t.order is None else t)
    return tuple(out)


def match_rank(wanted: ModeType, name: str) -> int | None:
    """How a model mode named ``name`` (by the classifier) has the ``wanted`` type: 0 as its
    dominant type, 1 as its secondary (beam-like) part, None not at all.
    """
    for rank, found in enumerate(name_types(name)):
        if wanted.matches(found):
            return rank
    return None
