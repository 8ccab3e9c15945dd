"""cairn: if I take this part out, along this path, does the rest stay put?

Python interface to libcairn (the C library; install it with `make install`, or point
CAIRN_LIBRARY at libcairn.so.0). An assembly is loaded from a file, a JSON string or a dict in
cairn's assembly format, then checked, simulated along its plan, planned, or asked for its free
directions:

    import cairn
    a = cairn.load("examples/blocks.json")
    r = a.check()
    print(r.verdict, r.moving_parts, r.forces)

Every call raises InputError (bad input, with `where`: the JSON path), NumericalError (no
verdict) or FileError; verdicts are results, not exceptions. "undecided" (a static solution
exists, the search for a motion from rest ran out of budget) is a result whose `decided` is
False, as the CLI's exit status 3.
"""
import json
import os
import threading

from . import _lib
from .errors import CairnError, FileError, InputError, NumericalError, OutOfMemoryError
from .results import (CheckResult, Contact, Directions, Margin, MarginResult, PartMotion, PathMargin, PlanResult,
                      SimulationResult, Step, GOOD, NEGATIVE, UNDECIDED)

__version__ = "0.1.0"
__all__ = ["load", "Assembly", "library_version", "CairnError", "InputError", "NumericalError",
           "FileError", "OutOfMemoryError", "CheckResult", "SimulationResult", "PlanResult", "Directions",
           "Margin", "MarginResult", "PathMargin",
           "Contact", "PartMotion", "Step", "GOOD", "NEGATIVE", "UNDECIDED"]


def library_version():
    """The version of the C library in use."""
    return _lib.version()


class Assembly:
    """A loaded assembly (immutable). Free it early with close() or a `with` block; it is freed
    when collected otherwise."""

    def __init__(self, ptr, source):
        self._ptr = ptr
        self.source = source
        # close() while another thread runs a command on it: freed when the last one returns
        self._lock = threading.Lock()
        self._busy = 0
        self._closing = False

    def __copy__(self):
        raise TypeError("a cairn.Assembly cannot be copied (it owns a C object); load it again")

    def __deepcopy__(self, memo):
        self.__copy__()

    def __reduce__(self):
        raise TypeError("a cairn.Assembly cannot be pickled; pickle its source and load it again")

    def close(self):
        """Free the C object now, or, if another thread is running a command on it, as soon as
        that returns; later commands raise InputError."""
        lock = getattr(self, "_lock", None)
        if lock is None:  # never fully made
            return
        with lock:
            if self._ptr is None:
                return
            if self._busy:
                self._closing = True
                return
            ptr, self._ptr = self._ptr, None
        if ptr.value:
            _lib.free(ptr)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    def _run(self, command, options):
        opts = {k: v for k, v in options.items() if v is not None}
        with self._lock:
            if self._ptr is None or self._closing:
                raise InputError("the assembly was closed", "", self.source)
            self._busy += 1
            ptr = self._ptr
        try:
            text, outcome = _lib.run(ptr, command, _dumps(opts, "options"), self.source, "figure" in opts)
        finally:
            with self._lock:
                self._busy -= 1
                last = self._closing and self._busy == 0
                if last:
                    self._ptr = None
            if last and ptr.value:
                _lib.free(ptr)
        return json.loads(text), outcome

    def check(self, *, solver=None, lp_check=None, accept_prestress=None, assume_planar=None, search_budget=None,
              reading=None, max_seconds=None, figure=None):
        """Does the assembly stay put? (`cairn check`.) solver: "auto", "lemke" or "pivot";
        lp_check=False skips the frictionless LP cross-check; accept_prestress=True takes a
        static solution as enough with friction (the weak reading); assume_planar=True: a 3-D
        prism (every part extruded along one axis across gravity) left undecided takes its 2-D
        section's verdict when that is stable (motions out of the section's plane assumed away;
        the section's own verdict is in the result's report["section"]); search_budget: LPs spent
        proving that nothing moves (default 5e7 over the square of its complementarity pairs,
        from 2000 to 20000); max_seconds: the wall time each such search
        may take (then undecided; the verdict depends on the machine's speed); reading: decide
        only that reading of the corner-on-corner contacts' normals; figure: a PNG file that
        receives the check's figure, as `cairn check --figure` draws it (needs
        libcairn_figure.so.0, installed beside libcairn)."""
        if figure is not None:
            figure = os.fspath(figure)
        r, o = self._run("check", dict(solver=solver, lp_check=lp_check, accept_prestress=accept_prestress,
                                       assume_planar=assume_planar, search_budget=search_budget, reading=reading, max_seconds=max_seconds,
                                       figure=figure))
        return CheckResult._from(r, o)

    def simulate(self, *, assemble=None, cold=None, accept_prestress=None, search_budget=None, margin=None):
        """Simulate the plan along its paths, every sample checked (`cairn simulate`; the
        assembly needs a plan). assemble=True also runs it backwards, as an assembly.
        margin=True (or a dict of margin's options: only, pair, axis, direction, margin_tol)
        finds each stable step's weakest margins along its path (Step.friction, .tilt,
        .lateral)."""
        r, o = self._run("simulate", dict(assemble=assemble, cold=cold, accept_prestress=accept_prestress,
                                          search_budget=search_budget, margin=_margin_option(margin)))
        return SimulationResult._from(r, o)

    def plan(self, *, all=None, subassemblies=None, exhaustive=None, max_sub=None, support=None,
             max_states=None, max_seconds=None, accept_prestress=None, search_budget=None, margin=None):
        """Search stable disassembly sequences and paths (`cairn plan`). exhaustive=True expands
        every state past 16 free parts too (bound it with max_states or max_seconds). margin=True
        (or a dict of margin's options) simulates each stable sequence listed with its margins
        and ranks them, strongest first (PlanResult.margins)."""
        r, o = self._run("plan", dict(all=all, subassemblies=subassemblies, exhaustive=exhaustive,
                                      max_sub=max_sub, support=support,
                                      max_states=max_states, max_seconds=max_seconds,
                                      accept_prestress=accept_prestress, search_budget=search_budget,
                                      margin=_margin_option(margin)))
        return PlanResult._from(r, o)

    def margin(self, *, only=None, pair=None, axis=None, direction=None, margin_tol=None, max_seconds=None,
               accept_prestress=None, assume_planar=None, search_budget=None):
        """How far from falling (`cairn margin`): the critical friction, the tilt angle and the
        lateral factor, each with the mechanism at collapse. only: a list of "friction", "tilt",
        "lateral"; pair: two part names (only their friction varies); axis, direction: the tilt
        axis and the lateral direction (default: the weakest); max_seconds leaves the brackets
        as they stand when it runs out (proved, wider: `stopped`)."""
        if isinstance(only, str):
            only = [only]
        r, o = self._run("margin", dict(only=list(only) if only is not None else None,
                                        pair=list(pair) if pair is not None else None,
                                        axis=[float(x) for x in axis] if axis is not None else None,
                                        direction=[float(x) for x in direction] if direction is not None else None,
                                        margin_tol=margin_tol, max_seconds=max_seconds,
                                        accept_prestress=accept_prestress, assume_planar=assume_planar,
                                        search_budget=search_budget))
        return MarginResult._from(r, o)

    def directions(self, parts=None):
        """Free removal directions of every free part, or (parts: a list of names) of that
        subassembly (`cairn directions`). A list of Directions."""
        if isinstance(parts, str):  # one name, not its letters
            parts = [parts]
        r, _ = self._run("directions", dict(parts=list(parts) if parts is not None else None))
        dim = r["dimension"]
        ds = r.get("directions", [])
        if isinstance(ds, dict):
            ds = [ds]
        return [Directions._from(d, dim) for d in ds]

    def contacts(self):
        """The contacts found from the geometry (`cairn contacts`): a list of Contact."""
        r, _ = self._run("contacts", {})
        return [Contact._from(dict(c, force=c.get("force", 0.0))) for c in r.get("contacts", [])]


def _plain(x):
    """numpy arrays and scalars as the lists and numbers JSON takes."""
    if hasattr(x, "tolist"):
        return x.tolist()
    raise TypeError(f"{type(x).__name__} is not a JSON value")


def _dumps(obj, what):
    try:
        return json.dumps(obj, allow_nan=False, default=_plain)
    except ValueError as e:  # NaN or infinity: JSON has neither
        raise InputError(f"not JSON: {e}; give finite numbers", "", what) from None
    except (TypeError, RecursionError) as e:
        raise InputError(f"not JSON: {e}", "", what) from None


def _text(s, src):
    if "\0" in s:
        raise InputError("the JSON text contains a NUL character", "", src)
    try:
        s.encode()
    except UnicodeEncodeError as e:
        raise InputError(f"the JSON text is not valid Unicode: {e}", "", src) from None
    return s


def _margin_option(margin):
    """simulate's and plan's margin=: True, or a dict of margin's options, as the JSON takes it."""
    if not isinstance(margin, dict):
        return margin
    margin = dict(margin)
    if isinstance(margin.get("only"), str):
        margin["only"] = [margin["only"]]
    for k in ("axis", "direction"):
        if margin.get(k) is not None:
            margin[k] = [float(x) for x in margin[k]]
    for k in ("only", "pair"):
        if margin.get(k) is not None:
            margin[k] = list(margin[k])
    return margin


def load(source, *, plan=None, name=None, friction=None, density=None, tolerance=None, supports=None):
    """An Assembly from a file path (str or os.PathLike), a JSON string (text starting with
    '{') or a dict, in cairn's assembly format or a COMPAS assembly's (a part per block, named by
    its node key). plan: a plan file to use instead of the assembly's own (files only). name: how
    messages call a string or dict (default "<string>", "<dict>"). friction, density, tolerance
    override the file's values; supports: a COMPAS assembly's support node keys (a list), as the
    CLI's --friction, --density, --tolerance and --supports."""
    try:
        opts = _lib.load_options(friction, density, tolerance, [supports] if isinstance(supports, str) else supports)
    except (TypeError, ValueError) as e:
        raise InputError(f"bad load option: {e}", "", name) from None
    if isinstance(source, bytes) and source.lstrip().startswith(b"{"):
        source = source.decode("utf-8", errors="surrogateescape")
    if isinstance(source, dict):
        src = name or "<dict>"
        if plan is not None:
            raise InputError("plan= goes with a file; put the plan in the dict instead", "", src)
        try:
            return Assembly(_lib.load_text(_dumps(source, src), src, opts), src)
        except InputError as e:
            if e.where and e.where.replace(":", "").isdigit():  # a place in text the user never saw
                raise InputError(f"the dict is not an assembly cairn can read: {e.message}", "", src) from None
            raise
    if isinstance(source, str) and source.lstrip().startswith("{"):
        src = name or "<string>"
        if plan is not None:
            raise InputError("plan= goes with a file; put the plan in the JSON text instead", "", src)
        return Assembly(_lib.load_text(_text(source, src), src, opts), src)
    if isinstance(source, (str, bytes, os.PathLike)):
        path = os.fsdecode(source)
        return Assembly(_lib.load_file(path, os.fsdecode(plan) if plan is not None else None, opts), path)
    raise TypeError(f"cairn.load takes a path, a JSON string or a dict, not {type(source).__name__}")
