"""The Python package against things it does not compute itself: the CLI's own JSON reports
(the same verdicts and forces), analytic answers (a block on an incline holds when mu >=
tan(theta); a block on a table carries its weight), an invariance (the parts reordered), and the
planner's best plan simulated again. CAIRN_BIN names the cairn binary of the same build."""
import csv
import io
import json
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

import cairn

ROOT = pathlib.Path(__file__).resolve().parents[2]
EX = ROOT / "examples"
CAIRN = os.environ.get("CAIRN_BIN", str(ROOT / "build" / "cairn"))

TABLE = {"name": "table", "fixed": True, "polygon": [[-5, -1], [5, -1], [5, 0], [-5, 0]]}


def cli_json(*args):
    out = subprocess.run([CAIRN, *map(str, args), "--json"], capture_output=True, text=True)
    assert out.returncode in (0, 1, 3), out.stderr
    return json.loads(out.stdout), out.returncode


def block(name, x0, y0, w=2.0, h=1.0):
    return {"name": name, "polygon": [[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h]]}


def test_version():
    assert cairn.library_version() == cairn.__version__


@pytest.mark.parametrize("path", sorted(p.name for p in EX.glob("*.json")))
def test_check_is_the_cli_report(path):
    """Every example: the package's report is the CLI's, key for key, and its verdict and exit
    status are the result's."""
    want, rc = cli_json("check", EX / path)
    with cairn.load(EX / path) as a:
        r = a.check()
    assert r.report == want
    assert r.verdict == want["verdict"] and r.stable == want["stable"]
    assert r.outcome == rc
    assert [c.force for c in r.contacts] == [c["force"] for c in want["contacts"]]


def test_blocks_without_c_tips():
    r = cairn.load(EX / "blocks_without_C.json").check()
    assert not r.stable and r.verdict == "unstable"
    assert r.moving_parts == ["B", "D"]
    assert {m.part for m in r.motion} == {"B", "D"}
    assert isinstance(r.motion[0].angular, float) and r.motion[0].linear.shape == (2,)


def test_weight_on_the_table():
    """A 2 x 1 block of density 3 under g = 10: 60 carried, half at each corner."""
    a = cairn.load({"dimension": 2, "gravity": [0, -10], "parts": [TABLE, dict(block("A", 0, 0), density=3)]})
    r = a.check()
    assert r.stable
    assert r.points.shape == (2, 2) and r.normals.shape == (2, 2)
    np.testing.assert_allclose(r.forces, [30, 30], rtol=1e-12)
    np.testing.assert_allclose(r.normals, [[0, 1], [0, 1]])


@pytest.mark.parametrize("theta_deg", [10, 25, 40])
def test_incline(theta_deg):
    """A block on a table with gravity tilted by theta: it holds when mu >= tan(theta) (strictly
    inside the cone: 5 % either side), slides otherwise."""
    t = math.radians(theta_deg)
    g = [9.81 * math.sin(t), -9.81 * math.cos(t)]
    for mu, holds in ((math.tan(t) * 1.05, True), (math.tan(t) * 0.95, False)):
        r = cairn.load({"dimension": 2, "gravity": g, "friction": mu, "parts": [TABLE, block("A", 0, 0, 1, 1)]}).check()
        assert r.stable is holds, (theta_deg, mu, r.verdict)
        if not holds:
            assert r.moving_parts == ["A"] and r.motion[0].linear[0] > 0


def test_part_order_does_not_matter():
    doc = json.loads((EX / "blocks_without_C.json").read_text())
    doc["parts"] = list(reversed(doc["parts"]))
    r = cairn.load(doc).check()
    assert not r.stable and sorted(r.moving_parts) == ["B", "D"]


def test_sources_agree():
    """A file, its text and its dict load to the same assembly."""
    text = (EX / "blocks.json").read_text()
    reports = [cairn.load(s).check().report for s in (EX / "blocks.json", text, json.loads(text))]
    assert reports[0] == reports[1] == reports[2]


def test_simulate_is_the_cli_report():
    plan = EX / "plans" / "fig6_C_exit_III.json"
    want, rc = cli_json("simulate", EX / "fig6.json", "--plan", plan)
    s = cairn.load(EX / "fig6.json", plan=plan).simulate()
    assert s.report == want and s.outcome == rc == 1
    assert not s.stable and s.steps[0].move == ["C"] and s.steps[0].status == "unstable"
    assert s.steps[0].unstable_at["moving_parts"] == ["E"]
    both = cairn.load(EX / "fig6.json", plan=plan).simulate(assemble=True)
    assert both.assembly is not None and both.invertible is not None


def test_best_plan_simulates_stable():
    """The planner's best plan, put in the file as its plan, is stable when simulated."""
    doc = json.loads((EX / "fig6.json").read_text())
    p = cairn.load(doc).plan()
    assert p.stable and p.best_plan
    want, _ = cli_json("plan", EX / "fig6.json")
    assert p.report == want
    doc["plan"] = p.best_plan
    s = cairn.load(doc).simulate()
    assert s.stable and len(s.steps) == len(p.best_plan)


def test_plan_exhaustive_past_16():
    """Two towers of 9 and 8 blocks: exhaustive=True counts every interleaving, C(17, 8)."""
    p = cairn.load(ROOT / "tests/cases/plan_exhaustive_towers.json").plan(exhaustive=True)
    assert p.stable and p.report["search"]["exhaustive"] and p.report["order_count"] == 24310
    want, _ = cli_json("plan", ROOT / "tests/cases/plan_exhaustive_towers.json", "--exhaustive")
    assert p.report == want


def test_directions():
    ds = cairn.load(EX / "blocks.json").directions()
    by = {d.parts: d for d in ds}
    assert by["C"].up_free and not by["A"].up_free
    assert by["C"].free_directions.shape[1] == 2
    np.testing.assert_allclose(np.linalg.norm(by["C"].free_directions, axis=1), 1)
    sub = cairn.load(EX / "blocks.json").directions(parts=["C", "D"])
    assert len(sub) == 1


def test_contacts():
    cs = cairn.load(EX / "blocks.json").contacts()
    want, _ = cli_json("contacts", EX / "blocks.json")
    assert [c.parts for c in cs] == [tuple(c["parts"]) for c in want["contacts"]]


def test_undecided_is_a_result():
    """The 3-D arch of two voussoirs: a static solution exists; 5 LPs do not decide whether a
    motion from rest does. Not an exception, not stable, not decided; the weak reading holds."""
    def hull(v):
        pts = []
        for y in (0, 1):
            for e in (0, 1):
                ang = math.pi * (v + e) / 2
                for rad in (10, 11.5):
                    pts.append([rad * math.cos(ang), y, rad if v + e == 1 else 0])
        return pts
    doc = {"dimension": 3, "friction": 0.6, "parts": [
        {"name": "ground", "fixed": True, "box": {"min": [-13, -1, -1], "max": [13, 2, 0]}},
        {"name": "left", "hull": hull(0)}, {"name": "right", "hull": hull(1)}]}
    a = cairn.load(doc)
    r = a.check(search_budget=5)
    assert r.verdict == "undecided" and not r.stable and not r.decided and r.outcome == cairn.UNDECIDED
    assert a.check(accept_prestress=True).stable
    # it is a prism along y: its 2-D section is checked too (with the same budget: 5 LPs leave
    # it undecided, 17 prove it), and assume_planar takes the section's verdict when stable
    assert r.report["section"]["axis"] == "y" and r.report["section"]["verdict"] == "undecided"
    assert not a.check(search_budget=5, assume_planar=True).decided
    p = a.check(search_budget=20, assume_planar=True)
    assert p.stable and p.proof == "section_planar_assumed" and p.report["section"]["search_nodes"] == 17
    # a wall-time limit instead: 1 ms does not decide what 5 LPs do not
    r = a.check(search_budget=1000000, max_seconds=0.001)
    assert r.verdict == "undecided" and r.outcome == cairn.UNDECIDED
    with pytest.raises(cairn.InputError):
        a.check(max_seconds=0)


def test_errors_carry_place_and_words():
    doc = {"dimension": 2, "parts": [TABLE, {"name": "L", "polygons": [[[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]]}]}
    with pytest.raises(cairn.InputError) as e:
        cairn.load(doc)
    assert e.value.where == "parts[1].polygons[0]" and "convex" in e.value.message
    assert isinstance(e.value, ValueError)
    # the CLI says the same
    bad = subprocess.run([CAIRN, "check", "-"], input=json.dumps(doc), capture_output=True, text=True)
    assert bad.returncode == 2 and e.value.message in bad.stderr and e.value.where in bad.stderr
    with pytest.raises(cairn.InputError) as e:
        cairn.load('{"dimension": 2,\n "parts": [}')
    assert e.value.where == "2:12"
    with pytest.raises(cairn.FileError):
        cairn.load(EX / "no_such_file.json")
    with pytest.raises(cairn.InputError, match="finite"):
        cairn.load({"dimension": 2, "gravity": [0, float("nan")], "parts": [TABLE]})
    with pytest.raises(TypeError):
        cairn.load(42)
    a = cairn.load(EX / "blocks.json")
    with pytest.raises(cairn.InputError) as e:
        a.check(solver="simplex")
    assert e.value.where == "options.solver"
    with pytest.raises(cairn.InputError) as e:
        a.directions(parts=["E"])
    assert e.value.where == "options.parts[0]"
    with pytest.raises(cairn.InputError) as e:
        a.simulate()
    assert "plan" in e.value.message
    a.close()
    with pytest.raises(cairn.InputError, match="closed"):
        a.check()


def test_review_findings():
    """Found in review: copies, a name for parts, a plan with a dict, the assembly run's verdict,
    numpy values and odd text."""
    import copy
    a = cairn.load(EX / "blocks.json")
    with pytest.raises(TypeError):
        copy.copy(a)
    with pytest.raises(TypeError):
        copy.deepcopy(a)
    # a string is one name, not its letters
    assert [d.parts for d in a.directions(parts="C")] == [d.parts for d in a.directions(parts=["C"])]
    with pytest.raises(cairn.InputError):
        a.directions(parts="AB")
    with pytest.raises(cairn.InputError, match="plan="):
        cairn.load(json.loads((EX / "blocks.json").read_text()), plan=EX / "plans" / "fig1_lift_C.json")
    # numpy numbers and arrays are JSON numbers and lists; a numpy budget is a whole number
    doc = {"dimension": 2, "gravity": np.array([0.0, -10.0]),
           "parts": [TABLE, {"name": "A", "polygon": np.array([[0, 0], [2, 0], [2, 1], [0, 1]])}]}
    assert cairn.load(doc).check(search_budget=np.int64(100)).stable
    assert cairn.load(doc).check(search_budget=2e3).stable
    with pytest.raises(cairn.InputError):
        cairn.load({"dimension": 2, "parts": [TABLE], "x": b"bytes"})
    with pytest.raises(cairn.InputError):
        cairn.load('{"dimension": 2, "parts": []}\x00 garbage')
    with pytest.raises(cairn.InputError):
        cairn.load('{"dimension": 2, "name": "\ud800", "parts": []}')
    with pytest.raises(cairn.InputError) as e:
        cairn.load({"dimension": 2, "parts": [TABLE], "friction": 10 ** 30})
    assert e.value.where == ""  # no line:column of text the user never saw
    assert cairn.load((EX / "blocks.json").read_bytes()).check().stable


def test_assemble_verdict_is_both_runs():
    """friction_drag: stable taken apart, not put together; the CLI exits 1, so `stable` is
    False, and the assembly run is a result of its own."""
    want, rc = cli_json("simulate", EX / "friction_drag.json", "--assemble")
    s = cairn.load(EX / "friction_drag.json").simulate(assemble=True)
    assert rc == 1 and s.outcome == 1 and not s.stable
    assert s.assembly is not None and s.assembly.stable == want["assembly"]["stable"]
    assert s.assembly.outcome == (0 if want["assembly"]["stable"] else 1)
    assert s.stable == (want["stable"] and want["assembly"]["stable"])


def test_long_names_in_contacts():
    """A name longer than 127 bytes whose cut would fall inside a UTF-8 character."""
    long = "A" + "é" * 100
    doc = {"dimension": 2, "parts": [TABLE, dict(block(long, 0, 0))]}
    cs = cairn.load(doc).contacts()
    assert all(c.parts == ("table", long) for c in cs) and len(cs) == 2


def test_compas_and_overrides():
    """A COMPAS assembly read directly, its supports named; the CLI says the same. --friction
    as friction=: the block on the 20-degree incline (mu 0.4 >= tan 20 = 0.364) slides at 0.3."""
    f = EX / "compas" / "cubes.json"
    r = cairn.load(f, supports=[0], friction=0.84).check()
    want, rc = cli_json("check", f, "--supports", "0", "--friction", "0.84")
    assert r.report == want and r.stable and rc == 0
    assert cairn.load(json.loads(f.read_text()), supports="0", friction=0.84).check().report == want
    with pytest.raises(cairn.InputError) as e:
        cairn.load(f)
    assert e.value.where == "--supports"
    assert cairn.load(EX / "incline.json").check().stable
    assert not cairn.load(EX / "incline.json", friction=0.3).check().stable
    # as the CLI, an override that is not a finite number in range is refused, never ignored
    for bad in ({"friction": float("nan")}, {"friction": float("inf")}, {"density": float("nan")},
                {"density": -1.0}, {"tolerance": float("nan")}, {"tolerance": 0.5}):
        with pytest.raises(cairn.InputError) as e:
            cairn.load(EX / "incline.json", **bad)
        assert next(iter(bad)) in str(e.value)


def test_close_while_another_thread_runs(monkeypatch):
    """close() while another thread is inside check(): the C object is freed only when that
    check returns (its result whole), and later calls say the assembly is closed. The library's
    run is held open until close() has returned, so the order is certain."""
    import threading
    from cairn import _lib
    a = cairn.load(EX / "blocks.json")
    inside, release, log, results = threading.Event(), threading.Event(), [], []
    real_run, real_free = _lib.run, _lib.free

    def held_run(*args):
        inside.set()
        release.wait()
        out = real_run(*args)
        log.append("run returned")
        return out

    def logged_free(ptr):
        log.append("freed")
        real_free(ptr)

    monkeypatch.setattr(_lib, "run", held_run)
    monkeypatch.setattr(_lib, "free", logged_free)
    t = threading.Thread(target=lambda: results.append(a.check()))
    t.start()
    inside.wait()
    a.close()
    log.append("close returned")
    release.set()
    t.join()
    assert log == ["close returned", "run returned", "freed"]
    assert len(results) == 1 and results[0].stable
    with pytest.raises(cairn.InputError):
        a.check()
    a.close()  # twice is fine


def test_close_races_with_checks():
    """Many threads check one assembly while another closes it at a random moment, 40 times:
    every call returns a whole result or says the assembly is closed; never a crash, a wrong
    verdict or names from freed memory."""
    import random
    import threading
    rng, seen = random.Random(7), set()
    for _ in range(40):
        a = cairn.load(EX / "blocks.json")
        outcomes, lock = [], threading.Lock()

        def worker():
            for _ in range(3):
                try:
                    r = a.check()
                    names = sorted({n for c in r.contacts for n in c.parts})
                    ok = r.stable and names == ["A", "B", "C", "D", "E"]
                    got = "result" if ok else "wrong"
                except cairn.InputError as e:
                    got = "closed" if "closed" in str(e) else "error: %s" % e
                with lock:
                    outcomes.append(got)

        threads = [threading.Thread(target=worker) for _ in range(6)]
        for t in threads:
            t.start()
        threading.Event().wait(rng.uniform(0, 0.002))
        a.close()
        for t in threads:
            t.join()
        assert len(outcomes) == 18 and set(outcomes) <= {"result", "closed"}, outcomes
        seen.update(outcomes)
    assert seen == {"result", "closed"}  # the close landed among the checks


def test_margin_block_on_a_table(tmp_path):
    """A block 1 wide and 2 high on a table with mu 0.8: it tips before it slides, at a lateral
    load of b/h = 0.5 g and a tilt of atan(0.5); it stands without friction (critical friction
    0). The package's report is the CLI's."""
    scene = {"dimension": 2, "gravity": [0, -9.81], "friction": 0.8,
             "parts": [TABLE, block("block", 0, 0, 1.0, 2.0)]}
    a = cairn.load(scene)
    m = a.margin()
    path = tmp_path / "block.json"
    path.write_text(json.dumps(scene))
    cli, code = cli_json("margin", path)
    assert cli == m.report and code == m.outcome
    assert m.verdict == "stable" and m.outcome == cairn.GOOD
    assert m.critical_friction == 0.0 and m.friction.end == "whole_range"
    assert m.tilt.value == pytest.approx(math.degrees(math.atan(0.5)), rel=1e-6)
    assert m.lateral.value == pytest.approx(0.5, rel=1e-6)
    assert m.lateral.mechanism["moving_parts"][0]["part"] == "block"
    only = a.margin(only="lateral", direction=[-1, 0])
    assert only.friction is None and only.tilt is None
    assert only.lateral.value == pytest.approx(0.5, rel=1e-6)
    assert list(only.lateral.direction) == [-1.0, 0.0]
    timed = a.margin(only="tilt", max_seconds=100)
    assert not timed.tilt.stopped and timed.tilt.mechanism_at > timed.tilt.value
    with pytest.raises(cairn.InputError) as e:
        a.margin(axis=[0, 0, 0])
    assert e.value.where == "options.axis"
    with pytest.raises(cairn.InputError) as e:
        a.margin(only=["tip"])
    assert e.value.where == "options.only"


def test_simulate_margins_along_the_path(tmp_path):
    """A block lifted off a column 1 wide and 4 high (mu 0.3): the column left alone tips at a
    lateral load of b/h = 0.25 g and a tilt of atan(0.25) at every sample; the package's report
    is the CLI's simulate --margin --json."""
    scene = {"dimension": 2, "gravity": [0, -9.81], "friction": 0.3,
             "parts": [TABLE, block("D", 0, 0, 1.0, 4.0), block("C", 0, 4, 1.0, 1.0)],
             "plan": [{"move": "C", "path": [[0, 3]]}]}
    a = cairn.load(scene)
    r = a.simulate(margin=True)
    path = tmp_path / "lift.json"
    path.write_text(json.dumps(scene))
    cli, code = cli_json("simulate", path, "--margin")
    assert cli == r.report and code == r.outcome
    s = r.steps[0]
    assert s.stable and s.critical_friction == 0.0
    assert s.lateral.value == pytest.approx(0.25, rel=1e-4) and s.lateral.samples >= 2
    assert s.tilt.value == pytest.approx(math.degrees(math.atan(0.25)), rel=1e-4)
    assert 0.0 <= s.lateral.distance <= 3.0 and s.lateral.mechanism["moving_parts"][0]["part"] == "D"
    only = a.simulate(margin={"only": "lateral", "direction": [-1, 0], "margin_tol": 1e-6})
    assert only.steps[0].friction is None and only.steps[0].tilt is None
    assert only.steps[0].lateral.value == pytest.approx(0.25, rel=1e-6)
    plain = a.simulate()
    assert plain.steps[0].lateral is None
    csv_path = tmp_path / "lift.csv"
    subprocess.run([CAIRN, "simulate", str(path), "--margin", "--csv", str(csv_path)], check=True,
                   capture_output=True)
    rows = list(csv.DictReader(io.StringIO(csv_path.read_text())))
    found = [float(x["lateral_g"]) for x in rows if x["lateral_g"]]
    assert found and all(v == pytest.approx(0.25, rel=1e-4) for v in found)
    assert all(x["critical_friction"] == "0" for x in rows if x["lateral_g"])
    with pytest.raises(cairn.InputError) as e:
        a.simulate(margin={"only": ["tip"]})
    assert e.value.where == "options.margin.only"
    with pytest.raises(cairn.InputError) as e:
        a.simulate(margin={"axis": [0, 0, 0]})
    assert e.value.where == "options.margin.axis"


def test_plan_margins_rank_the_sequences(tmp_path):
    """A column 1 wide and 3 high beside a block (mu 0.6): taking the block first leaves the
    column alone, which tips at b/h = 1/3 g; taking the column first leaves the block, which
    slides at mu = 0.6 g. The column-first sequences rank first; the report is the CLI's."""
    scene = {"dimension": 2, "gravity": [0, -9.81], "friction": 0.6,
             "parts": [TABLE, block("column", 0, 0, 1.0, 3.0), block("block", 1, 0, 2.0, 1.0)]}
    a = cairn.load(scene)
    r = a.plan(margin={"only": ["lateral"]})
    path = tmp_path / "col.json"
    path.write_text(json.dumps(scene))
    cli, code = cli_json("plan", path, "--margin", "--only", "lateral")
    assert cli == r.report and code == r.outcome
    assert r.ranked_by == "lateral" and len(r.margins) == len(r.report["sequences"])
    values = [m["lateral"]["factor"] for m in r.margins]
    assert values == sorted(values, reverse=True)
    first = r.report["sequences"][r.margins[0]["sequence"]]
    last = r.report["sequences"][r.margins[-1]["sequence"]]
    assert first[0]["move"] == ["column"] and last[0]["move"] == ["block"]
    assert values[0] == pytest.approx(0.6, rel=1e-4) and values[-1] == pytest.approx(1 / 3, rel=1e-4)
    assert r.margins[-1]["lateral"]["step"] == 0


def test_check_figure_is_the_cli_figure(tmp_path):
    a = cairn.load(str(EX / "blocks_without_C.json"))
    mine, cli = tmp_path / "py.png", tmp_path / "cli.png"
    r = a.check(figure=mine)
    assert r.verdict == "unstable"
    subprocess.run([CAIRN, "check", str(EX / "blocks_without_C.json"), "--figure", str(cli)],
                   stdout=subprocess.DEVNULL, check=False)
    assert mine.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert mine.read_bytes() == cli.read_bytes()


def test_check_figure_never_overwrites_the_input(tmp_path):
    src = tmp_path / "blocks.json"
    src.write_bytes((EX / "blocks.json").read_bytes())
    a = cairn.load(str(src))
    with pytest.raises(cairn.InputError) as e:
        a.check(figure=src)
    assert e.value.where == "options.figure" and "read from" in e.value.message
    assert src.read_bytes() == (EX / "blocks.json").read_bytes()
    with pytest.raises(cairn.InputError) as e:
        a.check(figure=tmp_path / "no-such-dir" / "x.png")
    assert e.value.where == "options.figure" and "cannot be written" in e.value.message
