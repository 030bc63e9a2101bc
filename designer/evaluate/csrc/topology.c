/* Mesh topology for the sign: welding, face geometry and pseudo-normals.
 *
 * The sign of a distance comes from the pseudo-normal of the nearest feature (Baerentzen
 * & Aanaes 2005): the face normal; for an edge, the sum of the normals of the faces
 * sharing it (one face on a boundary); for a vertex, the angle-weighted sum of its
 * faces' normals. Edges are found by a counting sort of their smaller vertex id, so no
 * hashing of every edge is needed; only vertices on open edges are hashed, to weld
 * corners that were split with bit-identical coordinates. */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "kernels.h"
#include "parallel.h"

/* splitmix64's finaliser: every input bit reaches the low bits the table index uses
 * (coordinates on a grid have mantissas ending in many zero bits) */
static inline uint64_t mix(uint64_t h)
{
    h ^= h >> 30;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 27;
    h *= 0x94D049BB133111EBull;
    h ^= h >> 31;
    return h;
}

void weld_vertices(const double *vertices, int64_t n, const int64_t *candidates, int64_t m,
                   int64_t *out)
{
    /* canonical index of each vertex: among candidates, the first with bit-identical
     * x, y, z; every other vertex maps to itself */
    const uint64_t *bits = (const uint64_t *)vertices;
    for (int64_t i = 0; i < n; i++)
        out[i] = i;
    int64_t size = 1;
    while (size < 2 * m)
        size <<= 1;
    int64_t *table = malloc(sizeof(int64_t) * size);
    if (table == NULL)
        return; /* nothing welded: the signs of open seams stay as they are */
    memset(table, 0xff, sizeof(int64_t) * size);  /* -1 */
    uint64_t mask = (uint64_t)(size - 1);
    for (int64_t c = 0; c < m; c++) {
        int64_t i = candidates[c];
        const uint64_t *p = bits + 3 * i;
        uint64_t slot = mix(mix(mix(p[0]) ^ p[1]) ^ p[2]) & mask;
        for (;;) {
            int64_t j = table[slot];
            if (j < 0) {
                table[slot] = i;
                break;
            }
            const uint64_t *q = bits + 3 * j;
            if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) {
                out[i] = j;
                break;
            }
            slot = (slot + 1) & mask;
        }
    }
    free(table);
}

typedef struct {
    const double *local;
    const int64_t *faces;
    double *tri, *normal, *angle;
} geometry_ctx;

static void geometry_range(void *arg, int64_t b, int64_t e)
{
    geometry_ctx *g = arg;
    for (int64_t f = b; f < e; f++) {
        double *t = g->tri + 9 * f;
        for (int c = 0; c < 3; c++)
            for (int a = 0; a < 3; a++)
                t[3 * c + a] = g->local[3 * g->faces[3 * f + c] + a];
        double e1x = t[3] - t[0], e1y = t[4] - t[1], e1z = t[5] - t[2];
        double e2x = t[6] - t[0], e2y = t[7] - t[1], e2z = t[8] - t[2];
        double nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
        double length = sqrt(nx * nx + ny * ny + nz * nz);
        double *n = g->normal + 3 * f;
        if (length > 0.0)
            n[0] = nx / length, n[1] = ny / length, n[2] = nz / length;
        else
            n[0] = n[1] = n[2] = 0.0;
        for (int c = 0; c < 3; c++) {
            int i = 3 * c, j = 3 * ((c + 1) % 3), k = 3 * ((c + 2) % 3);
            double ux = t[j] - t[i], uy = t[j + 1] - t[i + 1], uz = t[j + 2] - t[i + 2];
            double vx = t[k] - t[i], vy = t[k + 1] - t[i + 1], vz = t[k + 2] - t[i + 2];
            double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
            g->angle[3 * f + c] = atan2(sqrt(cx * cx + cy * cy + cz * cz),
                                        ux * vx + uy * vy + uz * vz);
        }
    }
}

void face_geometry(const double *local, const int64_t *faces, int64_t m, double *tri,
                   double *normal, double *angle, int n_threads)
{
    geometry_ctx g = {local, faces, tri, normal, angle};
    parallel_for(m, 1 << 13, n_threads, geometry_range, &g);
}

void vertex_normals(const int64_t *faces, int64_t m, const double *normal, const double *angle,
                    double *vert)
{
    /* vert (V, 3), zeroed by the caller: angle-weighted sum of each vertex's face normals */
    for (int64_t f = 0; f < m; f++)
        for (int c = 0; c < 3; c++) {
            double *v = vert + 3 * faces[3 * f + c];
            double w = angle[3 * f + c];
            for (int a = 0; a < 3; a++)
                v[a] += w * normal[3 * f + a];
        }
}

#define CROWDED INT64_MIN  /* an edge of three or more faces, not numbered yet */

typedef struct {
    const int64_t *faces, *first, *edges;
    int64_t *neighbour;
    _Atomic int64_t crowded;
} bucket_ctx;

static inline int64_t other_end(const int64_t *faces, int64_t e)
{
    /* the larger vertex of edge e = 3 face + k (corners k, k + 1) */
    int64_t a = faces[e], b = faces[e - e % 3 + (e % 3 + 1) % 3];
    return a > b ? a : b;
}

#define SMALL_BUCKET 64

static void match_buckets(void *arg, int64_t v0, int64_t v1)
{
    /* edges sharing their smaller vertex v are matched by their larger one: two faces
     * on an edge are each other's neighbour, one face has none, three or more are
     * "crowded" (marked CROWDED here, numbered afterwards) */
    bucket_ctx *c = arg;
    int64_t crowded = 0, others[SMALL_BUCKET];
    for (int64_t v = v0; v < v1; v++) {
        int64_t lo = c->first[v], n = c->first[v + 1] - lo;
        const int64_t *edges = c->edges + lo;
        if (n <= SMALL_BUCKET)
            for (int64_t j = 0; j < n; j++)
                others[j] = other_end(c->faces, edges[j]);
        for (int64_t i = 0; i < n; i++) {
            int64_t b = n <= SMALL_BUCKET ? others[i] : other_end(c->faces, edges[i]);
            int64_t same = 0, mate = -1;
            for (int64_t j = 0; j < n; j++) {
                int64_t o = n <= SMALL_BUCKET ? others[j] : other_end(c->faces, edges[j]);
                if (j != i && o == b)
                    same++, mate = edges[j];
            }
            c->neighbour[edges[i]] = same == 0 ? -1 : (same == 1 ? mate / 3 : CROWDED);
            crowded += same >= 2;
        }
    }
    atomic_fetch_add(&c->crowded, crowded);
}

int edge_neighbours(const int64_t *faces, int64_t m, int64_t n_vertices, const double *normal,
                    int64_t *neighbour, double **sums_out, int64_t *n_crowded, int n_threads)
{
    /* the face across edge k (corners k, k + 1) of each face: -1 on a boundary edge;
     * -2 - e where three or more faces share the edge, e indexing the sums of their
     * normals (the pseudo-normal of such an edge). Edges are grouped by their smaller
     * vertex (a counting sort), then matched within each group. */
    int64_t *first = calloc(n_vertices + 1, sizeof(int64_t));
    int64_t *fill = malloc(sizeof(int64_t) * (n_vertices > 0 ? n_vertices : 1));
    int64_t *edges = malloc(sizeof(int64_t) * (m > 0 ? 3 * m : 1));
    double *sums = NULL;
    int status = -1;
    if (!first || !fill || !edges)
        goto done;
    for (int64_t f = 0; f < m; f++)
        for (int k = 0; k < 3; k++) {
            int64_t a = faces[3 * f + k], b = faces[3 * f + (k + 1) % 3];
            first[(a < b ? a : b) + 1]++;
        }
    for (int64_t v = 0; v < n_vertices; v++)
        first[v + 1] += first[v];
    memcpy(fill, first, sizeof(int64_t) * n_vertices);
    for (int64_t f = 0; f < m; f++)
        for (int k = 0; k < 3; k++) {
            int64_t a = faces[3 * f + k], b = faces[3 * f + (k + 1) % 3];
            edges[fill[a < b ? a : b]++] = 3 * f + k;
        }
    bucket_ctx c = {faces, first, edges, neighbour};
    atomic_init(&c.crowded, 0);
    parallel_for(n_vertices, 1 << 14, n_threads, match_buckets, &c);
    int64_t crowded_edges = 0;
    if (atomic_load(&c.crowded) > 0) {
        /* number each crowded edge (in vertex order) and sum its faces' normals */
        sums = calloc(atomic_load(&c.crowded) * 3, sizeof(double));  /* >= edges * 3 */
        if (sums == NULL)
            goto done;
        for (int64_t v = 0; v < n_vertices; v++)
            for (int64_t i = first[v]; i < first[v + 1]; i++) {
                int64_t e = edges[i];
                if (neighbour[e] != CROWDED)
                    continue;  /* not crowded, or already numbered with its group */
                int64_t b = other_end(faces, e), id = crowded_edges++;
                for (int64_t j = i; j < first[v + 1]; j++) {
                    int64_t g = edges[j];
                    if (neighbour[g] == CROWDED && other_end(faces, g) == b) {
                        for (int a = 0; a < 3; a++)
                            sums[3 * id + a] += normal[3 * (g / 3) + a];
                        neighbour[g] = -2 - id;
                    }
                }
            }
    } else {
        sums = calloc(1, sizeof(double));
        if (sums == NULL)
            goto done;
    }
    *sums_out = sums;
    *n_crowded = crowded_edges;
    sums = NULL;
    status = 0;
done:
    free(first);
    free(fill);
    free(edges);
    free(sums);
    return status;
}
