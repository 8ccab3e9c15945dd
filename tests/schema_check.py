#!/usr/bin/env python3
"""Check docs/schema/assembly.schema.json against the examples and against cairn's own loader.

usage: python3 tests/schema_check.py CAIRN_BINARY [-v]

* every examples/*.json must validate against the schema's root (an assembly file), and every
  JSON file under examples/plans/ against $defs/planFile (a plan file for --plan);
* every tests/cases/*.json is loaded by cairn (`CAIRN check FILE`, or `CAIRN simulate ASSEMBLY
  --plan FILE` when the case's .expect uses the file as a plan file):
    - cairn loaded it (exit status other than 2): the schema must accept it;
    - cairn refused it (exit 2): the schema should reject it. Refusals of the structure (an
      unknown key, a missing key, a wrong type or an enumeration at a JSON path) are counted
      apart from refusals of values the schema cannot judge (convexity, overlaps, references).
Exit 1 when an example, or a case file cairn loaded, is rejected by the schema, or when a case
file cairn refuses for its structure is accepted by the schema; 0 otherwise.
Needs python3 and python3-jsonschema (draft 2020-12). -v lists every case file's verdicts.
"""
import json
import os
import re
import shlex
import subprocess
import sys

try:
    import jsonschema
except ImportError:
    sys.exit("schema_check: python3-jsonschema is missing (apt-get install python3-jsonschema)")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCHEMA = os.path.join(ROOT, "docs", "schema", "assembly.schema.json")
TIMEOUT = 60

# cairn's messages that say the structure is wrong (as opposed to a value it cannot use)
STRUCTURAL = re.compile(
    r"unknown key|expected|missing|found (?:a|an|null)\b|must be (?:a string|2 or 3|\"hold\")"
    r"|is a [23]-D shape|already a shape|has no shape|remove axis|a plan file|needs \"plan\"")
SYNTAX_WHERE = re.compile(r"^\d+:\d+$")  # line:column: the JSON text itself is bad


def strict_load(path):
    """Parse as jansson would: no NaN/Infinity, no numbers that overflow, no duplicate keys."""
    def no_constant(name):
        raise ValueError("invalid token %s" % name)

    def finite(text):
        x = float(text)
        if x in (float("inf"), float("-inf")):
            raise ValueError("real number overflow")
        return x

    def no_duplicates(pairs):
        out = {}
        for k, v in pairs:
            if k in out:
                raise ValueError("duplicate object key %r" % k)
            out[k] = v
        return out

    with open(path, "rb") as f:
        text = f.read().decode("utf-8")
    return json.loads(text, parse_constant=no_constant, parse_float=finite,
                      object_pairs_hook=no_duplicates)


def first_error(validator, doc):
    err = jsonschema.exceptions.best_match(validator.iter_errors(doc))
    if err is None:
        return None
    where = "".join("[%d]" % p if isinstance(p, int) else ".%s" % p for p in err.absolute_path)
    return "%s: %s" % (where.lstrip(".") or "$", err.message[:200])


def plan_case_assembly(case_json):
    """The assembly a case's .expect pairs with this file used as a plan file, or None."""
    expect = case_json[:-len(".json")] + ".expect"
    if not os.path.exists(expect):
        return None
    args = None
    with open(expect) as f:
        for line in f:
            if line.startswith("file:"):
                return None  # the case runs on another file
            if line.startswith("args:"):
                args = line[len("args:"):].strip()
    if not args:
        return None
    argv = shlex.split(args.replace("{examples}", os.path.join(ROOT, "examples")))
    if "--plan" not in argv or argv[0] != "simulate":
        return None
    i = argv.index("--plan")
    if i + 1 >= len(argv) or argv[i + 1] != "{}" or argv[1] in ("{}", "-"):
        return None
    return argv[1]


def run_cairn(cairn, argv):
    """(exit status, message after the file name, where) for one run; status None on timeout."""
    try:
        r = subprocess.run([cairn] + argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return None, "", ""
    lines = r.stderr.decode("utf-8", "replace").strip().splitlines()
    msg = lines[-1] if lines else ""
    if msg.startswith("cairn: "):
        msg = msg[len("cairn: "):]
    for a in argv:  # the message names the file it is about
        if msg.startswith(a + ": "):
            msg = msg[len(a) + 2:]
            break
    # "WHERE: text" where WHERE is a JSON path, "$" or line:column; some messages have none
    where, sep, text = msg.partition(": ")
    if not sep or not re.match(r"^(\$|\d+:\d+|[^\s\"']+)$", where):
        where, text = "", msg
    return r.returncode, text, where


def main():
    args = [a for a in sys.argv[1:] if a != "-v"]
    verbose = "-v" in sys.argv[1:]
    if len(args) != 1:
        sys.exit("usage: python3 tests/schema_check.py CAIRN_BINARY [-v]")
    cairn = os.path.abspath(args[0])
    if not os.access(cairn, os.X_OK):
        if cairn == os.path.join(ROOT, "build", "cairn"):
            print("schema_check: building cairn (make build)")
            subprocess.run(["make", "build"], cwd=ROOT, check=True,
                           stdout=subprocess.DEVNULL)
        if not os.access(cairn, os.X_OK):
            sys.exit("schema_check: %s is not an executable" % cairn)

    with open(SCHEMA) as f:
        schema = json.load(f)
    Validator = jsonschema.validators.validator_for(schema)
    Validator.check_schema(schema)
    assembly_v = Validator(schema)
    plan_v = Validator({"$schema": schema["$schema"], "$defs": schema["$defs"],
                        "$ref": "#/$defs/planFile"})

    failures = []

    def rel(p):
        return os.path.relpath(p, ROOT)

    # examples: every one must be accepted
    ex_dir = os.path.join(ROOT, "examples")
    examples = sorted(os.path.join(ex_dir, n) for n in os.listdir(ex_dir) if n.endswith(".json"))
    plans = sorted(os.path.join(d, n) for d, _, ns in os.walk(os.path.join(ex_dir, "plans"))
                   for n in ns if n.endswith(".json"))
    for files, validator, what in ((examples, assembly_v, "example"),
                                   (plans, plan_v, "plan file")):
        for path in files:
            try:
                doc = strict_load(path)
            except ValueError as e:
                failures.append("%s %s: not JSON cairn reads: %s" % (what, rel(path), e))
                continue
            err = first_error(validator, doc)
            if err:
                failures.append("%s %s rejected by the schema: %s" % (what, rel(path), err))

    # case files: judged by what cairn does with them
    case_dir = os.path.join(ROOT, "tests", "cases")
    cases = sorted(os.path.join(case_dir, n) for n in os.listdir(case_dir) if n.endswith(".json"))
    accepted = structural = structural_hit = other = other_hit = syntax = 0
    plan_cases = 0
    missed = []
    for path in cases:
        asm = plan_case_assembly(path)
        if asm:
            plan_cases += 1
            argv, validator, kind = ["simulate", asm, "--plan", path], plan_v, "plan file"
        else:
            argv, validator, kind = ["check", path], assembly_v, "assembly"
        rc, msg, where = run_cairn(cairn, argv)
        try:
            doc = strict_load(path)
            err = first_error(validator, doc)
        except (ValueError, UnicodeDecodeError) as e:
            doc, err = None, "not JSON: %s" % e
        name = rel(path)
        if rc != 2:  # loaded (a timeout counts as loaded: loading takes far less)
            if err:
                failures.append("%s (%s): cairn %s it (exit %s) but the schema rejects it: %s"
                                % (name, kind, "loads", "timeout" if rc is None else rc, err))
            else:
                accepted += 1
            if verbose and not err:
                print("ok       %s: loaded (exit %s), schema accepts" % (name, rc))
            continue
        if SYNTAX_WHERE.match(where) or doc is None:
            syntax += 1
            if verbose:
                print("syntax   %s: %s" % (name, msg))
            continue
        is_structural = bool(STRUCTURAL.search(msg))
        if is_structural:
            structural += 1
            structural_hit += bool(err)
            if not err:
                missed.append("%s: %s: %s" % (name, where, msg))
        else:
            other += 1
            other_hit += bool(err)
        if verbose:
            print("%-8s %s: cairn %s: %s | schema: %s"
                  % ("struct" if is_structural else "value", name, where, msg,
                     err or "ACCEPTS"))

    if missed:
        print("structural rejections the schema lets through:")
        for m in missed:
            print("  " + m)
    for f in failures:
        print("FAIL " + f)
    print("schema: %d examples, %d plan files, %d case files accepted as cairn accepts them; "
          "%d of %d structural rejections also rejected by the schema (and %d of %d rejections "
          "of values; %d with JSON syntax errors not judged; %d case files checked as plan files)"
          % (len(examples), len(plans), accepted, structural_hit, structural, other_hit, other,
             syntax, plan_cases))
    # the schema keeps up with the loader: a structural refusal it lets through is a failure too
    return 1 if failures or missed else 0


if __name__ == "__main__":
    sys.exit(main())
