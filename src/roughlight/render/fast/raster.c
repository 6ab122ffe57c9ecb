/* A random tile's region triangles counted on a view's torus of pixel centres: the compiled half of
 * roughlight/render/fast/raster.py, which documents the method and builds this file (raster.build_kernel).
 *
 * Every quantity follows raster.py's description, in double precision, with the same operations in the same order
 * for every view: built without fused multiply-adds or fast-math (-ffp-contract=off), the counts are the same
 * with every compiler on machines with IEEE double arithmetic (x86-64, arm64). */

#include <math.h>
#include <stdint.h>

/* The compiler that built this file, as the sweeps record it (raster.identity). */
const char *roughlight_compiler(void)
{
#if defined(__clang__)
    return "clang " __clang_version__;
#elif defined(__GNUC__)
    return "gcc " __VERSION__;
#else
    return "a C compiler";
#endif
}

/* x // y and x mod y as Python takes them (rounded down; y > 0 here). */
static int64_t floor_div(int64_t x, int64_t y) { return x / y - (x % y < 0); }
static int64_t floor_mod(int64_t x, int64_t y) { const int64_t m = x % y; return m < 0 ? m + y : m; }

/* One triangle, its corners at pixels (px, py) and heights pz, scanned onto the torus (a, b, c): each centre
 * inside keeps region r where it is the highest yet (zbuf, rbuf); returns the number of centres inside. */
static int64_t scan(const double px[3], const double py[3], const double pz[3], int64_t r, int64_t a, int64_t b,
                    int64_t c, double *zbuf, int32_t *rbuf)
{
    const double twice = (px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]);
    if (!(twice > 0.0)) /* faces away, or edge-on */
        return 0;
    /* corners in (y, x) order: each edge is walked from its lower end, the same way in both its triangles */
    int i0 = 0, i1 = 1, i2 = 2, s;
    if (py[i1] < py[i0] || (py[i1] == py[i0] && px[i1] < px[i0])) { s = i0; i0 = i1; i1 = s; }
    if (py[i2] < py[i1] || (py[i2] == py[i1] && px[i2] < px[i1])) {
        s = i1; i1 = i2; i2 = s;
        if (py[i1] < py[i0] || (py[i1] == py[i0] && px[i1] < px[i0])) { s = i0; i0 = i1; i1 = s; }
    }
    const double x0 = px[i0], y0 = py[i0], x1 = px[i1], y1 = py[i1], x2 = px[i2], y2 = py[i2];
    const int64_t first = (int64_t)ceil(y0 - 0.5), middle = (int64_t)ceil(y1 - 0.5), last = (int64_t)ceil(y2 - 0.5);
    if (last <= first)
        return 0;
    /* the height over the pixel plane: z = z_base + gx x + gy y */
    const double e1z = pz[1] - pz[0], e2z = pz[2] - pz[0];
    const double gx = (e1z * (py[2] - py[0]) - e2z * (py[1] - py[0])) / twice;
    const double gy = (e2z * (px[1] - px[0]) - e1z * (px[2] - px[0])) / twice;
    const double z_base = pz[0] - gx * px[0] - gy * py[0];
    const double s02 = (x2 - x0) / (y2 - y0);
    const double s01 = y1 > y0 ? (x1 - x0) / (y1 - y0) : 0.0;
    const double s12 = y2 > y1 ? (x2 - x1) / (y2 - y1) : 0.0;
    int64_t inside = 0;
    for (int64_t j = first; j < last; j++) { /* rows whose centre y = j + 1/2 lies in [y0, y2) */
        const double yc = (double)j + 0.5;
        double xa = x0 + (yc - y0) * s02;
        double xb = j < middle ? x0 + (yc - y0) * s01 : x1 + (yc - y1) * s12;
        if (xa > xb) { const double t = xa; xa = xb; xb = t; }
        const int64_t i_first = (int64_t)ceil(xa - 0.5), i_last = (int64_t)ceil(xb - 0.5); /* xa <= i + 1/2 < xb */
        if (i_last <= i_first)
            continue;
        inside += i_last - i_first;
        const int64_t q = floor_div(j, c), row = (j - q * c) * a;
        int64_t col = floor_mod(i_first - q * b, a);
        double z = z_base + gy * yc + gx * ((double)i_first + 0.5);
        for (int64_t i = i_first; i < i_last; i++) {
            if (z > zbuf[row + col]) {
                zbuf[row + col] = z;
                rbuf[row + col] = (int32_t)r;
            }
            z += gx;
            if (++col == a)
                col = 0;
        }
    }
    return inside;
}

/* Each view: the buffers cleared, every triangle's corners taken to pixels (matrix @ ((x, y) - z d)) and scanned,
 * the visible regions tallied. Arrays are C-ordered: tris (n_tris, 3, 3), region (n_tris,), shears (n_views, 2),
 * matrix (2, 2), visible and total (n_views, n_regions) zeroed by the caller, zbuf and rbuf (a c,) scratch. */
void roughlight_count_views(const double *tris, const int64_t *region, int64_t n_tris, int64_t n_regions,
                            const double *shears, int64_t n_views, const double *matrix, int64_t a, int64_t b,
                            int64_t c, int totals, double *visible, double *total, double *zbuf, int32_t *rbuf)
{
    const int64_t n_pix = a * c;
    for (int64_t v = 0; v < n_views; v++) {
        for (int64_t p = 0; p < n_pix; p++) {
            zbuf[p] = -INFINITY;
            rbuf[p] = -1;
        }
        const double dx = shears[2 * v], dy = shears[2 * v + 1];
        for (int64_t t = 0; t < n_tris; t++) {
            const double *corner = tris + 9 * t;
            double px[3], py[3], pz[3];
            for (int k = 0; k < 3; k++, corner += 3) {
                const double cx = corner[0] - corner[2] * dx, cy = corner[1] - corner[2] * dy;
                px[k] = matrix[0] * cx + matrix[1] * cy;
                py[k] = matrix[2] * cx + matrix[3] * cy;
                pz[k] = corner[2];
            }
            const int64_t inside = scan(px, py, pz, region[t], a, b, c, zbuf, rbuf);
            if (totals)
                total[v * n_regions + region[t]] += (double)inside;
        }
        for (int64_t p = 0; p < n_pix; p++)
            if (rbuf[p] >= 0)
                visible[v * n_regions + rbuf[p]] += 1.0;
    }
}

/* Each segment's star discrepancy against the pixel-centre rows r + 1/2 it spans (roughlight/render/fast/shares.py,
 * _star_discrepancy, which this computes to the bit): walking its rows, the running sum of (pixel centres left of
 * it) - (its x), one sum carried over every segment in turn as numpy's cumsum carries it, and of the segment's part
 * of it the largest absolute value from either end. star (n,) is written, 0 where a segment is not valid or spans no
 * row; valid (n,) is 0 or 1. */
void roughlight_star_discrepancy(const double *x0, const double *y0, const double *x1, const double *y1,
                                 const uint8_t *valid, int64_t n, double *star)
{
    double running = 0.0;
    for (int64_t s = 0; s < n; s++) {
        star[s] = 0.0;
        if (!valid[s])
            continue;
        const double lo = y0[s] < y1[s] ? y0[s] : y1[s], hi = y0[s] < y1[s] ? y1[s] : y0[s];
        const double first = ceil(lo - 0.5);
        const double rows = ceil(hi - 0.5) - first;
        if (!(rows > 0.0))
            continue;
        const int64_t count = (int64_t)rows;
        const double slope = (x1[s] - x0[s]) / (y1[s] - y0[s]);
        const double base = x0[s] - 0.5 + (first + 0.5 - y0[s]) * slope;
        const double before = running;
        double top = -INFINITY, bottom = INFINITY;
        for (int64_t r = 0; r < count; r++) {
            const double x = base + (double)r * slope;
            running += 0.5 - (x - floor(x));
            if (running > top)
                top = running;
            if (running < bottom)
                bottom = running;
        }
        const double high = top - before > 0.0 ? top - before : 0.0;
        const double low = bottom - before < 0.0 ? bottom - before : 0.0;
        const double total = running - before;
        double best = fabs(high);
        if (fabs(low) > best)
            best = fabs(low);
        if (fabs(total - high) > best)
            best = fabs(total - high);
        if (fabs(total - low) > best)
            best = fabs(total - low);
        star[s] = best;
    }
}
