/* Figures (figure.c, figure_sim.c) draw scenes of an assembly with figure_scene.c: what a
 * scene holds, how it is rendered, and the legends they share. Private to src/figure/. */
#ifndef CAIRN_FIGURE_SCENE_H
#define CAIRN_FIGURE_SCENE_H

#include "figure_plot.h"

/* What to draw: parts posed (absent ones left out), contacts, the parts that move. */
typedef struct {
    int id;
    double point[3], normal[3], force, friction[3];
    bool separates, slides;
} FigContact;

typedef struct {
    const cnPose *pose;        /* per part; NULL: as loaded */
    const unsigned char *absent; /* NULL: every part but grippers */
    int ncontacts;
    const FigContact *contacts;
    const cnPartMotion *motion; /* per part, NULL: nothing moves */
    const unsigned char *red;   /* per part: drawn red (it starts to move) */
    bool friction;
    const cnPose *moved;        /* per part, NULL: the red parts also drawn dashed where their
                                   motion takes them (a collapse mechanism) */
    const unsigned char *gripped; /* per part, NULL: drawn steel blue (the gripper moves it) */
} Scene;

/* Draw a scene on a cairo context; fit the view on the scenes `fitp` (the same view for the
 * pictures of one step). title: first line; verdict: second line (red when bad); legend: the
 * bottom line. */
typedef struct {
    const cnAssembly *a;
    const Scene *sc;
    const Scene *const *fitp;
    int nfit;
    const cnFigureOptions *o;
    const char *title, *verdict, *legend;
    bool bad;
    double fscale;
    const double *gravity; /* drawn as an arrow when not NULL */
} Render;

/* Write the rendering to `path` (PNG), or with formats = 3 to base.png, base.svg and base.pdf
 * (path is then the base name without extension). */
cnStatus cn_fg_render_files(const char *path, int formats, const Render *R, cnDiag *diag);

/* A check's contacts as drawn: points, normals, open and sliding, and (forces) their forces. */
void cn_fg_contacts(const cnCheckResult *r, int nc, bool forces, FigContact *fc);

/* The legends of a check's figure, without and with friction; ... in a step of a simulation,
 * before them */
#define CN_FG_LEGEND                                                                               \
    "blue: contact force on the upper part of each pair (longest = largest); dots: contacts "     \
    "(red opens, orange slides, hollow behind a part); red: parts that start to move, and how"
#define CN_FG_LEGEND_F                                                                             \
    "on the upper part of each pair: blue contact force (longest = largest), green friction; "    \
    "dots: contacts (red opens, orange slides, hollow behind a part); red: parts that start to move"
#define CN_FG_LEGEND_STEP "steel blue: the part the gripper moves; "

#endif
