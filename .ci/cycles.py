#!/usr/bin/env python3
"""Import cycles among the library's modules (test code excluded).

Top level: an edge A -> B when a non-test file of top module A names `crate::B` (a `use` or a
path). Files: an edge when a file names an item path that resolves to another file's module.
Prints every strongly connected component with more than one member; exit 1 when the top-level
graph has one (the file-level knots are listed for docs/architecture.md, not enforced).
`--cli` also checks the command line (`src/cli/`, in the binary, which the library's graph
skips): the same file-level edges among its files; exit 1 when they have a cycle.
Usage: .ci/cycles.py [--files] [--cli]
"""
import os, re, sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src")
SKIP_TOP = {"main.rs", "lib.rs", "cli"}


def strip_tests(text):
    # Cut `#[cfg(test)] mod x { ... }` blocks and `#[cfg(test)] mod x;` declarations.
    out, i = [], 0
    pat = re.compile(r"#\[cfg\(test\)\]\s*(pub(\([^)]*\))?\s+)?mod\s+\w+\s*([;{])")
    while True:
        m = pat.search(text, i)
        if not m:
            out.append(text[i:])
            break
        out.append(text[i:m.start()])
        if m.group(3) == ";":
            i = m.end()
            continue
        depth, j = 1, m.end()
        while j < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        i = j
    text = "".join(out)
    return re.sub(r"//[^\n]*", "", text)


def is_test_file(rel):
    base = os.path.basename(rel)
    return (base.startswith("tests") or base.endswith("_tests.rs") or "/tests/" in "/" + rel
            or base == "chi2.rs")


def files(cli=False):
    """The library's non-test files, or with `cli` the command line's."""
    for d, _, fs in os.walk(ROOT):
        for f in fs:
            if f.endswith(".rs"):
                rel = os.path.relpath(os.path.join(d, f), ROOT)
                top = rel.split(os.sep)[0]
                if is_test_file(rel) or (top != "cli" if cli else top in SKIP_TOP):
                    continue
                yield rel


def module_of(rel):
    parts = rel[:-3].split(os.sep)
    if parts[-1] == "mod":
        parts = parts[:-1]
    return parts


def expand_use(body):
    """`a::{b, c::{d}}` -> [a::b, a::c::d] (good enough for crate paths)."""
    body = re.sub(r"\s+", "", body)
    m = re.match(r"^(.*?)\{(.*)\}$", body)
    if not m:
        return [body]
    prefix, inner = m.group(1), m.group(2)
    parts, depth, cur = [], 0, ""
    for ch in inner:
        if ch == "," and depth == 0:
            parts.append(cur); cur = ""; continue
        depth += ch == "{"; depth -= ch == "}"
        cur += ch
    parts.append(cur)
    return [q for p in parts if p for q in expand_use(prefix + p)]


def references(text, mod):
    refs = []
    for m in re.finditer(r"\buse\s+([^;]+);", text):
        refs += expand_use(m.group(1))
    refs += re.findall(r"\b(?:crate|super)(?:::\w+)+", text)
    out = []
    for r in refs:
        parts = r.split("::")
        if parts[0] == "crate":
            out.append(parts[1:])
        elif parts[0] in ("super", "self"):
            base = list(mod) if parts[0] == "self" else list(mod)
            while parts and parts[0] in ("super", "self"):
                if parts[0] == "super" and base:
                    base = base[:-1]
                parts = parts[1:]
            out.append(base + parts)
    return [o for o in out if o]


def sccs(graph):
    index, low, stack, on, res, n = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(10000)
    def visit(v):
        index[v] = low[v] = n[0]; n[0] += 1; stack.append(v); on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w); low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop(); on.discard(w); comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                res.append(sorted(comp))
    for v in list(graph):
        if v not in index:
            visit(v)
    return res


def graphs(cli=False):
    """(top-level graph, file graph) over `files(cli)`."""
    mods = {}
    for rel in files(cli):
        mods[tuple(module_of(rel))] = rel
    top, filegraph = {}, {}
    for mod, rel in mods.items():
        text = strip_tests(open(os.path.join(ROOT, rel), encoding="utf-8").read())
        for ref in references(text, list(mod)):
            if ref[0] != mod[0]:
                top.setdefault(mod[0], set()).add(ref[0])
            # The longest module prefix of the path that is a file.
            for k in range(len(ref), 0, -1):
                t = tuple(ref[:k])
                if t in mods:
                    if t != mod and not (len(t) < len(mod) and mod[:len(t)] == t and k == len(t)):
                        filegraph.setdefault(rel, set()).add(mods[t])
                    break
    return top, filegraph


def main():
    top, filegraph = graphs()
    status = 0
    for comp in sccs({k: v for k, v in top.items()}):
        print("top-level cycle:", " <-> ".join(comp)); status = 1
    if "--files" in sys.argv:
        for comp in sccs(filegraph):
            print("file cycle:", " <-> ".join(comp))
    if status == 0:
        print("no import cycle among src/'s top-level modules")
    if "--cli" in sys.argv:
        cli = sccs(graphs(cli=True)[1])
        for comp in cli:
            print("cli file cycle:", " <-> ".join(comp))
        if cli:
            status = 1
        else:
            print("no import cycle among src/cli/'s files")
    return status


sys.exit(main())
