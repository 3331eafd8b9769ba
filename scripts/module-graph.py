#!/usr/bin/env python3
"""The module graph of raypack's library (src/, not the CLI): which module
uses which, from the `crate::…`, `super::…` and `self::…` paths in each
file's code (doc comments and test modules left out). Fails (exit 1) if the
graph has a cycle, and prints it; also fails if a module uses one of a
higher layer (the top-level folders of src/, bottom to top: LAYERS).

    ./scripts/module-graph.py            # edges, then "acyclic" or the cycles
    ./scripts/module-graph.py --dot      # Graphviz
    ./scripts/module-graph.py --quiet    # only the verdict (what CI runs)

Module `a::b` uses module `c::d` when its code names `crate::c::d` or an
item in it. A path is resolved to the longest module prefix it names; an
item re-exported by a module (`pub use child::Item`) resolves to the
module that defines it, so a parent re-exporting its children's items does
not count as using them. Declarations (`mod x;`) are not uses.
"""
import os
import re
import sys

# The top-level folders of src/, bottom to top: a module may use its own
# layer and those below it, never one above (an "upward arrow").
LAYERS = ["num", "geom", "scene", "query", "trace", "render", "host"]

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src")


def module_files():
    """{module path: file} for every library module."""
    out = {}
    for dirpath, _, files in os.walk(ROOT):
        rel = os.path.relpath(dirpath, ROOT)
        if rel.startswith("bin"):
            continue
        parts = [] if rel == "." else rel.split(os.sep)
        for f in files:
            if not f.endswith(".rs"):
                continue
            name = f[:-3]
            if rel == "." and name == "lib":
                mod = ()
            elif name == "mod":
                mod = tuple(parts)
            else:
                mod = tuple(parts + [name])
            out[mod] = os.path.join(dirpath, f)
    return out


def code_of(path):
    """The file's code without comments, strings and `#[cfg(test)]` modules."""
    text = open(path, encoding="utf-8").read()
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r'"(?:\\.|[^"\\])*"', '""', text)
    # Drop `#[cfg(test)] mod name { … }` blocks (brace matching) and
    # `#[cfg(test)] mod name;` declarations.
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
    return "".join(out)


def test_modules(files):
    """Modules declared under `#[cfg(test)]` (files of their own)."""
    tests = set()
    for mod, path in files.items():
        text = open(path, encoding="utf-8").read()
        for m in re.finditer(r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+(\w+)\s*;", text):
            tests.add(mod + (m.group(1),))
    return tests


def main():
    files = module_files()
    for t in test_modules(files):
        files.pop(t, None)
    mods = set(files)
    code = {m: code_of(p) for m, p in files.items()}

    # Every `use` statement, flattened to (path, local name, public).
    uses = {m: list(use_items(c)) for m, c in code.items()}
    # Re-exports: (module, item) -> module the item comes from.
    reexport = {}
    for m, items in uses.items():
        for path, local, public in items:
            if public:
                src = resolve_module(m, path, mods, {})
                if src is not None:
                    reexport[(m, local)] = src
    # Follow chains of re-exports to the defining module.
    for key in list(reexport):
        seen, mod = set(), reexport[key]
        while (mod, key[1]) in reexport and (mod, key[1]) not in seen:
            seen.add((mod, key[1]))
            mod = reexport[(mod, key[1])]
        reexport[key] = mod

    edges = set()
    for m, c in code.items():
        body = re.sub(r"\b(pub(\([^)]*\))?\s+)?use\s+[^;]+;", ";", c)
        # Names brought in by `use` and used in the code.
        for path, local, _ in uses[m]:
            target = resolve_module(m, path, mods, reexport)
            if target is None or target == m:
                continue
            if local == "*" or local == "self" or re.search(r"\b" + re.escape(local) + r"\b", body):
                edges.add((m, target))
        # Paths written out in the code.
        for p in re.finditer(r"\b((?:crate|super|self)(?:::\w+)+)", body):
            target = resolve_module(m, p.group(1), mods, reexport)
            if target is not None and target != m:
                edges.add((m, target))

    name = lambda m: "::".join(m) if m else "crate"
    if "--dot" in sys.argv:
        print("digraph raypack {")
        for a, b in sorted(edges):
            print(f'  "{name(a)}" -> "{name(b)}";')
        print("}")
        return 0
    if "--quiet" not in sys.argv:
        for a, b in sorted(edges):
            print(f"{name(a)} -> {name(b)}")
    cycles = find_cycles(mods, edges)
    if cycles:
        for c in cycles:
            print("CYCLE: " + " -> ".join(name(x) for x in c + [c[0]]))
        return 1
    unknown = sorted({m[0] for m in mods if m and m[0] not in LAYERS})
    if unknown:
        print("NOT IN A LAYER: " + ", ".join(unknown) + " (scripts/module-graph.py LAYERS)")
        return 1
    upward = sorted((a, b) for a, b in edges if a and b and LAYERS.index(a[0]) < LAYERS.index(b[0]))
    if upward:
        for a, b in upward:
            print(f"UPWARD: {name(a)} -> {name(b)}")
        return 1
    print(f"acyclic, no upward arrow: {len(mods)} modules in {len(LAYERS)} layers, {len(edges)} edges")
    return 0


def use_items(code):
    """(path, local name, public) for every name a `use` statement brings in."""
    for u in re.finditer(r"\b(pub(?:\([^)]*\))?\s+)?use\s+([^;]+);", code):
        public = u.group(1) is not None
        for path, local in flatten(u.group(2).replace("\n", " ").strip()):
            yield path, local, public


def flatten(tree, prefix=""):
    """`a::{b, c::{d as e}}` -> [("a::b", "b"), ("a::c::d", "e")]."""
    tree = tree.strip()
    g = re.match(r"^([\w:]*?)(?:::)?\{(.*)\}$", tree, flags=re.S)
    if g:
        base = prefix + g.group(1)
        depth, start, parts = 0, 0, []
        inner = g.group(2)
        for i, ch in enumerate(inner):
            if ch == "{":
                depth += 1
            elif ch == "}":
                depth -= 1
            elif ch == "," and depth == 0:
                parts.append(inner[start:i])
                start = i + 1
        parts.append(inner[start:])
        out = []
        for part in parts:
            if part.strip():
                out += flatten(part, base + "::" if base else "")
        return out
    path, _, alias = tree.partition(" as ")
    path = (prefix + path.strip()).strip(":")
    local = alias.strip() or path.rsplit("::", 1)[-1]
    return [(path, local)]


def resolve_module(m, path, mods, reexport):
    """The library module that path `path`, written in module `m`, names
    (the module itself, or the module defining the item it names); `None`
    for anything outside the library (`core`, other crates)."""
    parts = path.split("::")
    cur = list(m)
    if parts[0] == "crate":
        cur, parts = [], parts[1:]
    elif parts[0] in ("super", "self"):
        while parts and parts[0] == "super":
            cur, parts = cur[:-1], parts[1:]
        if parts and parts[0] == "self":
            parts = parts[1:]
    elif tuple(cur + [parts[0]]) not in mods:
        return None  # an external crate
    full = tuple(cur + parts)
    k = len(full)
    while k > 0 and full[:k] not in mods:
        k -= 1
    mod = full[:k]
    if k < len(full) and (mod, full[k]) in reexport:
        mod = reexport[(mod, full[k])]
    return mod


def find_cycles(mods, edges):
    adj = {m: [] for m in mods}
    for a, b in edges:
        adj.setdefault(a, []).append(b)
    color, stack, cycles = {}, [], []

    def dfs(u):
        color[u] = 1
        stack.append(u)
        for v in adj.get(u, []):
            if color.get(v, 0) == 0:
                dfs(v)
            elif color.get(v) == 1:
                cycles.append(stack[stack.index(v):])
        stack.pop()
        color[u] = 2

    for m in sorted(mods):
        if color.get(m, 0) == 0:
            dfs(m)
    return cycles


if __name__ == "__main__":
    sys.exit(main())
