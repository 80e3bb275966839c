#!/usr/bin/env python3
"""Builds the article's own loader from its text, for `bvhview-bench --article`.

usage: python3 bench/article.py SEED.txt OUT_DIR   (SEED: ../shared/seeds/000_*.txt)

The article's listing lost its line breaks when it was published (TEACHING.md, Part 7). This
script restores what Part 7 restores by hand, and nothing else: a line break after each `//`
comment and around each preprocessor line, the tab lost from `case '':` and `*p != ''`, and a
stand-in for `<gl/glut.h>` (the loader is timed, nothing is drawn). Where a comment ends is not
marked in the text; it ends where code resumes: the first place after `//` from which the text
reads as a C++ statement (a keyword or a name the listing declares, then ASCII up to the
statement's end). The article's code stays in the seed: the result is written to OUT_DIR only,
never into the repository. The driver times `loadFile` alone and prints
`loadFile seconds: S`; `make` builds it with -O2, as a release build would.
"""

import re
import subprocess
import sys
from pathlib import Path

# Words a statement of the listing starts with (keywords, types and the names it declares).
STARTERS = (
    "BVHJoint BVH class bool int unsigned void float char const FILE enum if else for while "
    "return switch case default break delete printf fseek rewind fclose root father "
    "currentNode p frameData frameCount frameTime pFrame jointCount currentFrame node "
    "glPushMatrix glPopMatrix glTranslatef glRotatef glutSolidSphere roateSpace drawRecursive "
    "stack child childNum name flags x y z assert"
).split()


def starter_pattern(text):
    """A statement's first word: the words above, and every name the listing uses twice or more
    (its locals, `counter`, `buffer`…): a comment's own ASCII words that it shares are ruled out
    by `reads_as_code`."""
    names = re.findall(r"[A-Za-z_][A-Za-z0-9_]*", text)
    words = set(STARTERS) | {n for n in set(names) if names.count(n) >= 2}
    alternatives = "|".join(sorted(words, key=len, reverse=True))
    return re.compile(r"(?:%s)(?![A-Za-z0-9_])" % alternatives)


def reads_as_code(text, at):
    """Whether the text from `at` to its statement's end (`;`, a brace or the next comment) is
    ASCII, never closes a parenthesis it did not open, and is more than a bare word before a
    comment."""
    ends = [i for i in (text.find(c, at) for c in (";", "{", "}", "//")) if i >= 0]
    end = min(ends) if ends else len(text)
    # A bare word before a brace or the next comment is the comment's own ("…or tab}").
    if re.fullmatch(r"\s*[A-Za-z_][A-Za-z0-9_]*\s*", text[at:end]) and not text.startswith((";", "{"), end):
        return False
    depth = 0
    for c in text[at:end]:
        if ord(c) > 127:
            return False
        depth += {"(": 1, ")": -1}.get(c, 0)
        if depth < 0:
            return False
    return True


def statement_end(text, at):
    """Just past the statement at `at`: its `;` outside parentheses, braces and quotes, or the
    `}` (and `;`) that closes its braces, or the next comment, or the text's end."""
    depth, braces, i = 0, 0, at
    while i < len(text):
        if text.startswith("//", i):
            return i
        c = text[i]
        if c in "\"'":
            close = text.find(c, i + 1)
            while close > 0 and text[close - 1] == "\\":
                close = text.find(c, close + 1)
            i = close if close > 0 else len(text)
        elif c in "([":
            depth += 1
        elif c in ")]":
            depth -= 1
        elif c == "{":
            braces += 1
        elif c == "}":
            braces -= 1
            if braces <= 0 and depth <= 0:
                return i + 1 + text.startswith(";", i + 1)
        elif c == ";" and depth <= 0 and braces <= 0:
            return i + 1
        i += 1
    return len(text)


def comment_end(text, start, starter):
    """Where the comment that starts at `start` (its `//`) ends: a commented-out line ends with
    its statement; a comment of words at the first place where a statement starts that reads as
    code (see `reads_as_code`), or another comment, a brace (one in quotes aside) or a `#`."""
    at = start + 2
    # `//` right before code: a line commented out (`//printf(...);`), which ends with its
    # statement, unless a comment of words follows that statement on its line: then the `//`
    # was an empty comment and the statement is code (`//float *pFrame;//…`).
    if text[at : at + 1] in ("{", "}") or (starter.match(text, at) and reads_as_code(text, at)):
        end = statement_end(text, at)
        if text.startswith("//", end) and end + 2 < len(text) and ord(text[end + 2]) > 127:
            return at
        return end
    while at < len(text):
        # A brace quoted in the comment (‘{’) is the comment's; any other ends it.
        quoted = text[at - 1] in "‘“「"
        if text.startswith("//", at) or (text[at] in "}{#" and not quoted):
            return at
        if starter.match(text, at) and reads_as_code(text, at):
            return at
        at += 1
    return len(text)


def restore(text):
    """The listing with its line breaks and tabs back (Part 7, fixes 1 and 2)."""
    # Preprocessor lines on lines of their own.
    text = re.sub(r'(#(?:include\s*(?:<[^>]*>|"[^"]*")|define\s+\w+|ifndef\s+\w+|endif))', r"\n\1\n", text)
    starter = starter_pattern(text)
    out, at = [], 0
    while True:
        start = text.find("//", at)
        if start < 0:
            out.append(text[at:])
            break
        end = comment_end(text, start, starter)
        out.append(text[at:end] + "\n")
        at = end
    text = "".join(out)
    return text.replace("case '':", "case '\\t':").replace("*p != ''", "*p != '\\t'")


STUB = """// Stands in for GLUT: the bench times loadFile, which draws nothing.
#pragma once
static void glPushMatrix() {}
static void glPopMatrix() {}
static void glTranslatef(float, float, float) {}
static void glRotatef(float, float, float, float) {}
static void glutSolidSphere(double, int, int) {}
"""

DRIVER = """// Times the article's loadFile on one file, as bvhview-bench reads it.
#include <cstdio>
#include <ctime>
#include "BVH.h"
int main(int argc, char **argv) {
    if (argc != 2) return 2;
    BVH model;
    timespec start, end;
    clock_gettime(CLOCK_MONOTONIC, &start);
    bool loaded = model.loadFile(argv[1]);
    clock_gettime(CLOCK_MONOTONIC, &end);
    if (!loaded) { std::printf("loadFile failed\\n"); return 1; }
    std::printf("frames: %u\\n", model.getFrameCount());
    std::printf("loadFile seconds: %.6f\\n",
                (end.tv_sec - start.tv_sec) + (end.tv_nsec - start.tv_nsec) * 1e-9);
    return 0;
}
"""


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    seed, out = Path(sys.argv[1]), Path(sys.argv[2])
    lines = seed.read_text(encoding="utf-8").splitlines()
    header_at = next(i for i, l in enumerate(lines) if l.startswith("#ifndef __BVH_H__"))
    header_end = next(i for i in range(header_at, len(lines)) if lines[i].rstrip().endswith("#endif"))
    source = next(l for l in lines if l.startswith("#include <cassert>") and "BVH::loadFile" in l)
    (out / "gl").mkdir(parents=True, exist_ok=True)
    (out / "BVH.h").write_text(restore("\n".join(lines[header_at : header_end + 1])) + "\n")
    (out / "BVH.cpp").write_text(restore(source) + "\n")
    (out / "gl" / "glut.h").write_text(STUB)
    (out / "driver.cpp").write_text(DRIVER)
    program = out / "article_load"
    subprocess.run(
        ["g++", "-O2", "-w", "-I", str(out), "-o", str(program), str(out / "BVH.cpp"), str(out / "driver.cpp")],
        check=True,
    )
    print(program)


if __name__ == "__main__":
    main()
