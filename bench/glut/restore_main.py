#!/usr/bin/env python3
"""Restores the article's main.cpp (init, display, keys) from the seed, for bench/glut/run.sh.

usage: python3 bench/glut/restore_main.py SEED.txt OUT_DIR

It uses bench/article.py's own `restore()` on the seed line that holds main.cpp, with two
changes: the file comes from the environment (`BVH_FILE`) instead of "sexy.bvh", and the
commented-out `//glutIdleFunc(display);` ends before `glutMainLoop();` (restore()'s rule for
where a comment ends is made for BVH.cpp, and would end it inside the name).
"""

import importlib.util
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
spec = importlib.util.spec_from_file_location("article", HERE.parent / "article.py")
article = importlib.util.module_from_spec(spec)
spec.loader.exec_module(article)

seed, out = Path(sys.argv[1]), Path(sys.argv[2])
lines = seed.read_text(encoding="utf-8").splitlines()
main = next(l for l in lines if l.startswith("#include <cstdio>") and "void display()" in l)
text = article.restore(main)
load = 'model.loadFile("sexy.bvh");'
assert text.count(load) == 1, "the loadFile call is not there once"
text = text.replace(load, 'model.loadFile(getenv("BVH_FILE"));')
split = "//glutIdleFunc(display);glutMainLoo\np();"
assert text.count(split) == 1, "the comment before glutMainLoop is not where it was"
text = text.replace(split, "//glutIdleFunc(display);\nglutMainLoop();")
out.mkdir(parents=True, exist_ok=True)
(out / "main.cpp").write_text(text + "\n")
