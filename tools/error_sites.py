#!/usr/bin/env python3
"""List every input-error message cairn can print (the format strings of fail(), cn_diag_set with
CN_ERR_INPUT and usage_error()) and, with --cases DIR, which of them no case's stderr matches.
A developer's tool (python3): `make test` checks docs/errors.md against cairn's output instead."""
import re, sys, glob, os, subprocess

def sites(root):
    out = []
    for path in sorted(glob.glob(os.path.join(root, 'src', '*.c')) + [os.path.join(root, 'cli', 'main.c')]):
        text = open(path).read()
        for m in re.finditer(r'\b(fail\(c,|cn_diag_set\([^,]+,\s*CN_ERR_INPUT,|usage_error\(|cn_lcp_read_fail\(|rfail\()', text):
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

def regex(fmt):
    r = re.escape(fmt.replace('\\"', '"').replace('\\\\', '\\'))
    r = re.sub(r'%(\\-)?[0-9]*(\\\.[0-9]+)?(zu|lld|ld|d|g|s|c)', '.*', r)
    return re.compile(r)

if __name__ == '__main__':
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ss = sites(root)
    if len(sys.argv) > 2 and sys.argv[1] == '--cases':
        msgs = open(sys.argv[2]).read()
        missing = [s for s in ss if not regex(s[2]).search(msgs)]
        for f, l, m in missing:
            print(f'{f}:{l}: {m}')
        print(f'{len(ss) - len(missing)} of {len(ss)} messages have a case', file=sys.stderr)
    else:
        for f, l, m in ss:
            print(f'{f}:{l}: {m}')
