#!/usr/bin/env python3
"""Lists C++ function bodies longer than a limit (default 100 lines).

Usage: scripts/function_lengths.py [--limit N] [--top K] [--allow FILE] PATH...   (files or folders)
Exit 1 when a function is longer than the limit, so CTest keeps every function
of src/, apps/ and python/src to small steps (docs/architecture.md, "Small steps").

--allow FILE names the functions that may stay longer, one "path function" a
line (path relative to the repository root, '#' starts a comment). An entry
that matches no long function is an error too, so the list only shrinks.

A body is a top-level brace block (namespaces and class bodies are looked into)
whose head ends in ')' plus qualifiers; lambdas count as part of their function.
Comments, strings and character literals are skipped.
"""
import argparse
import pathlib
import re
import sys

HEAD_SCOPE = re.compile(r'\b(namespace|class|struct|union|enum)\b[^;{()]*$')
HEAD_FUNC = re.compile(r'\)\s*(const|noexcept|override|final|mutable|->\s*[\w:<>,\s*&]+|\s)*$')
HEAD_INIT = re.compile(r'\)\s*:\s*.*$', re.S)  # constructor with a member-initialiser list


def strip(text):
    """Blanks comments and literals, keeping line breaks."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith('//', i):
            j = text.find('\n', i)
            i = n if j < 0 else j
        elif text.startswith('/*', i):
            j = text.find('*/', i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r'[^\n]', ' ', text[i:j]))
            i = j
        elif text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = ')' + m.group(1) + '"'
            j = text.find(end, i)
            j = n if j < 0 else j + len(end)
            out.append(re.sub(r'[^\n]', ' ', text[i:j]))
            i = j
        elif c in '"\'':
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == '\\' else 1
            out.append(' ' * (j + 1 - i))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return ''.join(out)


def functions(path):
    text = strip(path.read_text(errors='replace'))
    scopes = []  # per open brace: 'scope' (look inside), 'func' or 'block'
    head_start = 0
    result = []
    for i, c in enumerate(text):
        if c == '{':
            inside_func = any(k == 'func' for k, _ in scopes)
            head = text[head_start:i].strip()
            if inside_func:
                kind = 'block'
            elif HEAD_SCOPE.search(head) or head.endswith('extern "C"'):
                kind = 'scope'
            elif HEAD_FUNC.search(head) or HEAD_INIT.search(head):
                kind = 'func'
            else:
                kind = 'block'
            scopes.append((kind, i))
            if kind == 'func':
                name = re.findall(r'([~\w:]+(?:operator\s*\S+)?)\s*\(', head)
                result.append([name[0] if name else '?', text.count('\n', 0, i) + 1, None])
            head_start = i + 1
        elif c == '}':
            if scopes:
                kind, start = scopes.pop()
                if kind == 'func':
                    for r in reversed(result):
                        if r[2] is None:
                            r[2] = text.count('\n', 0, i) + 1
                            break
            head_start = i + 1
        elif c == ';':
            head_start = i + 1
    return [(n, a, b - a + 1) for n, a, b in result if b is not None]


def read_allow(path):
    """The (path, function) pairs of an allow-list file."""
    entries = []
    for line in pathlib.Path(path).read_text().splitlines():
        words = line.split('#', 1)[0].split()
        if not words:
            continue
        if len(words) != 2:
            sys.exit(f'error: {path}: "{line.strip()}": expected "path function"')
        entries.append(tuple(words))
    return entries


def allowed(where, name, entries):
    """The allow-list entry for a function at `where` (file:line), or None."""
    file = where.rsplit(':', 1)[0]
    for path, func in entries:
        if name == func and (file == path or file.endswith('/' + path)):
            return (path, func)
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('paths', nargs='+')
    ap.add_argument('--limit', type=int, default=100)
    ap.add_argument('--top', type=int, default=0, help='also list the K longest functions')
    ap.add_argument('--allow', help='file naming the functions that may stay longer (see above)')
    a = ap.parse_args()
    files = []
    for p in map(pathlib.Path, a.paths):
        files += sorted(p.rglob('*.[ch]pp')) if p.is_dir() else [p]
    found = [(length, f'{f}:{line}', name) for f in files for name, line, length in functions(f)]
    found.sort(reverse=True)
    for length, where, name in found[:a.top]:
        print(f'{length:5d}  {where}  {name}')
    entries = read_allow(a.allow) if a.allow else []
    used = set()
    long = []
    for length, where, name in (x for x in found if x[0] > a.limit):
        entry = allowed(where, name, entries)
        if entry:
            used.add(entry)
        else:
            long.append((length, where, name))
    for length, where, name in long:
        print(f'error: {where}: {name} is {length} lines (limit {a.limit}): split it into named steps', file=sys.stderr)
    stale = [e for e in entries if e not in used]
    for path, func in stale:
        print(f'error: {a.allow}: {path} {func} is no longer a function over {a.limit} lines: '
              'remove it from the list', file=sys.stderr)
    return 1 if long or stale else 0


if __name__ == '__main__':
    sys.exit(main())
