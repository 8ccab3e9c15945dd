#!/usr/bin/env python3
"""The quoted outputs of README and docs/*.md, run again and compared, so that the docs cannot
drift from what cairn prints.

Every ```console block is a list of commands (lines starting with "$ ") each followed by the
standard output it prints. A line "..." (indented or not) stands for any number of lines; the
first run of other lines must begin the output and each later run follow in order, line for
line (trailing blanks and times in seconds aside; a line ending in "..." quotes its beginning);
the output may go on past the quote, and the command must end with one of cairn's statuses
(0 to 3), not a crash. Commands run from the
repository's root with `build/cairn` replaced by the binary given; exit statuses are not
compared (a quoted unstable verdict exits 1). A block preceded by the line
"<!-- docs-check: slow -->" runs only with --slow.

    docs_check.py CAIRN [--slow] [--update]

--update writes each block's output back into its file: a quote without "..." by as many of
the output's first lines; in one with "...", each run of quoted lines is replaced by as many output lines from the
place where its first line's first word group (up to the first number) is found again.
"""
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
FILES = ["README.md"] + sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md")
                               if p.name != "gallery.md")  # gallery.md: written by tools/gallery.sh
SLOW_MARK = "<!-- docs-check: slow -->"
SECONDS = 600


def blocks(text):
    """(first line, last line, slow, indent) of each console block's body, 0-based, end
    exclusive; indent: the fence's (a block inside a list item is indented with it)."""
    lines = text.split("\n")
    out, i = [], 0
    while i < len(lines):
        if lines[i].strip() == "```console":
            indent = len(lines[i]) - len(lines[i].lstrip())
            j = i + 1
            while j < len(lines) and lines[j].strip() != "```":
                j += 1
            k = i - 1
            while k >= 0 and not lines[k].strip():
                k -= 1
            out.append((i + 1, j, k >= 0 and lines[k].strip() == SLOW_MARK, indent))
            i = j
        i += 1
    return out


def commands(body):
    """[(command, [quoted lines], offset of the first quoted line)] of one block's lines."""
    out = []
    for n, line in enumerate(body):
        if line.startswith("$ "):
            out.append([line[2:], [], n + 1])
        elif out:
            out[-1][1].append(line)
    for c in out:
        while c[1] and not c[1][-1].strip():
            c[1].pop()
    return out


def chunks(quoted):
    """The runs of quoted lines between "..." lines, and whether the quote starts and ends open."""
    runs, cur = [], []
    for line in quoted:
        if line.strip() == "...":
            runs.append(cur)
            cur = []
        else:
            cur.append(line.rstrip())
    runs.append(cur)
    return runs


def match(quoted, actual):
    """None when the quote matches the output, else the first quoted line that does not."""
    runs = chunks(quoted)
    actual = [a.rstrip() for a in actual]
    pos = 0
    for k, run in enumerate(runs):
        if not run:
            continue
        first = k == 0
        starts = [0] if first else range(pos, len(actual) - len(run) + 1)
        ok = [s for s in starts if same(actual[s:s + len(run)], run)]
        if not ok:
            at = starts[0] if first else pos
            for q, line in enumerate(run):
                if at + q >= len(actual) or not same_line(actual[at + q], line):
                    return line
            return run[-1] if run else "(end of output)"
        pos = ok[0] + len(run)
    return None


TIME = re.compile(r"\b\d+(\.\d+)?(e-?\d+)? s\b")


def same(a, b):
    """Lines equal but for times in seconds ("0.00205 s"), which vary from run to run."""
    return len(a) == len(b) and all(same_line(x, y) for x, y in zip(a, b))


def same_line(actual, quoted):
    """A quoted line that ends in "..." quotes the beginning of the line."""
    actual, quoted = TIME.sub("T s", actual), TIME.sub("T s", quoted)
    if quoted.endswith("...") and len(quoted) > 3:
        return actual.startswith(quoted[:-3].rstrip())
    return actual == quoted


def key_of(line):
    m = re.match(r"\s*[^0-9]*", line)
    return m.group(0) if m else line


def regenerate(quoted, actual):
    """quoted with each run of lines replaced by the output's lines at the same place."""
    actual = [a.rstrip() for a in actual]
    if all(line.strip() != "..." for line in quoted):
        return actual[:len(quoted)]  # a quote is the output's beginning
    out, pos = [], 0
    runs = chunks(quoted)
    for k, run in enumerate(runs):
        if k:
            out.append(next(l for l in quoted if l.strip() == "..."))
        if not run:
            continue
        if k == 0:
            at = 0
        else:
            want = key_of(run[0])
            at = next((s for s in range(pos, len(actual)) if key_of(actual[s]) == want), pos)
        out.extend(actual[at:at + len(run)])
        pos = at + len(run)
    return out


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    cairn = str(pathlib.Path(sys.argv[1]).resolve())
    slow, update = "--slow" in sys.argv, "--update" in sys.argv
    fails = runs = skipped = 0
    for name in FILES:
        path = ROOT / name
        text = path.read_text(errors="surrogateescape")
        lines = text.split("\n")
        edits = []
        for lo, hi, is_slow, indent in blocks(text):
            if is_slow and not slow:
                skipped += 1
                continue
            body = [line[indent:] if line[:indent].strip() == "" else line for line in lines[lo:hi]]
            for cmd, quoted, off in commands(body):
                if not cmd.startswith("build/cairn "):
                    continue
                runs += 1
                argv = cmd.replace("build/cairn", cairn, 1)
                try:
                    done = subprocess.run(argv, shell=True, cwd=ROOT, stdout=subprocess.PIPE,
                                          stderr=subprocess.DEVNULL, text=True, timeout=SECONDS)
                    actual = done.stdout.rstrip("\n").split("\n")
                except subprocess.TimeoutExpired:
                    print(f"FAIL docs: {name}:{lo + off}: '{cmd}' ran past {SECONDS} s")
                    fails += 1
                    continue
                if done.returncode < 0 or done.returncode > 3:  # 0-3 are cairn's answers
                    print(f"FAIL docs: {name}:{lo + off}: '{cmd}' ended with status {done.returncode}")
                    fails += 1
                    continue
                bad = match(quoted, actual)
                if bad is None:
                    continue
                if update:
                    edits.append((lo + off, len(quoted), [" " * indent + x if x else x
                                                          for x in regenerate(quoted, actual)]))
                    continue
                fails += 1
                print(f"FAIL docs: {name}:{lo + off}: '{cmd}' no longer prints the quoted line:\n  {bad}")
        for at, n, new in sorted(edits, reverse=True):
            lines[at:at + n] = new
        if edits:
            path.write_text("\n".join(lines), errors="surrogateescape")
            print(f"docs: {name}: {len(edits)} quoted output{'' if len(edits) == 1 else 's'} written again")
    print(f"docs: {runs} quoted commands run, {fails} differ" + (f", {skipped} slow blocks left out (--slow)" if skipped else ""))
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
