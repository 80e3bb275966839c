#!/usr/bin/env python3
"""The import graph of the library (src/) and of the Python crate (python/src/): which module
uses which, and any circle in it. Prints one line per module with what it uses, then the
circles; exits 1 if there is one. A module is a file (src/bvh/rows/scan.rs is bvh::rows::scan);
mod.rs and lib.rs are their folder's module, `crate` the root. Every path counts: a `use` in
any form (`use super::{A, b::C};`, `use crate::x::{self, Y as Z}`, nested braces, spread over
lines, `pub use child::Item`, a glob), and a path written in the code (`crate::x::f()`,
`super::super::T`, `child::f()` in the module that declares `child`), in inline modules too.
A path counts as a use of the longest module it names: `super::Item` uses the parent, even
when the parent only re-exports Item. So a child that names what its mod.rs holds or
re-exports uses the mod.rs like any other module, and a mod.rs and a file below it that use
each other are a circle. The one exception is the crate root's re-exports, the library's
public names: `crate::Error` is a use of where `Error` is defined (the root's own items count
like any other). Test code says nothing: an item under `#[cfg(test)]` (a `mod tests { … }`, a
test-only `fn`, a `#[cfg(test)] mod name;` and its file) is left out, and so are comments and
strings. A visibility such as `pub(in crate::retarget)` names no use. The command line
(src/cli/, src/main.rs) is left out. Usage: scripts/import_graph.py [--quiet]"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# (name, folder, parts of a path to leave out)
CRATES = [("bvhview", ROOT / "src", {"cli"}), ("bvhview-python", ROOT / "python" / "src", set())]


def module_of(src: Path, path: Path) -> str:
    parts = list(path.relative_to(src).with_suffix("").parts)
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return "::".join(parts) or "crate"


def lex(text: str) -> str:
    """The text with comments removed and every string and character literal emptied."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    i += 1
            out.append(" ")
        elif (raw := re.match(r'b?r(#*)"', text[i:])) and not (i and re.match(r"\w", text[i - 1])):
            end = '"' + raw.group(1)
            j = text.find(end, i + raw.end())
            i = n if j < 0 else j + len(end)
            out.append('""')
        elif c == '"' or (c == "b" and text.startswith('b"', i) and not (i and re.match(r"\w", text[i - 1]))):
            i += 1 if c == '"' else 2
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
            i += 1
            out.append('""')
        elif c == "'" and (ch := re.match(r"'(\\u\{[0-9a-fA-F]+\}|\\x[0-9a-fA-F]{2}|\\.|[^'\\\n])'", text[i:])):
            i += ch.end()
            out.append("' '")
        else:
            out.append(c)
            i += 1
    return "".join(out)


def item_end(text: str, i: int) -> int:
    """Where the item that starts at `i` ends: its `;`, or the brace that closes its body."""
    depth = 0
    while i < len(text):
        c = text[i]
        if c in "([":
            depth += 1
        elif c in ")]":
            depth -= 1
        elif c == ";" and depth == 0:
            return i + 1
        elif c == "{" and depth == 0:
            braces = 0
            while i < len(text):
                braces += {"{": 1, "}": -1}.get(text[i], 0)
                i += 1
                if braces == 0:
                    return i
        i += 1
    return i


TEST_ITEM = re.compile(r"#\[cfg\(test\)\]\s*(?:#\[[^\]]*\]\s*)*")


def strip_tests(text: str) -> tuple[str, list[str]]:
    """The text without its `#[cfg(test)]` items, and the names of test-only module files."""
    test_files = []
    while match := TEST_ITEM.search(text):
        end = item_end(text, match.end())
        declared = re.fullmatch(r"(?:pub(?:\([^)]*\))?\s+)?mod\s+(\w+)\s*;", text[match.end():end].strip())
        if declared:
            test_files.append(declared.group(1))
        text = text[: match.start()] + " " + text[end:]
    return text, test_files


def use_paths(tree: str) -> list[tuple[list[str], str | None]]:
    """The paths of a `use` tree with the name each binds (None for a glob):
    `a::{b, c::{self, D as E}, f::*}` is a::b (b), a::c (c), a::c::D (E), a::f (None)."""
    tokens = re.findall(r"::|[{},*]|\w+", tree)
    pos = 0

    def parse(prefix: list[str]) -> list[tuple[list[str], str | None]]:
        nonlocal pos
        path, paths, bound = list(prefix), [], ""
        while pos < len(tokens):
            t = tokens[pos]
            if t == "{":
                pos += 1
                while pos < len(tokens) and tokens[pos] != "}":
                    if tokens[pos] == ",":
                        pos += 1
                        continue
                    paths += parse(path)
                pos += 1
                return paths
            if t in (",", "}"):
                break
            pos += 1
            if t == "as":
                bound = tokens[pos] if pos < len(tokens) else ""
                pos += 1
            elif t == "*":
                bound = None
            elif t != "::" and t != "self":  # `x::{self}` is x itself
                path.append(t)
        if bound == "":
            bound = path[-1] if path else None
        return paths + [(path, bound)]

    return parse([])


def resolve(names: list[str], me: list[str], children: set[str]) -> list[str] | None:
    """The absolute path that `names` written in module `me` stands for; None if outside."""
    if not names:
        return None
    if names[0] == "crate":
        return names[1:]
    if names[0] in ("super", "self"):
        base = list(me)
        while names and names[0] in ("super", "self"):
            if names[0] == "super":
                base = base[:-1]
            names = names[1:]
        return base + names
    if names[0] in children:
        return me + names
    return None  # another crate, std, or a name in scope


ITEM = re.compile(r"\b(?:fn|struct|enum|const|static|type|trait|union|mod|macro_rules!)\s+(\w+)")
USE = re.compile(r"(?<![\w:])use\s+([^;]+);")


def inline_modules(text: str, own: list[str]) -> list[tuple[str, list[str]]]:
    """The file's text apart from its inline modules (`mod name { … }`), and each inline module's
    text with the path it is at (its `super` is the file's module)."""
    parts = []
    while match := re.search(r"\bmod\s+(\w+)\s*\{", text):
        end = item_end(text, match.start())
        body = text[match.end() : end - 1]
        parts += inline_modules(body, own + [match.group(1)])
        text = text[: match.start()] + f"mod {match.group(1)};" + text[end:]
    return [(text, own)] + parts


def crate_graph(src: Path, leave_out: set[str]) -> dict[str, list[str]]:
    files = sorted(p for p in src.rglob("*.rs") if p.name != "main.rs" and not leave_out & set(p.parts))
    texts = {module_of(src, p): strip_tests(lex(p.read_text())) for p in files}
    # A file declared `#[cfg(test)] mod name;` is test code, and so is everything below it.
    test_only = {name if me == "crate" else f"{me}::{name}" for me, (_, names) in texts.items() for name in names}
    modules = {m for m in texts if not any(m == t or m.startswith(t + "::") for t in test_only)}

    def split(module: str) -> list[str]:
        return module.split("::") if module != "crate" else []

    def home(absolute: list[str], depth: int = 0) -> str:
        """The module that the absolute path names, or that holds the item it names. An item the
        crate root only re-exports (`pub use io::error::Error`) is at home where it is defined."""
        n = len(absolute)
        while n and "::".join(absolute[:n]) not in modules:
            n -= 1
        module = "::".join(absolute[:n]) or "crate"
        rest = absolute[n:]
        if module == "crate" and rest and depth < 20 and rest[0] in imports[module] and rest[0] not in defined[module]:
            return home(imports[module][rest[0]] + rest[1:], depth + 1)
        return module

    paths, imports, defined = {}, {}, {}
    for me in modules:
        own = split(me)
        children = {m.split("::")[-1] for m in modules if split(m)[:-1] == own and m != "crate"}
        # `pub(in crate::x)` says who may see an item, not what it uses.
        text = re.sub(r"\bpub\s*\(\s*in\s+[\w:\s]+\)", "pub", texts[me][0])
        paths[me], imports[me] = [], {}
        for part, where in inline_modules(text, own):
            for match in USE.finditer(part):
                for names, bound in use_paths(match.group(1)):
                    absolute = resolve(names, where, children if where == own else set())
                    if absolute is not None:
                        paths[me].append(absolute)
                        if bound and where == own:
                            imports[me][bound] = absolute
            # Paths in the code: crate::…, super::…, self::…, child::… (not after `::`).
            for match in re.finditer(r"(?<![\w:$])\$?(\w+)((?:\s*::\s*\w+)+)", USE.sub(" ", part)):
                names = [match.group(1)] + re.findall(r"\w+", match.group(2))
                absolute = resolve(names, where, children if where == own else set())
                if absolute is not None:
                    paths[me].append(absolute)
        defined[me] = set(ITEM.findall(text))
    graph = {}
    for me in modules:
        graph[me] = sorted({home(absolute) for absolute in paths[me]} - {me})
    return graph


def circles_of(graph: dict[str, list[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module."""
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
    return circles


def main() -> int:
    quiet = "--quiet" in sys.argv
    total = 0
    for name, src, leave_out in CRATES:
        graph = crate_graph(src, leave_out)
        if not quiet:
            for module in sorted(graph):
                print(f"{name}: {module} -> {', '.join(graph[module]) or '(nothing)'}")
        circles = circles_of(graph)
        for circle in circles:
            print(f"{name}: circle: " + " <-> ".join(circle))
        print(f"{name}: {len(graph)} modules, {sum(len(u) for u in graph.values())} uses, {len(circles)} circles")
        total += len(circles)
    return 1 if total else 0


if __name__ == "__main__":
    sys.exit(main())
