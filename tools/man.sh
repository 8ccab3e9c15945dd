#!/usr/bin/env bash
# docs/cairn.1, the manual page, generated from `cairn --help` (one source for both):
#   tools/man.sh build/cairn           writes docs/cairn.1
#   tools/man.sh build/cairn --check   fails when docs/cairn.1 is not what --help says now
# Read it with `man -l docs/cairn.1` (or copy it to a man1 directory of MANPATH).
set -euo pipefail
CAIRN=$1
OUT="$(dirname "$0")/../docs/cairn.1"
version=$("$CAIRN" --version | cut -d' ' -f2)

page() {
  "$CAIRN" --help | awk -v version="$version" '
    function esc(s) { gsub(/\\/, "\\e", s); gsub(/-/, "\\-", s); sub(/^\./, "\\&.", s); sub(/^'"'"'/, "\\&'"'"'", s); return s }
    function flush() {
      if (syn != "") { print ".TP"; print ".B " esc(syn); print esc(desc) }
      syn = ""; desc = ""
    }
    BEGIN {
      print ".TH CAIRN 1 \"\" \"cairn " version "\" \"User Commands\""
      print ".SH NAME"
      print "cairn \\- does the rest of an assembly stay put? Stability of rigid assemblies under gravity by linear complementarity"
      print ".SH SYNOPSIS"
      print ".B cairn"
      print "\\fICOMMAND\\fR \\fIFILE\\fR [\\fIoptions\\fR]"
      print ".SH DESCRIPTION"
      print "cairn reads an assembly of rigid parts (2-D polygons, 3-D polyhedra) from a JSON file, finds the contacts from the geometry and decides whether it stays put (Baraff'"'"'s frictionless LCP, the Stewart\\-Trinkle LCP with Coulomb friction), along a part'"'"'s motion path too; it plans disassembly sequences and finds removal directions. The file format, the verdicts and the examples are described in the README of the source distribution; every error message is listed in docs/errors.md."
      section = ""
    }
    /^commands:/ { section = "cmd"; print ".SH COMMANDS"; next }
    /^exit status:/ { flush(); print ".SH EXIT STATUS"; sub(/^exit status: /, ""); print esc($0); section = "exit"; next }
    section == "cmd" && /^  [a-z]/ { flush(); syn = $0; sub(/^ +/, "", syn); cont = 1; next }
    section == "cmd" && /^           *\[/ && cont { s = $0; sub(/^ +/, "", s); syn = syn " " s; next }
    section == "cmd" && /^      / { cont = 0; s = $0; sub(/^ +/, "", s); desc = desc (desc == "" ? "" : " ") s; next }
    section == "cmd" && /^$/ { flush(); next }
    section == "cmd" && /^[A-Za-z-]/ { flush(); section = "conv"; print ".SH CONVENTIONS"; print esc($0); next }
    section == "conv" && /^$/ { next }
    section == "conv" { print esc($0); next }
    END {
      flush()
      print ".SH FILES"
      print "An assembly is a JSON object: \\fBdimension\\fR (2 or 3), \\fBparts\\fR (each with a \\fBname\\fR, a shape: \\fBpolygon\\fR, \\fBpolygons\\fR, \\fBbox\\fR, \\fBhull\\fR or \\fBmesh\\fR, and \\fBfixed\\fR for supports), optionally \\fBgravity\\fR, \\fBfriction\\fR, \\fBdensity\\fR and a \\fBplan\\fR (steps: \\fBmove\\fR, \\fBpath\\fR, \\fBsupport\\fR \\fBhold\\fR or \\fBpush\\fR). A COMPAS assembly file is read directly. docs/format.md of the source distribution describes every key."
      print ".SH EXAMPLES"
      print "Does a 3-D stack with friction stand, and with what forces:"
      print ".PP"
      print ".RS"
      print ".nf"
      print "cairn check examples/stack3d.json"
      print ".fi"
      print ".RE"
      print ".PP"
      print "Simulate the paper'"'"'s Fig. 4 plan, drawing each step:"
      print ".PP"
      print ".RS"
      print ".nf"
      print "cairn simulate examples/fig4.json \\-\\-plan examples/plans/fig4_lift_A.json \\-\\-figures out"
      print ".fi"
      print ".RE"
      print ".PP"
      print "Every stable disassembly order of four blocks, as JSON:"
      print ".PP"
      print ".RS"
      print ".nf"
      print "cairn plan examples/blocks.json \\-\\-json"
      print ".fi"
      print ".RE"
      print ".PP"
      print "How far a block on an incline is from sliding:"
      print ".PP"
      print ".RS"
      print ".nf"
      print "cairn margin examples/incline.json \\-\\-only friction,tilt"
      print ".fi"
      print ".RE"
      print ".SH SEE ALSO"
      print "The README, docs/cli.md (every option), docs/format.md (the file format), docs/method.md and docs/errors.md (every message) of the cairn source distribution."
    }
  '
}

if [ "${2:-}" = --check ]; then
  if ! diff -u "$OUT" <(page) >/dev/null; then
    echo "docs/cairn.1 is not what 'cairn --help' says now: run tools/man.sh $CAIRN" >&2
    diff -u "$OUT" <(page) | head -20 >&2
    exit 1
  fi
  # the examples run as written (from the source tree), each to a verdict (exit 0 or 1)
  root="$(cd "$(dirname "$0")/.." && pwd)"
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  while IFS= read -r ex; do
    args=$(printf '%s' "${ex#cairn }" | sed 's/\\-/-/g; s/--figures out/--figures '"${tmp//\//\\/}"'\/out/')
    rc=0
    (cd "$root" && eval "\"$CAIRN\" $args" >/dev/null 2>&1) || rc=$?
    if [ "$rc" -gt 1 ]; then echo "manual page: example '$ex' exits $rc" >&2; exit 1; fi
  done < <(sed -n '/^\.SH EXAMPLES/,/^\.SH SEE ALSO/p' "$OUT" | grep '^cairn ')
  echo "manual page: matches --help, its examples run"
else
  page >"$OUT"
fi
