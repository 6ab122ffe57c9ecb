/* A regular surface's facet shares, clipped exactly in C: each facet's visible-lit and visible-shadowed area of
 * one period's image, for many views under one light (roughlight.render.exact.pyramid, which builds and loads it).
 *
 * The method is the exact reference's (clipping.py, reference.py), with convex pieces in place of GEOS's overlays.
 * A regular surface's facets are convex (a truncated pyramid's top and four sides, surfaces/geometry.py), so along
 * a direction D (toward the viewer or the light, plan shift d = (Dx/Dz, Dy/Dz)) what hides a facet f of period 0
 * is a set of convex polygons: its projection's overlaps with the projections of the facet copies in front of it
 * (higher at the overlap's centroid: facets meet only at edges, so there they are in front throughout). Mapped back
 * onto f's plan footprint (the inverse of the affine map x, y -> (x - z dx, y - z dy) on f's plane), the view's
 * and the light's occluders are subtracted from the footprint, kept as disjoint convex pieces: a convex piece minus
 * a convex occluder is the piece's parts outside each of the occluder's edges in turn. The areas left, times the
 * facet's projection ratio 1 - alpha dx - beta dy, are its visible and its visible-lit area of the view's image,
 * whose period has area 1.
 *
 * Double precision throughout; pieces of less than PIECE_EPS (periods^2) are floating-point slivers and dropped.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#define MAXV 64          /* a convex piece's most corners */
#define MAX_PIECES 20000 /* a facet's most pieces at once */
#define MAX_COPIES 200000
#define MIN_OVERLAP 1e-13 /* clipping.py's: smaller overlaps are slivers */
#define EDGE_ON 1e-12     /* clipping.py's: a facet whose projection ratio is smaller is edge-on */
#define PIECE_EPS 1e-18
#define SAME_POINT 1e-13 /* corners nearer than this (periods, |dx| + |dy|) are one; shorter edges have no direction */
#define GRAZING_LIGHT 1e-9 /* reference.py's: a light this low lights nothing */

enum { OK = 0, TOO_MANY_PIECES = -1, TOO_MANY_CORNERS = -2, NO_MEMORY = -3, TOO_MANY_COPIES = -4, BAD_INPUT = -5 };

typedef struct {
    int n;
    double x[MAXV], y[MAXV];
} poly;

typedef struct {
    int n, cap;
    poly *p;
} polys;

static double signed_area(const poly *p) {
    double s = 0.0;
    for (int i = 0; i < p->n; i++) {
        int j = i + 1 == p->n ? 0 : i + 1;
        s += p->x[i] * p->y[j] - p->y[i] * p->x[j];
    }
    return 0.5 * s;
}

static void centroid(const poly *p, double *cx, double *cy) {
    double a = 0.0, sx = 0.0, sy = 0.0;
    for (int i = 0; i < p->n; i++) {
        int j = i + 1 == p->n ? 0 : i + 1;
        double c = p->x[i] * p->y[j] - p->y[i] * p->x[j];
        a += c;
        sx += (p->x[i] + p->x[j]) * c;
        sy += (p->y[i] + p->y[j]) * c;
    }
    *cx = sx / (3.0 * a);
    *cy = sy / (3.0 * a);
}

static void bbox(const poly *p, double *box) {
    box[0] = box[2] = p->x[0];
    box[1] = box[3] = p->y[0];
    for (int i = 1; i < p->n; i++) {
        box[0] = fmin(box[0], p->x[i]);
        box[2] = fmax(box[2], p->x[i]);
        box[1] = fmin(box[1], p->y[i]);
        box[3] = fmax(box[3], p->y[i]);
    }
}

/* counter-clockwise, as the half-planes below take it */
static void make_ccw(poly *p) {
    if (signed_area(p) >= 0.0) return;
    for (int i = 0, j = p->n - 1; i < j; i++, j--) {
        double t = p->x[i]; p->x[i] = p->x[j]; p->x[j] = t;
        t = p->y[i]; p->y[i] = p->y[j]; p->y[j] = t;
    }
}

static int add_corner(poly *p, double x, double y) {
    if (p->n > 0 && fabs(x - p->x[p->n - 1]) + fabs(y - p->y[p->n - 1]) <= SAME_POINT) return OK; /* no edge of
                                                                                                  * length 0 */
    if (p->n >= MAXV) return TOO_MANY_CORNERS;
    p->x[p->n] = x;
    p->y[p->n++] = y;
    return OK;
}

/* The part of convex `in` where s = a x + b y - c <= 0 (sign +1) or >= 0 (sign -1), into `out`, with no repeated
 * corner; 0, or TOO_MANY_CORNERS. */
static int clip(const poly *in, double a, double b, double c, double sign, poly *out) {
    out->n = 0;
    int err = OK;
    for (int i = 0; i < in->n && !err; i++) {
        int j = i + 1 == in->n ? 0 : i + 1;
        double si = sign * (a * in->x[i] + b * in->y[i] - c), sj = sign * (a * in->x[j] + b * in->y[j] - c);
        if (si <= 0.0) err = add_corner(out, in->x[i], in->y[i]);
        if (!err && ((si < 0.0 && sj > 0.0) || (si > 0.0 && sj < 0.0))) {
            double t = si / (si - sj);
            err = add_corner(out, in->x[i] + t * (in->x[j] - in->x[i]), in->y[i] + t * (in->y[j] - in->y[i]));
        }
    }
    while (out->n > 1 && fabs(out->x[0] - out->x[out->n - 1]) + fabs(out->y[0] - out->y[out->n - 1]) <= SAME_POINT)
        out->n--;
    return err;
}

/* Edge k of convex ccw `q` as the line a x + b y = c with its inside a x + b y <= c. */
static void edge_line(const poly *q, int k, double *a, double *b, double *c) {
    int j = k + 1 == q->n ? 0 : k + 1;
    double ex = q->x[j] - q->x[k], ey = q->y[j] - q->y[k];
    *a = ey;
    *b = -ex;
    *c = ey * q->x[k] - ex * q->y[k];
}

/* `p` intersected with convex ccw `q`, into `out` (out->n < 3 when they do not overlap). */
static int intersect(const poly *p, const poly *q, poly *out) {
    poly tmp = *p;
    for (int k = 0; k < q->n; k++) {
        double a, b, c;
        edge_line(q, k, &a, &b, &c);
        if (fabs(a) + fabs(b) <= SAME_POINT) continue; /* no direction */
        int err = clip(&tmp, a, b, c, 1.0, out);
        if (err) return err;
        if (out->n < 3) return OK;
        tmp = *out;
    }
    *out = tmp;
    return OK;
}

static int push(polys *list, const poly *p) {
    if (list->n == list->cap) {
        if (list->cap >= MAX_PIECES) return TOO_MANY_PIECES;
        int cap = list->cap ? 2 * list->cap : 16;
        poly *grown = realloc(list->p, (size_t)cap * sizeof(poly));
        if (!grown) return NO_MEMORY;
        list->p = grown;
        list->cap = cap;
    }
    list->p[list->n++] = *p;
    return OK;
}

/* `pieces` minus convex ccw `occ` (its box `ob`), the result in `out` (pieces stay disjoint and convex). */
static int subtract(const polys *pieces, const poly *occ, const double *ob, polys *out) {
    out->n = 0;
    for (int i = 0; i < pieces->n; i++) {
        const poly *piece = &pieces->p[i];
        double pb[4];
        bbox(piece, pb);
        int err;
        if (pb[2] <= ob[0] || ob[2] <= pb[0] || pb[3] <= ob[1] || ob[3] <= pb[1]) {
            if ((err = push(out, piece))) return err;
            continue;
        }
        poly rest = *piece, outside, inside;
        for (int k = 0; k < occ->n; k++) {
            double a, b, c;
            edge_line(occ, k, &a, &b, &c);
            if (fabs(a) + fabs(b) <= SAME_POINT) continue; /* no direction */
            if ((err = clip(&rest, a, b, c, -1.0, &outside))) return err;
            if (outside.n >= 3 && signed_area(&outside) > PIECE_EPS && (err = push(out, &outside))) return err;
            if ((err = clip(&rest, a, b, c, 1.0, &inside))) return err;
            if (inside.n < 3 || signed_area(&inside) <= PIECE_EPS) break;
            rest = inside;
        }
    }
    return OK;
}

static double total_area(const polys *pieces) {
    double s = 0.0;
    for (int i = 0; i < pieces->n; i++) s += signed_area(&pieces->p[i]);
    return s;
}

/* The surface: F facets' corners (F, 4, 3; `sides` of each used), planes z = alpha x + beta y + gamma. */
typedef struct {
    int64_t F;
    const double *corners;
    const int64_t *sides;
    const double *alpha, *beta, *gamma;
} surface;

static double ratio(const surface *s, int64_t f, double dx, double dy) {
    return 1.0 - s->alpha[f] * dx - s->beta[f] * dy;
}

/* facet f's projection along plan shift d, shifted by (m, n) */
static void projected(const surface *s, int64_t f, double dx, double dy, double m, double n, poly *p) {
    p->n = (int)s->sides[f];
    for (int i = 0; i < p->n; i++) {
        const double *c = s->corners + (f * 4 + i) * 3;
        p->x[i] = c[0] - c[2] * dx + m;
        p->y[i] = c[1] - c[2] * dy + n;
    }
    make_ccw(p);
}

/* oblique coordinates along d on facet f's plane back to its plan footprint (clipping.py's from_oblique) */
static void to_plan(const surface *s, int64_t f, double dx, double dy, poly *p) {
    double al = s->alpha[f], be = s->beta[f], ga = s->gamma[f];
    double a = 1.0 - dx * al, b = -dx * be, c = -dy * al, e = 1.0 - dy * be, xo = -dx * ga, yo = -dy * ga;
    double det = a * e - b * c, ia = e / det, ib = -b / det, ic = -c / det, ie = a / det;
    double ox = -(ia * xo + ib * yo), oy = -(ic * xo + ie * yo);
    for (int i = 0; i < p->n; i++) {
        double x = p->x[i], y = p->y[i];
        p->x[i] = ia * x + ib * y + ox;
        p->y[i] = ic * x + ie * y + oy;
    }
    make_ccw(p);
}

/* What hides facet f along plan shift d (f facing it), mapped onto f's plan footprint, appended to `occ`. */
static int occluders(const surface *s, int64_t f, double dx, double dy, polys *occ) {
    poly home, other, overlap;
    double hb[4], gb[4], tol = 1e-12;
    projected(s, f, dx, dy, 0.0, 0.0, &home);
    bbox(&home, hb);
    double det_f = ratio(s, f, dx, dy);
    for (int64_t g = 0; g < s->F; g++) {
        double det_g = ratio(s, g, dx, dy);
        if (det_g <= EDGE_ON) continue;
        projected(s, g, dx, dy, 0.0, 0.0, &other);
        bbox(&other, gb);
        double m0 = ceil(hb[0] - gb[2] - 1.0), m1 = floor(hb[2] - gb[0] + 1.0);
        double n0 = ceil(hb[1] - gb[3] - 1.0), n1 = floor(hb[3] - gb[1] + 1.0);
        if ((m1 - m0 + 1.0) * (n1 - n0 + 1.0) > MAX_COPIES) return TOO_MANY_COPIES;
        for (double m = m0; m <= m1; m++) {
            if (gb[2] + m <= hb[0] + tol || gb[0] + m >= hb[2] - tol) continue;
            for (double n = n0; n <= n1; n++) {
                if (g == f && m == 0.0 && n == 0.0) continue;
                if (gb[3] + n <= hb[1] + tol || gb[1] + n >= hb[3] - tol) continue;
                projected(s, g, dx, dy, m, n, &other);
                int err = intersect(&home, &other, &overlap);
                if (err) return err;
                if (overlap.n < 3 || signed_area(&overlap) <= MIN_OVERLAP) continue;
                double cx, cy;
                centroid(&overlap, &cx, &cy);
                double z_g = (s->alpha[g] * (cx - m) + s->beta[g] * (cy - n) + s->gamma[g]) / det_g;
                double z_f = (s->alpha[f] * cx + s->beta[f] * cy + s->gamma[f]) / det_f;
                if (!(z_g > z_f)) continue;
                to_plan(s, f, dx, dy, &overlap);
                if ((err = push(occ, &overlap))) return err;
            }
        }
    }
    return OK;
}

/* `pieces` minus every polygon of `occ`, in place (`spare` a second list). */
static int subtract_all(polys *pieces, polys *spare, const polys *occ) {
    for (int k = 0; k < occ->n && pieces->n > 0; k++) {
        double ob[4];
        bbox(&occ->p[k], ob);
        int err = subtract(pieces, &occ->p[k], ob, spare);
        if (err) return err;
        polys t = *pieces;
        *pieces = *spare;
        *spare = t;
    }
    return OK;
}

/* Each facet's visible-lit and visible-shadowed area of each view's image (one period: the facets' areas sum to 1)
 * under each of several lights, each view's visibility clipped once for all of them.
 *
 * corners (F, 4, 3), sides (F,), alpha, beta, gamma (F,): the facets; normals (F, 3) unit; lights (L, 3) unit toward
 * each light; shadows 0 or 1; views (V, 3) unit toward the detector, above the horizon; lit, shadowed (L, V, F) out.
 * Returns 0, or a negative code (the enum above) with the outputs unfinished. */
int roughlight_pyramid_shares(const double *corners, const int64_t *sides, int64_t F, const double *alpha,
                              const double *beta, const double *gamma, const double *normals, const double *lights,
                              int64_t L, int shadows, const double *views, int64_t V, double *lit, double *shadowed) {
    surface s = {F, corners, sides, alpha, beta, gamma};
    for (int64_t f = 0; f < F; f++)
        if (sides[f] < 3 || sides[f] > 4) return BAD_INPUT;
    int err = OK;
    polys *shade = calloc((size_t)(L * F), sizeof(polys)); /* each light's occluders of each facet, on its footprint */
    int *facing = calloc((size_t)(L * F), sizeof(int));     /* 1: the facet faces the light */
    polys seen = {0, 0, NULL}, pieces = {0, 0, NULL}, spare = {0, 0, NULL}, occ = {0, 0, NULL};
    if (!shade || !facing) { err = NO_MEMORY; goto done; }
    for (int64_t l = 0; l < L; l++) {
        const double *light = lights + 3 * l;
        double dlx = 0.0, dly = 0.0;
        int light_up = light[2] >= GRAZING_LIGHT;
        if (light_up) { dlx = light[0] / light[2]; dly = light[1] / light[2]; }
        for (int64_t f = 0; f < F; f++) {
            const double *nf = normals + 3 * f;
            double ndotl = nf[0] * light[0] + nf[1] * light[1] + nf[2] * light[2];
            int64_t k = l * F + f;
            if (!shadows) { facing[k] = ndotl > 0.0; continue; }
            facing[k] = light_up && ndotl > 0.0 && ratio(&s, f, dlx, dly) > EDGE_ON;
            if (facing[k] && (err = occluders(&s, f, dlx, dly, &shade[k]))) goto done;
        }
    }
    for (int64_t v = 0; v < V; v++) {
        const double *D = views + 3 * v;
        if (!(D[2] > 0.0)) { err = BAD_INPUT; goto done; }
        double dx = D[0] / D[2], dy = D[1] / D[2];
        for (int64_t f = 0; f < F; f++) {
            double det = ratio(&s, f, dx, dy);
            for (int64_t l = 0; l < L; l++) lit[(l * V + v) * F + f] = shadowed[(l * V + v) * F + f] = 0.0;
            if (det <= EDGE_ON) continue;
            occ.n = 0;
            if ((err = occluders(&s, f, dx, dy, &occ))) goto done;
            poly foot;
            projected(&s, f, 0.0, 0.0, 0.0, 0.0, &foot);
            seen.n = 0;
            if ((err = push(&seen, &foot))) goto done;
            if ((err = subtract_all(&seen, &spare, &occ))) goto done;
            double visible = total_area(&seen) * det;
            for (int64_t l = 0; l < L; l++) {
                int64_t k = l * F + f, out = (l * V + v) * F + f;
                double bright = 0.0;
                if (facing[k] && shade[k].n == 0) bright = visible;
                else if (facing[k]) {
                    pieces.n = 0;
                    for (int i = 0; i < seen.n; i++)
                        if ((err = push(&pieces, &seen.p[i]))) goto done;
                    if ((err = subtract_all(&pieces, &spare, &shade[k]))) goto done;
                    bright = fmin(total_area(&pieces) * det, visible);
                }
                lit[out] = bright;
                shadowed[out] = visible - bright;
            }
        }
    }
done:
    if (shade)
        for (int64_t k = 0; k < L * F; k++) free(shade[k].p);
    free(shade);
    free(facing);
    free(seen.p);
    free(pieces.p);
    free(spare.p);
    free(occ.p);
    return err;
}
