/* Grids of the error maps and rasters.
 *
 * nearest_point_grid: nearest-neighbour gridding of scattered points. Local coordinates
 * in metres: x grows east from the grid's west edge, y grows north and is <= 0 inside
 * the grid (0 at its north edge). Points are bucketed by grid cell (a counting sort);
 * each cell centre then searches rings of cells around its own, nearest ring first, and
 * stops once no point of a farther ring can beat the best found, so the result is the
 * exact nearest point within the gap.
 *
 * highest_surface: the highest triangle under each cell centre. Coordinates local to
 * the grid's top-left corner (x = easting - x_min, y = y_max - northing, both growing
 * into the grid). A vertical ray cast down at a cell centre first hits the highest
 * triangle whose footprint contains the centre; triangles seen edge-on from above
 * (walls) have no footprint and are skipped. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernels.h"
#include "parallel.h"

static inline int64_t clamp64(int64_t v, int64_t lo, int64_t hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

typedef struct {
    const double *x, *y;
    int64_t rows, cols;
    double cell, gap;
    int64_t *key;
    const int64_t *start, *order;
    int64_t *out;
} grid_ctx;

static void key_range(void *arg, int64_t b, int64_t e)
{
    grid_ctx *g = arg;
    for (int64_t p = b; p < e; p++) {
        /* points beyond the grid go to its edge cells; the clamp runs in double so
         * that far-off points cannot overflow the integer */
        double fj = floor(g->x[p] / g->cell), fi = floor(-g->y[p] / g->cell);
        fj = fj > 0.0 ? fj : 0.0;  /* (a NaN goes to 0 too) */
        fi = fi > 0.0 ? fi : 0.0;
        fj = fj < (double)(g->cols - 1) ? fj : (double)(g->cols - 1);
        fi = fi < (double)(g->rows - 1) ? fi : (double)(g->rows - 1);
        g->key[p] = (int64_t)fi * g->cols + (int64_t)fj;
    }
}

static void search_rows(void *arg, int64_t i0, int64_t i1)
{
    grid_ctx *g = arg;
    const double cell = g->cell, gap2 = g->gap * g->gap;
    const int64_t rows = g->rows, cols = g->cols;
    /* a point r cells away (in rows or columns) is at least (r - 0.5) cells from a centre */
    const int64_t reach = (int64_t)ceil(g->gap / cell + 0.5);
    for (int64_t i = i0; i < i1; i++) {
        double cy = -(i + 0.5) * cell;
        for (int64_t j = 0; j < cols; j++) {
            double cx = (j + 0.5) * cell;
            double best = gap2;
            int64_t best_p = -1;
            for (int64_t r = 0; r <= reach; r++) {
                if (r >= 1 && (r - 0.5) * cell * ((r - 0.5) * cell) > best)
                    break; /* every point of this ring and beyond is farther (an equally
                            * near one may still win the tie on its lower index) */
                int64_t ii_end = i + r + 1 < rows ? i + r + 1 : rows;
                for (int64_t ii = i - r > 0 ? i - r : 0; ii < ii_end; ii++) {
                    int ring_row = ii == i - r || ii == i + r;
                    int64_t step = ring_row ? 1 : 2 * r;
                    int64_t jj = ring_row ? (j - r > 0 ? j - r : 0) : j - r;
                    int64_t jj_end = j + r < cols - 1 ? j + r : cols - 1;
                    for (; jj <= jj_end; jj += step) {
                        if (jj < 0)
                            continue;
                        int64_t k = ii * cols + jj;
                        for (int64_t s = g->start[k]; s < g->start[k + 1]; s++) {
                            int64_t p = g->order[s];
                            double dx = g->x[p] - cx, dy = g->y[p] - cy;
                            double d2 = dx * dx + dy * dy;
                            if (d2 < best || (d2 == best && best_p >= 0 && p < best_p))
                                best = d2, best_p = p;
                        }
                    }
                }
            }
            g->out[i * cols + j] = best_p;
        }
    }
}

int nearest_point_grid(const double *x, const double *y, int64_t n, int64_t rows,
                       int64_t cols, double cell, double gap, int64_t *out, int n_threads)
{
    int64_t n_cells = rows * cols;
    int64_t *key = malloc(sizeof(int64_t) * (n > 0 ? n : 1));
    int64_t *start = calloc(n_cells + 1, sizeof(int64_t));
    int64_t *fill = malloc(sizeof(int64_t) * (n_cells > 0 ? n_cells : 1));
    int64_t *order = malloc(sizeof(int64_t) * (n > 0 ? n : 1));
    int status = -1;
    if (!key || !start || !fill || !order)
        goto done;
    grid_ctx g = {x, y, rows, cols, cell, gap, key, start, order, out};
    parallel_for(n, 1 << 14, n_threads, key_range, &g);
    for (int64_t p = 0; p < n; p++)
        start[key[p] + 1]++;
    for (int64_t k = 0; k < n_cells; k++)
        start[k + 1] += start[k];
    memcpy(fill, start, sizeof(int64_t) * n_cells);
    for (int64_t p = 0; p < n; p++)
        order[fill[key[p]]++] = p;
    parallel_for(rows, 1, n_threads, search_rows, &g);
    status = 0;
done:
    free(key);
    free(start);
    free(fill);
    free(order);
    return status;
}

void highest_surface(const double *xy_local, const double *z, const int64_t *faces, int64_t m,
                     double cell, int64_t rows, int64_t cols, double *out)
{
    /* out (rows, cols), NaN-filled by the caller */
    const double eps = 1e-12;
    for (int64_t f = 0; f < m; f++) {
        int64_t a = faces[3 * f], b = faces[3 * f + 1], c = faces[3 * f + 2];
        double ax = xy_local[2 * a], ay = xy_local[2 * a + 1];
        double bx = xy_local[2 * b], by = xy_local[2 * b + 1];
        double cx = xy_local[2 * c], cy = xy_local[2 * c + 1];
        double det = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay);
        double scale = fmax(fabs(bx - ax) + fabs(cx - ax), fabs(by - ay) + fabs(cy - ay));
        if (fabs(det) <= 1e-12 * scale * scale || scale == 0.0)
            continue;
        double x_lo = fmin(ax, fmin(bx, cx)), x_hi = fmax(ax, fmax(bx, cx));
        double y_lo = fmin(ay, fmin(by, cy)), y_hi = fmax(ay, fmax(by, cy));
        double fj0 = ceil(x_lo / cell - 0.5), fj1 = floor(x_hi / cell - 0.5);
        double fi0 = ceil(y_lo / cell - 0.5), fi1 = floor(y_hi / cell - 0.5);
        if (fj1 < 0.0 || fi1 < 0.0 || fj0 > (double)(cols - 1) || fi0 > (double)(rows - 1))
            continue; /* wholly outside the grid */
        int64_t j0 = fj0 < 0.0 ? 0 : (int64_t)fj0, i0 = fi0 < 0.0 ? 0 : (int64_t)fi0;
        int64_t j1 = clamp64((int64_t)fj1, 0, cols - 1), i1 = clamp64((int64_t)fi1, 0, rows - 1);
        for (int64_t i = i0; i <= i1; i++) {
            double py = (i + 0.5) * cell;
            for (int64_t j = j0; j <= j1; j++) {
                double px = (j + 0.5) * cell;
                /* barycentric weights of (px, py) */
                double wb = ((px - ax) * (cy - ay) - (cx - ax) * (py - ay)) / det;
                double wc = ((bx - ax) * (py - ay) - (px - ax) * (by - ay)) / det;
                double wa = 1.0 - wb - wc;
                if (wa < -eps || wb < -eps || wc < -eps)
                    continue;
                double h = wa * z[a] + wb * z[b] + wc * z[c];
                if (!(out[i * cols + j] >= h)) /* NaN or lower */
                    out[i * cols + j] = h;
            }
        }
    }
}
