// bench/glut/shim/gl/glut.h: stands in for the article's <gl/glut.h> (Windows path) on Linux.
// It includes the real freeglut <GL/glut.h>; nothing of the article's drawing is replaced.
// Added (observation only, no GL state changed):
//  * glutSwapBuffers() in display(): before the real swap, read the back buffer (the picture
//    display() just drew) with glReadPixels into $CAPTURE (binary PPM, top row first), print
//    glGetError() and the modelview stack depth, then swap; exit(0) unless $HOLD is set.
//  * with -DCHECK_STACK: glPushMatrix()/glPopMatrix() in BVH::drawRecursive call the real
//    function, then print the joint's name (r->name, in scope there), glGetError() and
//    GL_MODELVIEW_STACK_DEPTH.
#pragma once
#include <GL/glut.h>
// main.cpp calls cos/sin without an include (MSVC's headers brought them in); libstdc++'s
// <math.h> puts the float overloads in the global namespace: cos(float), as the oracle README says.
#include <math.h>
#include <cstdio>
#include <cstdlib>

static const char *shim_err(GLenum e) {
    switch (e) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    default: return "other";
    }
}

static inline void shim_swap() {
    GLenum e = glGetError();
    GLint depth = 0, maxdepth = 0, vp[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_MODELVIEW_STACK_DEPTH, &depth);
    glGetIntegerv(GL_MAX_MODELVIEW_STACK_DEPTH, &maxdepth);
    glGetIntegerv(GL_VIEWPORT, vp);
    std::fprintf(stderr, "shim: renderer=%s\n", (const char *)glGetString(GL_RENDERER));
    std::fprintf(stderr, "shim: glGetError at glutSwapBuffers = 0x%04X %s; modelview depth %d of max %d; viewport %dx%d\n",
                 e, shim_err(e), depth, maxdepth, vp[2], vp[3]);
    const char *out = std::getenv("CAPTURE");
    if (out) {
        int w = vp[2], h = vp[3];
        unsigned char *px = (unsigned char *)std::malloc((size_t)w * h * 3);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadBuffer(GL_BACK);
        glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, px);
        FILE *f = std::fopen(out, "wb");
        std::fprintf(f, "P6\n%d %d\n255\n", w, h);
        for (int y = h - 1; y >= 0; y--) std::fwrite(px + (size_t)y * w * 3, 1, (size_t)w * 3, f);
        std::fclose(f);
        std::free(px);
        std::fprintf(stderr, "shim: wrote %s (%dx%d)\n", out, w, h);
    }
    glutSwapBuffers();
    if (!std::getenv("HOLD")) std::exit(0);
}
#define glutSwapBuffers() shim_swap()

#ifdef CHECK_STACK
static int shim_pushes = 0, shim_pops = 0;
static inline void shim_report(const char *what, int n, const char *name) {
    GLenum e = glGetError();
    GLint depth = 0;
    glGetIntegerv(GL_MODELVIEW_STACK_DEPTH, &depth);
    std::fprintf(stderr, "%s #%d %-8s depth after=%2d glGetError=0x%04X %s\n", what, n, name, depth, e, shim_err(e));
}
static inline void shim_push(const char *name) { glPushMatrix(); shim_report("push", ++shim_pushes, name); }
static inline void shim_pop(const char *name) { glPopMatrix(); shim_report("pop ", ++shim_pops, name); }
#define glPushMatrix() shim_push((const char *)r->name)
#define glPopMatrix() shim_pop((const char *)r->name)
#endif

#ifdef SHIM_FRAME_ENV
// Optional (build flag -DSHIM_FRAME_ENV only): start at frame $FRAME instead of 0, as pressing W
// that many times would. main() is the only caller of glutMainLoop; `model` is main.cpp's global.
#define glutMainLoop() (std::getenv("FRAME") ? model.setCurrentFrame(std::atoi(std::getenv("FRAME"))) : (void)0, glutMainLoop())
#endif
