/* Bounding-volume hierarchy over triangles and exact nearest-triangle queries.
 *
 * The hierarchy is built over triangles sorted by the Morton code of their centroids
 * (one grid scale for all axes); a node splits its range where the highest differing
 * Morton bit changes (Karras 2012), or in the middle when all codes are equal. Queries
 * descend nearest child first and prune every box (and every triangle's own box) not
 * closer than the best distance so far, so the result is the exact nearest triangle.
 * Points are processed in Morton order, in blocks run in parallel; within a block each
 * point starts from the previous point's triangle as an upper bound. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "closest.h"
#include "kernels.h"
#include "parallel.h"

#define LEAF_SIZE 8
#define STACK 256  /* deeper than any tree built here: <= 63 bit splits + log2(M) middle splits */
#define BLOCK 512  /* points per parallel work item; consecutive points warm-start each other */
#define PREFETCH 8  /* points ahead whose coordinates and distance are fetched early */

static inline double dmin(double a, double b) { return a < b ? a : b; }
static inline double dmax(double a, double b) { return a > b ? a : b; }

/* ------------------------------------------------------------------ Morton codes */
static inline uint64_t spread21(uint64_t v)
{
    v = (v | (v << 32)) & 0x1F00000000FFFFull;
    v = (v | (v << 16)) & 0x1F0000FF0000FFull;
    v = (v | (v << 8)) & 0x100F00F00F00F00Full;
    v = (v | (v << 4)) & 0x10C30C30C30C30C3ull;
    v = (v | (v << 2)) & 0x1249249249249249ull;
    return v;
}

static inline uint64_t morton_of(const double p[3], const double lo[3], const double scale[3])
{
    const double top = (double)((1 << 21) - 1);
    uint64_t code = 0;
    for (int a = 0; a < 3; a++) {
        double q = (p[a] - lo[a]) * scale[a];
        q = q > 0.0 ? q : 0.0;  /* (a NaN goes to 0 too: the cast below stays defined) */
        q = q < top ? q : top;
        code |= spread21((uint64_t)q) << a;
    }
    return code;
}

typedef struct {
    const double *xyz, *lo, *scale;
    const int64_t *faces;
    uint64_t *out;
} morton_ctx;

static void centroid_range(void *arg, int64_t b, int64_t e)
{
    morton_ctx *c = arg;
    for (int64_t f = b; f < e; f++) {
        const int64_t *v = c->faces + 3 * f;
        double centroid[3];
        for (int a = 0; a < 3; a++)
            centroid[a] = (c->xyz[3 * v[0] + a] + c->xyz[3 * v[1] + a] + c->xyz[3 * v[2] + a]) / 3.0;
        c->out[f] = morton_of(centroid, c->lo, c->scale);
    }
}

void centroid_codes(const double *local, const int64_t *faces, int64_t m, const double lo[3],
                    const double scale[3], uint64_t *out, int n_threads)
{
    morton_ctx c = {local, lo, scale, faces, out};
    parallel_for(m, 1 << 14, n_threads, centroid_range, &c);
}

int radix_argsort(const uint64_t *codes, int64_t n, int64_t *order)
{
    /* LSD radix sort on 16-bit digits, stable; digits equal for every code are skipped */
    int64_t *tmp = malloc(sizeof(int64_t) * (n > 0 ? n : 1));
    int64_t *count = malloc(sizeof(int64_t) * ((1 << 16) + 1));
    if (tmp == NULL || count == NULL) {
        free(tmp);
        free(count);
        return -1;
    }
    int64_t *src = order, *dst = tmp;
    for (int64_t i = 0; i < n; i++)
        src[i] = i;
    for (int shift = 0; shift < 64; shift += 16) {
        memset(count, 0, sizeof(int64_t) * ((1 << 16) + 1));
        for (int64_t i = 0; i < n; i++)
            count[((codes[i] >> shift) & 0xFFFF) + 1]++;
        int64_t most = 0;
        for (int d = 0; d <= (1 << 16); d++)
            most = count[d] > most ? count[d] : most;
        if (most == n)
            continue; /* this digit is the same for every code */
        for (int d = 0; d < (1 << 16); d++)
            count[d + 1] += count[d];
        for (int64_t i = 0; i < n; i++) {
            int64_t j = src[i];
            dst[count[(codes[j] >> shift) & 0xFFFF]++] = j;
        }
        int64_t *swap = src;
        src = dst;
        dst = swap;
    }
    if (src != order)
        memcpy(order, src, sizeof(int64_t) * n);
    free(tmp);
    free(count);
    return 0;
}

/* ------------------------------------------------------------------ construction */
static int64_t split(const uint64_t *codes, int64_t start, int64_t end)
{
    uint64_t first = codes[start], last = codes[end - 1];
    if (first == last)
        return (start + end) >> 1;
    int bit = 63 - __builtin_clzll(first ^ last);
    /* first index in [start, end) whose code has that bit set (codes are sorted) */
    int64_t lo = start, hi = end - 1;
    while (lo < hi) {
        int64_t mid = (lo + hi) >> 1;
        if ((codes[mid] >> bit) & 1u)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

int64_t build_bvh(const uint64_t *codes, const double *tri, int64_t m, double *box,
                  int64_t *link)
{
    /* link: an inner node has (first child, 0) with its two children side by side; a leaf
     * has (first triangle, number of triangles). Node 0 is the root and parents precede
     * their children, so boxes are computed in one backward pass. */
    int64_t cap = m > 0 ? 2 * m - 1 : 1;
    int64_t *span = malloc(sizeof(int64_t) * 2 * cap);
    if (span == NULL)
        return -2;
    int64_t stack[STACK];
    span[0] = 0, span[1] = m;
    stack[0] = 0;
    int64_t n_nodes = 1;
    int sp = 1;
    while (sp > 0) {
        int64_t node = stack[--sp];
        int64_t s = span[2 * node], c = span[2 * node + 1];
        if (c <= LEAF_SIZE) {
            link[2 * node] = s, link[2 * node + 1] = c;
            continue;
        }
        if (sp + 2 > STACK) {
            free(span);
            return -1;
        }
        int64_t cut = split(codes, s, s + c);
        link[2 * node] = n_nodes, link[2 * node + 1] = 0;
        span[2 * n_nodes] = s, span[2 * n_nodes + 1] = cut - s;
        span[2 * n_nodes + 2] = cut, span[2 * n_nodes + 3] = s + c - cut;
        stack[sp] = n_nodes, stack[sp + 1] = n_nodes + 1;
        sp += 2;
        n_nodes += 2;
    }
    for (int64_t node = n_nodes - 1; node >= 0; node--) {
        double *bx = box + 6 * node;
        if (link[2 * node + 1] > 0) {
            for (int a = 0; a < 3; a++) {
                double mn = INFINITY, mx = -INFINITY;
                int64_t first = span[2 * node];
                for (int64_t t = first; t < first + span[2 * node + 1]; t++)
                    for (int corner = 0; corner < 3; corner++) {
                        double v = tri[9 * t + 3 * corner + a];
                        mn = dmin(mn, v);
                        mx = dmax(mx, v);
                    }
                bx[a] = mn, bx[3 + a] = mx;
            }
        } else {
            const double *c0 = box + 6 * link[2 * node], *c1 = c0 + 6;
            for (int a = 0; a < 3; a++) {
                bx[a] = dmin(c0[a], c1[a]);
                bx[3 + a] = dmax(c0[3 + a], c1[3 + a]);
            }
        }
    }
    free(span);
    return n_nodes;
}

/* ------------------------------------------------------------------------ queries */
static inline double gap(double lo, double p, double hi)
{
    return dmax(dmax(lo - p, 0.0), p - hi);
}

static inline double box_d2(double px, double py, double pz, const double *b)
{
    return sq(gap(b[0], px, b[3])) + sq(gap(b[1], py, b[4])) + sq(gap(b[2], pz, b[5]));
}

static inline double min3(double a, double b, double c) { return dmin(dmin(a, b), c); }
static inline double max3(double a, double b, double c) { return dmax(dmax(a, b), c); }

static inline double tri_box_d2(double px, double py, double pz, const double *t)
{
    return sq(gap(min3(t[0], t[3], t[6]), px, max3(t[0], t[3], t[6])))
         + sq(gap(min3(t[1], t[4], t[7]), py, max3(t[1], t[4], t[7])))
         + sq(gap(min3(t[2], t[5], t[8]), pz, max3(t[2], t[5], t[8])));
}

/* index of the triangle nearest to p among those closer than sqrt(best) (else best_t) */
static int64_t nearest_triangle(double px, double py, double pz, const mesh_index_t *m,
                                double best, int64_t best_t)
{
    int64_t stack[STACK];
    double stack_d[STACK];
    stack[0] = 0;
    stack_d[0] = box_d2(px, py, pz, m->box);
    int sp = 1;
    while (sp > 0) {
        sp--;
        if (stack_d[sp] >= best)
            continue;
        int64_t node = stack[sp];
        int64_t first = m->link[2 * node], n_tri = m->link[2 * node + 1];
        if (n_tri > 0) {
            for (int64_t t = first; t < first + n_tri; t++) {
                const double *tri = m->tri + 9 * t;
                if (tri_box_d2(px, py, pz, tri) >= best)
                    continue; /* cheaper than the exact test, and rejects most of a leaf */
                double d2 = closest_point(px, py, pz, tri).d2;
                if (d2 < best)
                    best = d2, best_t = t;
            }
            continue;
        }
        int64_t near = first, far = first + 1;
        double d_near = box_d2(px, py, pz, m->box + 6 * near);
        double d_far = box_d2(px, py, pz, m->box + 6 * far);
        if (d_near > d_far) { /* push the farther child first: the nearer one is searched next */
            int64_t s = near;
            near = far, far = s;
            double d = d_near;
            d_near = d_far, d_far = d;
        }
        if (d_far < best)
            stack[sp] = far, stack_d[sp] = d_far, sp++;
        if (d_near < best)
            stack[sp] = near, stack_d[sp] = d_near, sp++;
    }
    return best_t;
}

static double signed_distance(double px, double py, double pz, int64_t t, const mesh_index_t *m)
{
    const double *tri = m->tri + 9 * t;
    const double *nf = m->normals_face;
    closest_t c = closest_point(px, py, pz, tri);
    if (c.feature == FACE) /* exact form in the face's Voronoi region: along the unit normal */
        return (px - tri[0]) * nf[3 * t] + (py - tri[1]) * nf[3 * t + 1]
             + (pz - tri[2]) * nf[3 * t + 2];
    double nx, ny, nz;
    if (c.feature >= VERT0) {
        int64_t v = m->corner_vertex[3 * t + c.feature - VERT0];
        nx = m->normals_vert[3 * v], ny = m->normals_vert[3 * v + 1];
        nz = m->normals_vert[3 * v + 2];
    } else {
        int64_t g = m->neighbours[3 * t + c.feature - EDGE0];
        nx = nf[3 * t], ny = nf[3 * t + 1], nz = nf[3 * t + 2];
        if (g >= 0) {
            nx += nf[3 * g], ny += nf[3 * g + 1], nz += nf[3 * g + 2];
        } else if (g <= -2) {
            const double *s = m->crowded + 3 * (-2 - g);
            nx = s[0], ny = s[1], nz = s[2];
        }
    }
    double d = sqrt(c.d2);
    double s = (px - c.q[0]) * nx + (py - c.q[1]) * ny + (pz - c.q[2]) * nz;
    return s < 0.0 ? -d : d;
}

typedef struct {
    const double *points, *origin;
    const int64_t *order;
    const mesh_index_t *mesh;
    double limit_d2;
    int64_t n;
    double *dist;
    int64_t *nearest;
} query_ctx;

static void query_blocks(void *arg, int64_t b0, int64_t b1)
{
    query_ctx *c = arg;
    const mesh_index_t *m = c->mesh;
    for (int64_t b = b0; b < b1; b++) {
        int64_t warm = -1;
        int64_t end = (b + 1) * BLOCK < c->n ? (b + 1) * BLOCK : c->n;
        for (int64_t k = b * BLOCK; k < end; k++) {
            int64_t i = c->order[k];
            if (k + PREFETCH < end) { /* the cloud is read and written in Morton order */
                int64_t ahead = c->order[k + PREFETCH];
                __builtin_prefetch(c->points + 3 * ahead);
                __builtin_prefetch(c->dist + ahead, 1);
            }
            const double *p = c->points + 3 * i;
            double px = p[0] - c->origin[0], py = p[1] - c->origin[1], pz = p[2] - c->origin[2];
            double best = c->limit_d2;
            int64_t start = -1;
            if (warm >= 0) { /* the previous point's triangle bounds this one's distance */
                double d2 = closest_point(px, py, pz, m->tri + 9 * warm).d2;
                if (d2 < best)
                    best = d2, start = warm;
            }
            int64_t t = nearest_triangle(px, py, pz, m, nextafter(best, INFINITY), start);
            if (c->nearest != NULL)
                c->nearest[i] = t;
            if (t < 0) {
                c->dist[i] = NAN;
                continue;
            }
            warm = t;
            c->dist[i] = signed_distance(px, py, pz, t, m);
        }
    }
}

typedef struct {
    const double *points, *origin, *lo, *scale;
    uint64_t *codes;
} point_codes_ctx;

static void point_codes_range(void *arg, int64_t b, int64_t e)
{
    point_codes_ctx *c = arg;
    for (int64_t i = b; i < e; i++) {
        const double *p = c->points + 3 * i;
        double local[3] = {p[0] - c->origin[0], p[1] - c->origin[1], p[2] - c->origin[2]};
        /* a coarse order (about 10 bits per axis) is all the warm start needs */
        c->codes[i] = morton_of(local, c->lo, c->scale) >> 31;
    }
}

int query(const double *points_world, int64_t n, const double origin[3], const double lo[3],
          const double scale[3], const mesh_index_t *mesh, double limit_d2, double *dist,
          int64_t *nearest, int n_threads)
{
    /* Spatially sorted points share most of their search path and warm-start each
     * other with the previous point's triangle. */
    uint64_t *codes = malloc(sizeof(uint64_t) * (n > 0 ? n : 1));
    int64_t *order = malloc(sizeof(int64_t) * (n > 0 ? n : 1));
    int status = -1;
    if (codes == NULL || order == NULL)
        goto done;
    point_codes_ctx pc = {points_world, origin, lo, scale, codes};
    parallel_for(n, 1 << 14, n_threads, point_codes_range, &pc);
    if (radix_argsort(codes, n, order) != 0)
        goto done;
    free(codes);
    codes = NULL;
    query_ctx c = {points_world, origin, order, mesh, limit_d2, n, dist, nearest};
    parallel_for((n + BLOCK - 1) / BLOCK, 1, n_threads, query_blocks, &c);
    status = 0;
done:
    free(codes);
    free(order);
    return status;
}
