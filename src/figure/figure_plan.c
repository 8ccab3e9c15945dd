/* plan --html: the rows of a plan's sequence x path table, each simulated along its paths, on one
 * interactive page. */
#include <stdio.h>
#include <string.h>

#include "cairn/cairn.h"
#include "cairn/figure.h"
#include "core.h"

/* The label of a table row on the page: its number, then each step's parts and path. NULL out of
 * memory. */
static char *row_label(const cnAssembly *a, int row, const cnPlanSequence *seq) {
    size_t cap = 64;
    for (int k = 0; k < seq->n; k++) cap += 8 + strlen(seq->steps[k].path) + 64 * (size_t)seq->steps[k].move.n;
    char *label = cn_malloc(cap);
    if (!label) return NULL;
    int len = snprintf(label, cap, "%d.", row + 1);
    for (int k = 0; k < seq->n; k++) {
        const cnPlanMove *m = &seq->steps[k];
        len += snprintf(label + len, cap - (size_t)len, " ");
        for (int j = 0; j < m->move.n; j++)
            len += snprintf(label + len, cap - (size_t)len, "%s%.60s", j ? "+" : "", a->parts[m->move.idx[j]].name);
        len += snprintf(label + len, cap - (size_t)len, " (%s)", m->path);
    }
    return label;
}

/* A row with steps to play: not empty (the assembly not stable as it stands), and no move
 * rejected by Proposition 1 on no particular path (the search past 16 free parts rejects a part
 * that way before generating its paths). */
static bool playable_row(const cnPlanSequence *seq) {
    if (seq->n == 0) return false;
    for (int k = 0; k < seq->n; k++)
        if (seq->steps[k].nseg == 0) return false;
    return true;
}

cnStatus cn_figure_plan_html(const char *path, const char *file, const cnLoadOptions *load, const cnAssembly *a,
                             const cnPlanResult *r, const cnSimOptions *so, cnDiag *diag) {
    cnDiag own;
    if (!diag) diag = &own;
    cn_diag_clear(diag);
    int n = 0, done = 0, playable = 0;
    size_t cap_rows = (size_t)(r->nrows < CN_FIGURE_PLAN_ROWS ? r->nrows : CN_FIGURE_PLAN_ROWS) + 1;
    cnAssembly **asms = cn_calloc(cap_rows, sizeof *asms);
    cnSimResult *sims = cn_calloc(cap_rows, sizeof *sims);
    const cnSimResult **runs = cn_calloc(cap_rows, sizeof *runs);
    char **labels = cn_calloc(cap_rows, sizeof *labels);
    const char **details = cn_calloc(cap_rows, sizeof *details);
    cnStatus s = !asms || !sims || !runs || !labels || !details ? cn_diag_oom(diag) : CN_OK;
    for (int row = 0; row < r->nrows && s == CN_OK; row++) {
        const cnPlanSequence *seq = &r->table[row].seq;
        if (!playable_row(seq) || ++playable > CN_FIGURE_PLAN_ROWS) continue;
        int i = n++;
        char *plan = cn_plan_sequence_json(a, seq);
        s = plan ? cn_assembly_load_with(file, NULL, plan, load, &asms[i], diag) : cn_diag_oom(diag);
        cn_string_free(plan);
        if (s == CN_OK) s = cn_simulate(asms[i], so, &sims[i], diag);
        if (s != CN_OK) {
            if (!diag->file[0]) snprintf(diag->file, sizeof diag->file, "%s", file); /* the input's fault */
            break;
        }
        runs[i] = &sims[i];
        done++; /* sims[0 .. done - 1] are freed at the end */
        details[i] = cn_plan_row_word(&r->table[row]);
        if (!(labels[i] = row_label(a, row, seq))) s = cn_diag_oom(diag);
    }
    if (s == CN_OK) {
        /* no row to play: the page shows the assembly at rest and why */
        if (n == 0) asms[0] = (cnAssembly *)a;
        char more[160];
        snprintf(more, sizeof more, "disassembly sequences: click a row to play it (the first %d of the table's %d "
                 "rows with steps; the text report lists the table)", CN_FIGURE_PLAN_ROWS, playable);
        const char *sub = playable > n ? more
                          : n > 0 ? "disassembly sequences: click a row to play it"
                          : r->unstable_at_start ? "no sequence to play: the assembly is not stable as it stands"
                                                 : "no sequence to play";
        s = cn_figure_html(path, (const cnAssembly *const *)asms, runs, (const char *const *)labels, details, n, sub,
                           diag);
        if (n == 0) asms[0] = NULL;
    }
    for (int i = 0; i < done; i++) cn_sim_result_free(&sims[i]);
    for (int i = 0; labels && i < (int)cap_rows; i++) cn_free(labels[i]);
    for (int i = 0; asms && i < (int)cap_rows - 1; i++) cn_assembly_free(asms[i]);
    cn_free(asms), cn_free(sims), cn_free(runs), cn_free(labels), cn_free(details);
    return s;
}
