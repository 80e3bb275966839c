#!/usr/bin/env python3
"""The import graph of src/: which module uses which (by `crate::` and `super::` paths), and
any circle in it. Prints one line per module with what it uses, then the circles; exits 1 if
there is one. A module is a file (src/bvh/rows/scan.rs is bvh::rows::scan); mod.rs and lib.rs
are their folder's module. A child that names its parent's (or an ancestor's) own items uses
it like any other module, so a mod.rs and a file below it that use each other are a circle; a
mod.rs's `pub use child::Item` is a use of the child. A visibility such as
`pub(in crate::retarget)` names no use. Usage: scripts/import_graph.py [--quiet]"""
import re
import sys
from pathlib import Path

SRC = Path(__file__).resolve().parent.parent / "src"


def module_of(path: Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return "::".join(parts) or "crate"


def strip_comments_and_tests(text: str) -> str:
    # Unit tests may use anything; comments and strings say nothing about imports.
    text = re.sub(r"#\[cfg\(test\)\]\s*mod tests\s*\{.*", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    # `pub(in crate::x)` says who may see an item, not what it uses.
    text = re.sub(r"\bpub\(in [\w:]+\)", "pub", text)
    return re.sub(r'"(\\.|[^"\\])*"', '""', text)


def main() -> int:
    files = sorted(p for p in SRC.rglob("*.rs") if p.name != "main.rs" and "cli" not in p.parts)
    modules = {module_of(p) for p in files}
    graph = {}
    for path in files:
        me = module_of(path)
        text = strip_comments_and_tests(path.read_text())
        used = set()
        own = me.split("::") if me != "crate" else []
        for match in re.finditer(r"\b(crate|super)((?:::\w+)+)", text):
            # `super` is the module that holds this one, whatever file it is written in.
            base = [] if match.group(1) == "crate" else own[:-1]
            names = base + match.group(2).strip(":").split("::")
            # The longest prefix that is a module.
            for n in range(len(names), 0, -1):
                candidate = "::".join(names[:n])
                if candidate in modules:
                    if candidate != me:
                        used.add(candidate)
                    break
        # `use name::` of a child module declared with `mod name;` in a folder module.
        for match in re.finditer(r"^\s*(?:pub(?:\([\w:]+\))?\s+)?use\s+(\w+)::", text, flags=re.M):
            child = f"{me}::{match.group(1)}" if me != "crate" else match.group(1)
            if child in modules:
                used.add(child)
        graph[me] = sorted(used)
    quiet = "--quiet" in sys.argv
    if not quiet:
        for module in sorted(graph):
            print(f"{module} -> {', '.join(graph[module]) or '(nothing)'}")
    # Circles: strongly connected components of more than one module.
    index, low, stack, on, circles = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, []):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    for circle in circles:
        print("circle: " + " <-> ".join(circle))
    print(f"{len(graph)} modules, {sum(len(u) for u in graph.values())} uses, {len(circles)} circles")
    return 1 if circles else 0


if __name__ == "__main__":
    sys.exit(main())
