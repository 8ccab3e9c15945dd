#!/usr/bin/env python3
"""List every input-error message cairn can print: the format strings of the loader's
cn_ld_fail(), cn_diag_set with CN_ERR_INPUT (or a code it passes on) and usage_error() in every
C and C++ source under src/ and cli/, and the texts of the *_why() functions that callers put into messages.
  error_sites.py                      list them (FILE:LINE: format)
  error_sites.py --cases MESSAGES     those no message in the file matches (tools/errors.sh --messages)
  error_sites.py --check docs/errors.md
      fail (exit 1) unless each has a case in the catalogue or an exemption there (the table of
      messages no case triggers, each with why), and each exemption matches a message of the source;
      run by tools/errors.sh --check (the error_catalogue test)."""
import re, sys, glob, os, subprocess

# Where a message is made: the loader's cn_ld_fail() (src/io/load_*.c), cn_diag_set with
# CN_ERR_INPUT or with a code it passes on (diag->code: a message rewritten with its context), the
# CLI's cli_usage_error(), and the LCP reader's failures.
CALL = re.compile(r'\b(cn_ld_fail\(c,|cn_diag_set\([^,]+,\s*(CN_ERR_INPUT|[A-Za-z_]+(->|\.)code),|(?:cli_)?usage_error\(|cn_lcp_read_fail\(|rfail\()')

def source_files(root):
    """Every C and C++ source of the library (src/ and its stage folders, at any depth) and the CLI."""
    files = []
    for top in ('src', 'cli'):
        for ext in ('c', 'cpp', 'h'):
            files += glob.glob(os.path.join(root, top, '**', '*.' + ext), recursive=True)
    return sorted(set(files))

def why_texts(root, path, text):
    """The texts of a function that names why something failed (e.g. cn_mesh_split_why): each
    `return "..."` in its body is part of a message, put in by a caller's %s."""
    out = []
    for m in re.finditer(r'^const char \*\w+_why\([^)]*\)\s*\{', text, re.M):
        end = text.find('\n}', m.end())
        for r in re.finditer(r'return\s+((?:"(?:[^"\\]|\\.)*"\s*)+);', text[m.end():end]):
            fmt = ''.join(re.findall(r'"((?:[^"\\]|\\.)*)"', r.group(1)))
            line = text.count('\n', 0, m.end() + r.start()) + 1
            out.append((os.path.relpath(path, root), line, fmt))
    return out

def sites(root):
    out = []
    for path in source_files(root):
        text = open(path, encoding='utf-8', errors='surrogateescape').read()
        out += why_texts(root, path, text)
        for m in CALL.finditer(text):
            i = m.end()
            # the format: the first string literal run after the call's location argument
            lits = []
            j = i
            depth = 1
            while j < len(text) and depth > 0:
                ch = text[j]
                if ch == '"':
                    k = j + 1
                    while text[k] != '"':
                        k += 2 if text[k] == '\\' else 1
                    lits.append((j, text[j + 1:k]))
                    j = k + 1
                    continue
                if ch == '(':
                    depth += 1
                elif ch == ')':
                    depth -= 1
                j += 1
            if not lits:
                continue
            # join adjacent literals (C concatenation): the longest run separated by whitespace only
            runs, cur, last = [], [], None
            for pos, s in lits:
                if last is not None and text[last:pos].strip() == '':
                    cur.append(s)
                else:
                    if cur: runs.append(''.join(cur))
                    cur = [s]
                last = pos + len(s) + 2
            if cur: runs.append(''.join(cur))
            fmt = max(runs, key=len)
            if fmt in ('%s', ''):
                continue
            line = text.count('\n', 0, m.start()) + 1
            out.append((os.path.relpath(path, root), line, fmt))
    return out

CONV = re.compile(r'%%|%[-+ #0]*[0-9*]*(?:\.[0-9*]+)?(?:hh|h|ll|l|z|j|t|L)?[diouxXeEfFgGcsp]')

def regex(fmt):
    """The messages a printf format can print: each conversion matches any text."""
    fmt = fmt.replace('\\"', '"').replace('\\\\', '\\')
    parts, last = [], 0
    for m in CONV.finditer(fmt):
        parts.append(re.escape(fmt[last:m.start()]))
        parts.append('%' if m.group() == '%%' else '.*')
        last = m.end()
    parts.append(re.escape(fmt[last:]))
    return re.compile(''.join(parts))

def catalogue(path):
    """docs/errors.md: the messages of its cases (the last column of the case table) and its
    exemptions (the table of messages no case triggers: message, then why, which must be given)."""
    cases, exempt = [], []
    for line in open(path, encoding='utf-8', errors='surrogateescape'):
        if not line.startswith('| ') or line.startswith('|---'):
            continue
        cells = [c.strip().replace('\\|', '|') for c in re.split(r'(?<!\\)\|', line.strip())[1:-1]]
        if len(cells) == 4 and cells[0].startswith('['):
            cases.append(cells[3].strip('`'))
        elif len(cells) == 2 and cells[0].startswith('`'):
            exempt.append((cells[0].strip('`'), cells[1]))
    return cases, exempt

def main(argv):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ss = sites(root)
    if len(argv) > 2 and argv[1] == '--cases':
        # a file of messages, one a line (tools/errors.sh CAIRN --messages): the sites none matches
        msgs = open(argv[2], encoding='utf-8', errors='surrogateescape').read()
        missing = [s for s in ss if not regex(s[2]).search(msgs)]
        for f, l, m in missing:
            print(f'{f}:{l}: {m}')
        print(f'{len(ss) - len(missing)} of {len(ss)} messages have a case', file=sys.stderr)
        return 0
    if len(argv) > 2 and argv[1] == '--check':
        # docs/errors.md: every site must have a case there, or an exemption that says why
        cases, exempt = catalogue(argv[2])
        text = '\n'.join(cases)
        covered, exempted, missing = 0, 0, []
        used = set()
        for f, l, m in ss:
            r = regex(m)
            if r.search(text):
                covered += 1
                continue
            hit = [k for k, (msg, why) in enumerate(exempt) if r.search(msg)]
            if hit and all(exempt[k][1] for k in hit):
                exempted += 1
                used.update(hit)
            else:
                missing.append((f, l, m))
        for f, l, m in missing:
            print(f'{f}:{l}: no case and no exemption in {os.path.basename(argv[2])}: {m}')
        for msg, why in exempt:
            if not why:
                print(f'{os.path.basename(argv[2])}: the exemption `{msg}` does not say why no case reaches it')
        stale = [exempt[k][0] for k in range(len(exempt)) if k not in used and exempt[k][1]]
        for msg in stale:
            print(f'{os.path.basename(argv[2])}: the exemption `{msg}` matches no message of the source')
        print(f'{covered} of {len(ss)} messages have a case, {exempted} are exempted, {len(missing)} have neither',
              file=sys.stderr)
        return 1 if missing or stale or not all(why for _, why in exempt) else 0
    for f, l, m in ss:
        print(f'{f}:{l}: {m}')
    return 0

if __name__ == '__main__':
    sys.exit(main(sys.argv))
