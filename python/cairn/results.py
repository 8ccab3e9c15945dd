"""What the commands return: dataclasses read from the JSON report (format_version 1), with numpy
arrays where numbers come in rows. Each result keeps the whole report as `report` (a dict), so
nothing the command says is lost."""
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

GOOD, NEGATIVE, UNDECIDED = 0, 1, 3


def _vec(v):
    return np.asarray(v, dtype=float) if v is not None else None


@dataclass(frozen=True)
class Contact:
    """One contact point: parts[0] pushes on parts[1] along `normal` with `force`."""

    id: int
    parts: tuple
    kind: str
    point: np.ndarray
    normal: np.ndarray
    force: float
    force_normalized: float
    friction: Optional[np.ndarray]
    separates: bool
    slides: bool

    @classmethod
    def _from(cls, c):
        return cls(c["id"], tuple(c["parts"]), c.get("kind", ""), _vec(c["point"]), _vec(c["normal"]),
                   float(c["force"]), float(c.get("force_normalized", 0.0)), _vec(c.get("friction")),
                   bool(c.get("separates", False)), bool(c.get("slides", False)))


@dataclass(frozen=True)
class PartMotion:
    """How a part starts to move: `linear` (dimension components) and `angular` (a number in
    2-D, a vector in 3-D), in the report's `motion_quantity`."""

    part: str
    linear: np.ndarray
    angular: object

    @classmethod
    def _from(cls, m):
        ang = m.get("angular")
        return cls(m["part"], _vec(m["linear"]), _vec(ang) if isinstance(ang, list) else float(ang or 0.0))


class _Outcome:
    """`outcome`: what the CLI would exit with (GOOD 0, NEGATIVE 1, UNDECIDED 3)."""

    @property
    def decided(self):
        """False when the search for a motion from rest ran out of budget: no verdict."""
        return self.outcome != UNDECIDED


class _Rows:
    """Contacts as arrays: points (n x dim), normals (n x dim), forces (n)."""

    @property
    def points(self):
        return np.array([c.point for c in self.contacts]).reshape(len(self.contacts), self.dimension)

    @property
    def normals(self):
        return np.array([c.normal for c in self.contacts]).reshape(len(self.contacts), self.dimension)

    @property
    def forces(self):
        return np.array([c.force for c in self.contacts], dtype=float)


@dataclass(frozen=True)
class CheckResult(_Rows, _Outcome):
    """`check`: does the assembly stay put? verdict is "stable", "unstable", "not_guaranteed"
    (with friction: a static solution exists but so does a motion from rest) or "undecided" (the
    search for a motion from rest ran out of budget: no verdict; `decided` is False)."""

    stable: bool
    verdict: str
    dimension: int
    friction: bool
    proof: Optional[str]
    moving_parts: list
    motion: list
    motion_quantity: str
    reference_weight: float
    contacts: list
    outcome: int
    report: dict = field(repr=False)

    @classmethod
    def _from(cls, r, outcome):
        ref = r.get("reference_weight") or {}
        return cls(bool(r["stable"]), r["verdict"], int(r["dimension"]), bool(r.get("friction")),
                   r.get("stability_proof"), list(r.get("moving_parts", [])),
                   [PartMotion._from(m) for m in r.get("motion", [])], r.get("motion_quantity", ""),
                   float(ref.get("weight", 0.0)) if isinstance(ref, dict) else float(ref),
                   [Contact._from(c) for c in r.get("contacts", [])], outcome, r)


@dataclass(frozen=True)
class Step:
    """One simulated plan step: the parts it moves, its status ("stable", "unstable",
    "infeasible", "undecided", ...) and, when it fails, where (`unstable_at`: time, moving
    parts, motion). With simulate(margin=...), a stable step's weakest margins along its path:
    `friction`, `tilt`, `lateral` (PathMargin, or None when not found)."""

    move: list
    status: str
    stable: bool
    start_time: float
    end_time: float
    unstable_at: Optional[dict]
    friction: Optional["PathMargin"]
    tilt: Optional["PathMargin"]
    lateral: Optional["PathMargin"]
    report: dict = field(repr=False)

    @property
    def critical_friction(self):
        if self.friction is None:
            return None
        return self.friction.value if self.friction.value is not None else float("inf")

    @classmethod
    def _from(cls, s):
        m = s.get("margin") or {}
        f, t, l = m.get("friction"), m.get("tilt"), m.get("lateral")
        return cls(list(s.get("move", [])), s.get("status", ""), bool(s.get("stable")),
                   float(s.get("start_time", 0.0)), float(s.get("end_time", 0.0)), s.get("unstable_at"),
                   PathMargin._from(f, "critical", None) if f else None,
                   PathMargin._from(t, "angle", "axis") if t else None,
                   PathMargin._from(l, "factor", "direction") if l else None, s)


@dataclass(frozen=True)
class SimulationResult(_Outcome):
    """`simulate`: the plan along its paths (Algorithm 1). `stable` is the CLI's verdict: every
    step stable, and with assemble=True the assembly run too; `verdict` and `steps` are the
    disassembly run's. `assembly` is the same plan run as an assembly (simulate(...,
    assemble=True)), a SimulationResult of its own, with `invertible` saying whether the two
    agree."""

    stable: bool
    verdict: str
    steps: list
    assembly: Optional["SimulationResult"]
    invertible: Optional[bool]
    outcome: int
    report: dict = field(repr=False)

    @classmethod
    def _from(cls, r, outcome=None):
        asm = r.get("assembly")
        sub = cls._from(asm) if isinstance(asm, dict) else None
        stable = bool(r["stable"]) and (sub is None or sub.stable)
        if outcome is None:  # a run of its own (the assembly run): its own outcome
            outcome = GOOD if stable else UNDECIDED if r.get("verdict") == "undecided" else NEGATIVE
        return cls(stable, r.get("verdict", ""), [Step._from(s) for s in r.get("steps", [])], sub,
                   r.get("invertible"), outcome, r)


@dataclass(frozen=True)
class PlanResult(_Outcome):
    """`plan`: stable disassembly sequences. `best_plan` is the first stable sequence as plan
    steps ({"move", "path", "support"}: the file's plan format, ready to simulate); `orders` the
    stable orders of the parts listed. With plan(margin=...), `margins` ranks the stable
    sequences listed, strongest first: dicts with `sequence` (index into the report's
    "sequences"), `status`, and `critical_friction`, `friction`, `tilt`, `lateral` as
    PathMargin-like dicts with the weakest `step`; `ranked_by` names the kind."""

    stable: bool
    stable_single_part: bool
    best_plan: Optional[list]
    sequence_count: float
    orders: list
    search: dict
    margins: Optional[list]
    ranked_by: Optional[str]
    outcome: int
    report: dict = field(repr=False)

    @classmethod
    def _from(cls, r, outcome):
        m = r.get("margins") or {}
        return cls(bool(r["stable"]), bool(r.get("stable_single_part")), r.get("best_plan"),
                   r.get("sequence_count", 0), list(r.get("stable_orders", [])), r.get("search", {}),
                   m.get("sequences") if m else None, m.get("ranked_by") if m else None, outcome, r)


@dataclass(frozen=True)
class Directions:
    """`directions`: for a part (or the subassembly asked for), whether straight up is free and
    the free directions of translation (unit vectors, one per row)."""

    parts: object
    up_free: Optional[bool]
    free_directions: np.ndarray
    report: dict = field(repr=False)

    @classmethod
    def _from(cls, d, dim):
        free = d.get("free_directions", [])
        return cls(d.get("parts"), d.get("up_free"), np.array(free, dtype=float).reshape(len(free), dim), d)


@dataclass(frozen=True)
class Margin:
    """One margin (`margin`): `value` is the critical friction coefficient, the tilt angle in
    degrees or the lateral factor in g; `direction` the tilt axis or the lateral direction (None
    for friction); `end` "found", "none" (not stable anywhere searched) or "whole_range";
    `not_stable_at` the nearest value where the verdict was not stable, and `verdict_there` that
    verdict; `mechanism` a dict of the parts that move and the pairs that open or slide at
    `mechanism_at`; `stopped`: max_seconds ran out (the bracket is proved, but wider)."""

    value: Optional[float]
    direction: Optional[np.ndarray]
    end: str
    not_stable_at: Optional[float]
    verdict_there: Optional[str]
    verdicts: int
    mechanism: Optional[dict]
    mechanism_at: Optional[float]
    stopped: bool

    @classmethod
    def _from(cls, m, key, dkey):
        v = m.get(key)
        return cls(float(v) if v is not None else None, _vec(m.get(dkey)) if dkey else None, m["end"],
                   m.get("not_stable_at"), m.get("verdict_there"), int(m.get("verdicts", 0)), m.get("mechanism"),
                   m.get("mechanism_at"), bool(m.get("stopped", False)))


@dataclass(frozen=True)
class PathMargin(Margin):
    """A step's weakest margin along its path (simulate(margin=...)): a Margin, and where it is
    (`time`, `distance` along the path) among the `samples` whose margin was found."""

    time: float
    distance: float
    samples: int

    @classmethod
    def _from(cls, m, key, dkey):
        b = Margin._from(m, key, dkey)
        return cls(**{f: getattr(b, f) for f in b.__dataclass_fields__}, time=float(m["time"]),
                   distance=float(m["distance"]), samples=int(m["samples"]))


@dataclass(frozen=True)
class MarginResult(_Outcome):
    """`margin`: how far from falling. verdict as loaded; friction, tilt and lateral are Margin
    (None when not asked for); critical_friction the friction margin's value (inf: none)."""

    verdict: str
    friction: Optional[Margin]
    tilt: Optional[Margin]
    lateral: Optional[Margin]
    outcome: int
    report: dict = field(repr=False)

    @property
    def critical_friction(self):
        if self.friction is None:
            return None
        return self.friction.value if self.friction.value is not None else float("inf")

    @classmethod
    def _from(cls, r, outcome):
        f, t, l = r.get("friction"), r.get("tilt"), r.get("lateral")
        return cls(r["verdict"], Margin._from(f, "critical", None) if f else None,
                   Margin._from(t, "angle", "axis") if t else None,
                   Margin._from(l, "factor", "direction") if l else None, outcome, r)
