#!/usr/bin/env python3
"""Builds the article's own loader from its text, for `bvhview-bench --article`.

usage: python3 bench/article.py SEED.txt OUT_DIR [--patched] [--print]
       (SEED: ../shared/seeds/000_*.txt)

The article's listing lost its line breaks when it was published (TEACHING.md, Part 7). This
script restores what Part 7 restores by hand, and nothing else: a line break after each `//`
comment and around each preprocessor line, the tab lost from `case '':` and `*p != ''`, and a
stand-in for `<gl/glut.h>` (the loader is timed, nothing is drawn). Where a comment ends is not
marked in the text; it ends where code resumes: the first place after `//` from which the text
reads as a C++ statement (a keyword or a name the listing declares, then ASCII up to the
statement's end). The article's code stays in the seed: the result is written to OUT_DIR only,
never into the repository. The driver times `loadFile` alone and prints
`loadFile seconds: S`; `make` builds it with -O2, as a release build would.

`--print` builds TEACHING.md Part 7's printing stub and driver instead (`article_print FILE`
prints the tree as `init` does; `article_print FILE N` prints the GL calls `draw` makes for
frame N, as `bvhview trace` writes them). `--patched` builds the loader made robust to
whitespace, line endings and number widths, as the one that made tests/oracle was (its README):
the `PATCHES` below replace the article's fixed strides with reads that stop where a name or a
number does, and nothing else (`getFlags` and its fixed 10-byte steps between channel names,
the three channels per joint, `print` and `draw` stay the article's). `tests/article/article_program_rebuilt.rs`
runs it on BVH files bvhview writes.
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

# The patched loader: (what the article's code says, what replaces it, why). Each must match the
# restored BVH.cpp exactly once. `strtod` reads a number as `atof` does and says where it ended,
# where the article steps a fixed 5 or 8 bytes.
BLANK = "(*p == ' ' || *p == '\\t')"
PATCHES = [
    (
        "new unsigned char[iFileSize];",
        "new unsigned char[iFileSize + 1]();",
        "a NUL after the file's last byte, so that no scan runs past the end of the buffer",
    ),
    (
        "p += 7;root = newNode();",
        "while(*p == '\\r' || *p == '\\n' || %s) p++;p += 4;while(%s) p++;root = newNode();"
        % (BLANK, BLANK),
        "`ROOT name` after any line ending (the article skips 7 bytes: CR LF and `ROOT `)",
    ),
    (
        "for(i = 0; i < NAMESIZE && *p != '\\n';i++){node->name[i] = *p;p++;}if(i == NAMESIZE) --i;node->name[i-1] = 0;",
        "for(i = 0; i < NAMESIZE - 1 && *p != '\\n' && *p != '\\r';i++){node->name[i] = *p;p++;}"
        "while(i > 0 && (node->name[i-1] == ' ' || node->name[i-1] == '\\t')) --i;node->name[i] = 0;"
        "while(*p != '\\n' && *p != 0) p++;",
        "a name ends at the line's end, CR or not (the article drops its last byte, meant to be "
        "the CR), blanks after it left out, kept to 23 bytes as tests/oracle/print keeps them",
    ),
    (
        "p += 7;root->x = (float)atof((char*)p);p += 5;if(*p == ' ') p++;"
        "root->y = (float)atof((char*)p);p += 5;if(*p == ' ') p++;"
        "root->z = (float)atof((char*)p);p += 5;",
        "p += 6;root->x = (float)strtod((char*)p, (char**)&p);"
        "root->y = (float)strtod((char*)p, (char**)&p);"
        "root->z = (float)strtod((char*)p, (char**)&p);",
        "the root's OFFSET in numbers of any width (the article steps 5 bytes per number)",
    ),
    (
        "p += 7;currentNode->x = atof((const char *)p);p += 8;while(*p != ' ' && *p != '\\t' ) p++;p++;"
        "currentNode->y = atof((const char *)p);p += 8;while(*p != ' ' && *p != '\\t' ) p++;p++;"
        "currentNode->z = atof((const char *)p);",
        "p += 6;currentNode->x = strtod((const char *)p, (char**)&p);"
        "currentNode->y = strtod((const char *)p, (char**)&p);"
        "currentNode->z = strtod((const char *)p, (char**)&p);",
        "an OFFSET in numbers of any width (the article steps 8 bytes, then to a blank)",
    ),
    (
        "bool BVH::processJoint(){p += 6;",
        "bool BVH::processJoint(){p += 5;while(%s) p++;" % BLANK,
        "`JOINT` and any blanks before the name",
    ),
    (
        "p += 4;BVHJoint *node = newNode();",
        "p += 3;while(%s) p++;BVHJoint *node = newNode();" % BLANK,
        "`End` and any blanks before `Site`",
    ),
    (
        "p += 11;currentNode->flags = getFlags();",
        "p += 8;while(%s) p++;while(*p >= '0' && *p <= '9') p++;while(%s) p++;"
        "currentNode->flags = getFlags();" % (BLANK, BLANK),
        "`CHANNELS`, the count and any blanks before the first channel",
    ),
    (
        "frameData[i][j] = (float)atof((char*)p);p += 8;while(*p != ' ' && *p != '\\t') p++;p++;",
        "frameData[i][j] = (float)strtod((char*)p, (char**)&p);",
        "a row's numbers of any width, separated by any blanks (the article steps 8 bytes)",
    ),
    (
        "p+=2;}",
        "}",
        "any line ending after a row, or none (the article skips 2 bytes: CR LF); `strtod` "
        "skips it before the next number",
    ),
]


def patch(source):
    """The restored BVH.cpp with `PATCHES` made, each exactly once."""
    for old, new, why in PATCHES:
        found = source.count(old)
        if found != 1:
            sys.exit("bench/article.py: the patch for %s matches %d times, not once" % (why, found))
        source = source.replace(old, new)
    return source


PRINT_STUB = """// stub/gl/glut.h (TEACHING.md, Part 7): stands in for GLUT while only BVH.cpp is built.
#pragma once
#include <cstdio>
static void glPushMatrix() { std::printf("glPushMatrix();\\n"); }
static void glPopMatrix() { std::printf("glPopMatrix();\\n"); }
static void glTranslatef(float x, float y, float z) {
    std::printf("glTranslatef(%f, %f, %f);\\n", x, y, z);
}
static void glRotatef(float a, float x, float y, float z) {
    std::printf("glRotatef(%f, %f, %f, %f);\\n", a, x, y, z);
}
static void glutSolidSphere(double r, int slices, int stacks) {
    std::printf("glutSolidSphere(%f, %d, %d);\\n", r, slices, stacks);
}
"""

PRINT_DRIVER = """// driver.cpp (TEACHING.md, Part 7): the tree as init prints it, or frame N's draw calls.
#include <cstdio>
#include <cstdlib>
#include "BVH.h"
int main(int argc, char **argv) {
    if (argc < 2) return 2;
    BVH model;
    if (!model.loadFile(argv[1])) { std::printf("loadFile failed\\n"); return 1; }
    if (argc == 2) { model.print(); return 0; }
    model.setCurrentFrame(std::atoi(argv[2]));
    model.draw();
    return 0;
}
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
    flags = [a for a in sys.argv[1:] if a.startswith("--")]
    paths = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(paths) != 2 or any(f not in ("--patched", "--print") for f in flags):
        sys.exit(__doc__)
    seed, out = Path(paths[0]), Path(paths[1])
    lines = seed.read_text(encoding="utf-8").splitlines()
    header_at = next(i for i, l in enumerate(lines) if l.startswith("#ifndef __BVH_H__"))
    header_end = next(i for i in range(header_at, len(lines)) if lines[i].rstrip().endswith("#endif"))
    source = next(l for l in lines if l.startswith("#include <cassert>") and "BVH::loadFile" in l)
    (out / "gl").mkdir(parents=True, exist_ok=True)
    (out / "BVH.h").write_text(restore("\n".join(lines[header_at : header_end + 1])) + "\n")
    restored = restore(source)
    if "--patched" in flags:
        restored = patch(restored)
    (out / "BVH.cpp").write_text(restored + "\n")
    printing = "--print" in flags
    (out / "gl" / "glut.h").write_text(PRINT_STUB if printing else STUB)
    (out / "driver.cpp").write_text(PRINT_DRIVER if printing else DRIVER)
    program = out / ("article_print" if printing else "article_load")
    subprocess.run(
        ["g++", "-O2", "-w", "-I", str(out), "-o", str(program), str(out / "BVH.cpp"), str(out / "driver.cpp")],
        check=True,
    )
    print(program)


if __name__ == "__main__":
    main()
