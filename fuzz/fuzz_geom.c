/* libFuzzer target: bytes -> a valid but nasty assembly (parts stacked on each other on a
 * coarse grid so that they touch, then nudged by 1e-12..1e-6 of their size to only just touch
 * or only just overlap, scaled by 1e-4..1e4, rotated, with mass ratios up to 1e6, vertices
 * on vertices and on edges) -> contact detection, static check and a lift of the top part.
 * A byte after the parts' bytes, when there is one, picks two more generators: far from the
 * origin (the whole assembly moved by 1e4..1e9 times its size, past the 1e8 that is refused) and
 * extreme magnitudes (gravity 1e-150..1e150, densities spread over 1e-150..1e150, friction from
 * 5e-324 to 1e300, coordinates scaled by 1e-100..1e100). Every LCP solution inside is verified by
 * the library; here any crash, hang or sanitizer report is a finding (make fuzz). */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cairn/cairn.h"
#include "fuzz.h"

typedef struct {
    const uint8_t *p;
    size_t n, i;
} Bytes;

static unsigned take(Bytes *b) { return b->i < b->n ? b->p[b->i++] : 0u; }

/* nudges as fractions of the part size: touching exactly, just apart, just overlapping */
static const double kNudge[8] = {0, 0, 1e-12, -1e-12, 1e-9, -1e-9, 1e-6, -1e-6};
static const double kScale[5] = {1e-4, 1e-2, 1, 1e2, 1e4};

/* where the whole assembly is moved to (the far generator) */
static double g_offset[3];

/* a point of the assembly frame: scale, rotate about the vertical axis (3-D) or in the plane */
static void emit_point(Buf *b, int dim, double s, double c, double sn, double x, double y,
                       double z) {
    double px = s * (c * x - sn * y) + g_offset[0], py = s * (sn * x + c * y) + g_offset[1];
    if (dim == 2) put(b, "[%.17g,%.17g]", px, py);
    else put(b, "[%.17g,%.17g,%.17g]", px, py, s * z + g_offset[2]);
}

/* the generators beyond the default */
enum { GEN_PLAIN, GEN_FAR, GEN_EXTREME, GEN_FAR_EXTREME };
static const double kFriction[4] = {5e-324, 1e-12, 1e12, 1e300};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Bytes in = {data, size, 0};
    unsigned h = take(&in);
    int dim = (h & 1) ? 3 : 2;
    int nparts = 1 + (int)((h >> 1) % 6);
    double scale = kScale[(h >> 4) % 5];
    double ang = (double)take(&in) * (6.283185307179586 / 256.0);
    double c = cos(ang), sn = sin(ang);
    unsigned f = take(&in);
    double mu = (f & 1) ? (double)(f >> 1) / 64.0 : 0.0;
    /* the generator: a byte after the 3 + 5 nparts the scene takes, if there is one, and two
     * more for the extreme magnitudes (each chosen apart from the others) */
    size_t at = 3 + 5 * (size_t)nparts;
    unsigned gen = at < size ? data[at] : 0u, e1 = at + 1 < size ? data[at + 1] : 0u,
             e2 = at + 2 < size ? data[at + 2] : 0u;
    double gmag = 1, dspread = 0;
    memset(g_offset, 0, sizeof g_offset);
    if (gen % 4 == GEN_EXTREME || gen % 4 == GEN_FAR_EXTREME) {
        gmag = pow(10.0, -150 + 50 * (double)(e1 % 7));
        dspread = 25 * (double)((e1 >> 3) % 7); /* densities 10^(-dspread..dspread) apart */
        scale = pow(10.0, -100 + 50 * (double)(e2 % 5));
        mu = kFriction[(e2 >> 3) % 4];
    }
    if (gen % 4 == GEN_FAR || gen % 4 == GEN_FAR_EXTREME) {
        double far = pow(10.0, 4 + (double)((gen >> 2) % 6)) * 16 * scale; /* times the ground's size */
        g_offset[0] = 0.6 * far, g_offset[1] = -0.8 * far, g_offset[2] = dim == 3 ? 0.3 * far : 0;
    }
    /* gravity rotates with the assembly: "down" is -y in 2-D, -z in 3-D, before rotation */
    Buf b = {malloc(256), 0, 256};
    put(&b, "{\"dimension\":%d,\"friction\":%.17g,", dim, mu);
    if (dim == 2) put(&b, "\"gravity\":[%.17g,%.17g],", gmag * sn, -gmag * c);
    else put(&b, "\"gravity\":[0,0,%.17g],", -9.81 * gmag);
    put(&b, "\"parts\":[{\"name\":\"G\",\"fixed\":true,");
    /* ground: a slab [-8,8] x [-1,0] (x [-8,8] in 3-D) */
    double top[8], xlo[8], ylo[8];
    top[0] = 0, xlo[0] = -3, ylo[0] = -3;
    if (dim == 2) {
        put(&b, "\"polygon\":[");
        emit_point(&b, 2, scale, c, sn, -8, -1, 0), put(&b, ",");
        emit_point(&b, 2, scale, c, sn, 8, -1, 0), put(&b, ",");
        emit_point(&b, 2, scale, c, sn, 8, 0, 0), put(&b, ",");
        emit_point(&b, 2, scale, c, sn, -8, 0, 0), put(&b, "]}");
    } else {
        put(&b, "\"hull\":[");
        for (int k = 0; k < 8; k++) {
            if (k) put(&b, ",");
            emit_point(&b, 3, scale, c, sn, (k & 1) ? 8 : -8, (k & 2) ? 8 : -8, (k & 4) ? 0 : -1);
        }
        put(&b, "]}");
    }
    for (int i = 1; i <= nparts; i++) {
        unsigned on = take(&in) % (unsigned)i; /* rests on part `on` (0 = ground) */
        unsigned g = take(&in), w = take(&in), sh = take(&in), m = take(&in);
        double width = 0.5 + 0.5 * (double)(w % 8), height = 0.5 + 0.5 * (double)((w >> 3) % 4);
        double x0 = xlo[on] + 0.5 * (double)(g % 16) - 2.0, y0 = ylo[on] + 0.5 * (double)((g >> 4) % 8);
        double nudge = kNudge[sh % 8] * (width > height ? width : height);
        double z0 = top[on] + nudge;
        double density = pow(10.0, (double)(m % 7)); /* mass ratios up to 1e6 */
        if (dspread > 0) density = pow(10.0, dspread * ((double)(m % 3) - 1));
        put(&b, ",{\"name\":\"P%d\",\"density\":%.17g,", i, density);
        int shape = (int)((sh >> 3) % 4);
        if (dim == 2) {
            put(&b, "\"polygon\":[");
            if (shape == 1) { /* triangle standing on a vertex: vertex on edge or on vertex */
                emit_point(&b, 2, scale, c, sn, x0, z0, 0), put(&b, ",");
                emit_point(&b, 2, scale, c, sn, x0 + width / 2, z0 + height, 0), put(&b, ",");
                emit_point(&b, 2, scale, c, sn, x0 - width / 2, z0 + height, 0);
            } else if (shape == 2) { /* sliver: a parallelogram of 1e-9 thickness at one end */
                emit_point(&b, 2, scale, c, sn, x0, z0, 0), put(&b, ",");
                emit_point(&b, 2, scale, c, sn, x0 + width, z0, 0), put(&b, ",");
                emit_point(&b, 2, scale, c, sn, x0 + width, z0 + height * 1e-9, 0), put(&b, ",");
                emit_point(&b, 2, scale, c, sn, x0, z0 + height, 0);
            } else { /* box, possibly sheared by a near-coplanar top */
                double tilt = shape == 3 ? height * 1e-7 : 0;
                emit_point(&b, 2, scale, c, sn, x0, z0, 0), put(&b, ",");
                emit_point(&b, 2, scale, c, sn, x0 + width, z0, 0), put(&b, ",");
                emit_point(&b, 2, scale, c, sn, x0 + width, z0 + height + tilt, 0), put(&b, ",");
                emit_point(&b, 2, scale, c, sn, x0, z0 + height, 0);
            }
            put(&b, "]}");
            xlo[i] = x0, ylo[i] = 0;
        } else {
            double depth = 0.5 + 0.5 * (double)((w >> 5) % 8);
            put(&b, "\"hull\":[");
            if (shape == 1) { /* pyramid on its apex, or a tetrahedron on an edge */
                emit_point(&b, 3, scale, c, sn, x0, y0, z0), put(&b, ",");
                if (g & 1) emit_point(&b, 3, scale, c, sn, x0 + width, y0, z0), put(&b, ",");
                emit_point(&b, 3, scale, c, sn, x0 - width, y0 - depth, z0 + height), put(&b, ",");
                emit_point(&b, 3, scale, c, sn, x0 + width, y0 - depth, z0 + height), put(&b, ",");
                emit_point(&b, 3, scale, c, sn, x0, y0 + depth, z0 + height);
            } else if (shape == 2) { /* edge-on-edge crossing: a wedge lying across */
                emit_point(&b, 3, scale, c, sn, x0 - width, y0, z0), put(&b, ",");
                emit_point(&b, 3, scale, c, sn, x0 + width, y0, z0), put(&b, ",");
                emit_point(&b, 3, scale, c, sn, x0 - width, y0 - depth, z0 + height), put(&b, ",");
                emit_point(&b, 3, scale, c, sn, x0 + width, y0 - depth, z0 + height), put(&b, ",");
                emit_point(&b, 3, scale, c, sn, x0 - width, y0 + depth, z0 + height), put(&b, ",");
                emit_point(&b, 3, scale, c, sn, x0 + width, y0 + depth, z0 + height);
            } else {
                double tilt = shape == 3 ? height * 1e-7 : 0;
                for (int k = 0; k < 8; k++) {
                    if (k) put(&b, ",");
                    emit_point(&b, 3, scale, c, sn, x0 + ((k & 1) ? width : 0),
                               y0 + ((k & 2) ? depth : 0),
                               z0 + ((k & 4) ? height + ((k & 1) ? tilt : 0) : 0));
                }
            }
            put(&b, "]}");
            xlo[i] = x0, ylo[i] = y0;
        }
        top[i] = z0 + height;
    }
    put(&b, "]}");
    if (getenv("CAIRN_FUZZ_PRINT")) printf("%s\n", b.s); /* to replay a finding with the CLI */

    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_string(b.s, "fuzz", &a, &d) == CN_OK) {
        cnContactQuery q = cn_contact_query_default();
        cnContactSet cs = {0};
        cnOverlap ov;
        if (cn_contacts_find(a, &q, &cs, &ov, &d) == CN_OK) cn_contacts_free(&cs);
        cnCheckOptions co = cn_check_options_default();
        co.max_nodes = 20; /* the search for a motion from rest: a slow input stays quick */
        cnCheckResult r;
        if (cn_check(a, &co, &r, &d) == CN_OK) cn_check_result_free(&r);
        if (nparts <= 3) {
            cnPlanOptions po = cn_plan_options_default();
            po.max_states = 20;
            po.sim.check.max_nodes = 20;
            po.max_seconds = 2;
            cnPlanResult pr;
            if (cn_plan(a, &po, &pr, &d) == CN_OK) cn_plan_result_free(&pr);
        }
        cn_assembly_free(a);
    }
    free(b.s);
    return 0;
}
