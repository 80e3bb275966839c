#!/bin/sh
# The article's whole GLUT program (BVH.h, BVH.cpp, main.cpp), rebuilt from the article's text
# and drawn by real OpenGL (freeglut, Mesa llvmpipe) under Xvfb: its first picture of a file.
#
# usage: bench/glut/run.sh SEED.txt FILE.bvh OUT_DIR
#   OUT_DIR/original.png   the window after the first display() (frame 0, angle 10, 600x600)
#   OUT_DIR/stack.txt      glGetError and the modelview stack depth after every glPushMatrix
#                          and glPopMatrix of drawRecursive
# Needs g++, freeglut3-dev, xvfb (apt-get). shim/gl/glut.h stands in for <gl/glut.h>: it includes
# the real <GL/glut.h> and only observes (reads the picture back before the swap, logs the stack).
# On Mesa 22.3.6 this reproduces tests/oracle's pictures of tiny_crlf.bvh to the pixel.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
seed=$1 file=$2 out=$3
mkdir -p "$out"
python3 "$here/../article.py" "$seed" "$out/src" >/dev/null
python3 "$here/restore_main.py" "$seed" "$out/src"
g++ -O2 -w -I "$here/shim" -I "$out/src" -DCHECK_STACK -o "$out/viewer" \
    "$out/src/BVH.cpp" "$out/src/main.cpp" -lglut -lGLU -lGL -lm
BVH_FILE=$file CAPTURE=$out/original.ppm xvfb-run -a -s "-screen 0 1024x768x24" "$out/viewer" \
    2>"$out/stack.txt" >/dev/null
python3 "$here/ppm_to_png.py" "$out/original.ppm" "$out/original.png"
grep -E 'OVERFLOW|UNDERFLOW' "$out/stack.txt" || echo "no stack error"
