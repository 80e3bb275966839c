#!/usr/bin/env python3
"""Every public struct, enum and trait of bvhview's rustdoc has an example in its own docs.

Reads the HTML that `cargo doc --no-deps` wrote (target/doc/bvhview, or the folder given): the
items listed on all.html are the ones a user of the library sees (doc-hidden plumbing is not
listed), and a type's example is a Rust code block in the docs above its methods.
Exits 1 naming each type without one.
"""

import pathlib
import re
import sys


def top_docs(page: str) -> str:
    """The type's own docs: the block rustdoc opens before the implementations."""
    found = re.search(r'<details class="toggle top-doc" open>.*?<div class="docblock">(.*?)</div></details>', page, re.S)
    return found.group(1) if found else ""


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "target/doc/bvhview")
    listing = (root / "all.html").read_text()
    pages = sorted({link for link in re.findall(r'href="([^"]+\.html)"', listing)
                    if link.rsplit("/", 1)[-1].startswith(("struct.", "enum.", "trait."))})
    if not pages:
        print(f"doc examples: no types listed in {root / 'all.html'}", file=sys.stderr)
        return 1
    missing = [page for page in pages if 'class="rust' not in top_docs((root / page).read_text())]
    for page in missing:
        print(f"doc examples: {page} has no example", file=sys.stderr)
    print(f"doc examples: {len(pages)} public types, {len(pages) - len(missing)} with an example")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
